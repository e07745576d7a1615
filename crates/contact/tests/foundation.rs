//! The elastic-foundation contact on round surfaces against laws that can fail: the paper's
//! Hertz force (closed form and an independent quadrature of the exact overlap), the matched
//! layer, Lankarani–Nikravesh damping, balance of forces and moments, and dissipation.

mod common;

use common::foundation::*;
use common::{BEARING_RADIUS, CLEARANCE, round_joint, steel};
use contact::{
    BodyState, ContactModelKind, Foundation, Frictionless, LankaraniNikravesh, RadiusSample,
    SurfaceProfile,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[test]
fn round_surfaces_reproduce_the_papers_hertz_force() {
    let joint = foundation(round_joint([0.0, 0.0], [0.0, 0.0], hertz(), Frictionless));
    let line_modulus = Foundation::calibrated(&steel(), &steel()).line_modulus();
    let (ri, rj) = (BEARING_RADIUS, BEARING_RADIUS - CLEARANCE);
    let stiffness = joint.stiffness(ri, rj);
    let bearing = BodyState::at_rest(0.0, 0.0, 0.0);
    // (δ, expected F/(K δ^1.5) from the leading-order √(c/(c + δ)) and its next terms).
    for (delta, low, high) in [
        (1e-6, 0.995, 1.0),
        (10e-6, 0.982, 0.992),
        (30e-6, 0.955, 0.970),
    ] {
        let e = CLEARANCE + delta;
        for phi in [0.3, 2.0, -2.5] {
            let pin = BodyState::at_rest(e * f64::cos(phi), e * f64::sin(phi), 0.7);
            let f = joint.forces(&bearing, &pin, None);
            let magnitude = f.pin.x.hypot(f.pin.y);
            let ratio = magnitude / (stiffness * delta.powf(1.5));
            let leading = (4.0 * std::f64::consts::SQRT_2 / 3.0)
                * line_modulus
                * (ri * rj).sqrt()
                * delta.powf(1.5)
                / (CLEARANCE + delta).sqrt();
            let quadrature = quadrature_force(line_modulus, e, ri, rj);
            eprintln!(
                "δ = {:4.0} µm φ = {phi:+.1}: F = {magnitude:.1} N, F/(K δ^1.5) = {ratio:.4}, \
                 against the quadrature {:+.2e}, against the leading order {:+.2e}; {} nodes",
                delta * 1e6,
                magnitude / quadrature - 1.0,
                magnitude / leading - 1.0,
                f.diagnostics.contact_cells
            );
            assert!(
                low <= ratio && ratio <= high,
                "δ = {delta:e}: ratio {ratio}"
            );
            // 1000 nodes against a converged integral of the exact overlap: the linear
            // interpolation between nodes costs 0.25 % when only 20 nodes touch (δ = 1 µm).
            assert!(
                (magnitude / quadrature - 1.0).abs() < 3e-3,
                "{magnitude} vs {quadrature}"
            );
            // The force points back along −e.
            let along = -(f.pin.x * phi.cos() + f.pin.y * phi.sin()) / magnitude;
            assert!(along > 1.0 - 1e-9, "{along}");
        }
    }
}

/// A groove the pin fits exactly: the pin's circle (radius `r`) centred `offset` from the bearing
/// centre along x, `o cos ψ + √(r² − o² sin² ψ)`, worn into a bore `bore` (> r) that it leaves
/// as it was behind: with `bore − r` tiny the groove spans the whole facing half.
#[derive(Clone, Copy, Debug)]
struct FittedGroove {
    pin_radius: f64,
    offset: f64,
    bore: f64,
}

impl SurfaceProfile for FittedGroove {
    fn sample(&self, angle: f64) -> RadiusSample {
        let (o, r) = (self.offset, self.pin_radius);
        let (s, c) = angle.sin_cos();
        let root = (r * r - o * o * s * s).sqrt();
        let groove = o * c + root;
        if groove <= self.bore {
            return RadiusSample {
                radius: self.bore,
                slope: 0.0,
                curvature: 0.0,
            };
        }
        RadiusSample {
            radius: groove,
            slope: -o * s - o * o * s * c / root,
            curvature: -o * c
                - o * o * (c * c - s * s) / root
                - o.powi(4) * s * s * c * c / root.powi(3),
        }
    }
}

/// The conformal limit of the layer: a pin pressed `δ` further into a groove it fits overlaps by
/// `δ cos α` over the half outline facing the push (Persson's and Ciavarella & Decuzzi's
/// `cos θ` pressure of the zero-clearance limit), so the layer carries
/// `F = k w R ∫ cos² α dα = (π/2) k w R δ`, linear in `δ` (Hertz's `δ^{3/2}` needs a clearance).
/// With the calibrated `k w = E*/√2` that is `(π/(2√2)) E* R δ`: Liu, Zhang & Yang's conformal
/// limit `(π/(2√2)) E* L δ` with the radius in place of the hinge width `L`; the pin-in-hole
/// layer is Liu's own (docs/model.md §10.7).
#[test]
fn a_pin_in_a_groove_it_fits_carries_the_conformal_closed_form() {
    let rj = BEARING_RADIUS - CLEARANCE;
    let width = 0.1;
    let groove = FittedGroove {
        pin_radius: rj,
        offset: CLEARANCE,
        bore: rj + 1e-8,
    };
    let effective_modulus = 1.0 / (2.0 * steel().compliance());
    let conformal = std::f64::consts::PI / (2.0 * std::f64::consts::SQRT_2) * effective_modulus;
    for (name, layer, length) in [
        ("calibrated", Foundation::calibrated(&steel(), &steel()), rj),
        (
            "pin-in-hole",
            Foundation::pin_in_hole(&steel(), &steel(), rj, width).expect("valid"),
            width,
        ),
    ] {
        let joint = common::off_centre_joint(
            groove,
            contact::CircularProfile::new(rj),
            hertz(),
            Frictionless,
        )
        .with_model(ContactModelKind::Foundation(layer));
        // The off-centre joint's bearing and pin centres (as in `place`): the pin's centre goes
        // `offset + δ` from the bearing's along x.
        let bearing = BodyState::at_rest(0.0, 0.0, 0.0);
        let (bc, pc) = ([0.04, -0.02], [-0.03, 0.025]);
        for delta in [0.2e-6, 1e-6, 5e-6] {
            let e = CLEARANCE + delta;
            let pin = BodyState::at_rest(bc[0] + e - pc[0], bc[1] - pc[1], 0.0);
            let f = joint.forces(&bearing, &pin, None);
            let closed = 0.5 * std::f64::consts::PI * layer.line_modulus() * rj * delta;
            let error = -f.pin.x / closed - 1.0;
            // The same closed form in material terms: (π/(2√2)) E* × length × δ.
            let material = conformal * length * delta;
            eprintln!(
                "{name}: δ = {:.1} µm: F = {:.2} kN, closed form {:.2} kN ({error:+.2e}), \
                 (π/(2√2)) E* {} δ = {:.2} kN, transverse {:.1e} N, {} nodes",
                delta * 1e6,
                -f.pin.x * 1e-3,
                closed * 1e-3,
                if length == width { "L" } else { "R_j" },
                material * 1e-3,
                f.pin.y,
                f.diagnostics.contact_cells
            );
            // What separates the layer from the closed form: the overlap is radial from the
            // bearing centre, not along the groove's normal (angles ~ c/R), and the outline is
            // linear between 1000 nodes, 500 of them loaded; measured 2e-5 to 8e-5, required
            // < 5e-4.
            assert!(error.abs() < 5e-4, "{name}, δ = {delta:e}: {error:e}");
            assert!(
                (closed / material - 1.0).abs() < 1e-12,
                "{closed} vs {material}"
            );
            assert!(f.pin.y.abs() < 1e-3 * closed, "{}", f.pin.y);
            assert!(
                f.diagnostics.contact_cells > 450,
                "{}",
                f.diagnostics.contact_cells
            );
        }
    }
}

/// At its reference overlap (4 % of the clearance, 20 µm) the matched layer gives the Hertz
/// force, up to the 1000-node discretisation (< 0.1 % there).
#[test]
fn the_matched_layer_gives_the_hertz_force_at_its_reference_overlap() {
    let joint = round_joint([0.0, 0.0], [0.0, 0.0], hertz(), Frictionless).with_model(
        ContactModelKind::Foundation(
            Foundation::hertz_matched(
                &steel(),
                &steel(),
                BEARING_RADIUS,
                BEARING_RADIUS - CLEARANCE,
                0.04,
            )
            .expect("valid"),
        ),
    );
    let stiffness = joint.stiffness(BEARING_RADIUS, BEARING_RADIUS - CLEARANCE);
    let bearing = BodyState::at_rest(0.0, 0.0, 0.0);
    for (delta, low, high) in [
        (1e-6, 1.015, 1.03),
        (20e-6, 0.999, 1.001),
        (30e-6, 0.985, 1.0),
    ] {
        let pin = BodyState::at_rest(CLEARANCE + delta, 0.0, 0.0);
        let f = joint.forces(&bearing, &pin, None);
        let ratio = f.pin.x.abs() / (stiffness * f64::powf(delta, 1.5));
        eprintln!(
            "matched layer: δ = {:.0} µm, F/(K δ^1.5) = {ratio:.4}",
            delta * 1e6
        );
        assert!(low <= ratio && ratio <= high, "{delta}: {ratio}");
    }
}

/// Within one impact's range of rates (`|δ̇| ≤ δ̇⁻`) the layer's damping is Lankarani–Nikravesh
/// per node, so on round surfaces the total is the law's force; beyond it the rate is held at
/// `±δ̇⁻`, so a contact that began gently (δ̇⁻ at the law's 1e-4 m/s floor) and then moves at
/// 5 cm/s adds `χ` of the elastic force, as much as an impact's onset does, not the
/// `χ · 500` the unlimited law would (the persistent contact of a pin in its groove).
#[test]
fn damping_is_lankarani_nikravesh_within_an_impacts_rates_and_held_beyond() {
    let restitution = 0.9;
    let joint = foundation(round_joint(
        [0.0, 0.0],
        [0.0, 0.0],
        LankaraniNikravesh::new(restitution).expect("valid"),
        Frictionless,
    ));
    let chi = 0.75 * (1.0 - restitution * restitution);
    let bearing = BodyState::at_rest(0.0, 0.0, 0.0);
    let delta = 15e-6;
    let e = CLEARANCE + delta;
    let at_rest = joint.forces(&bearing, &BodyState::at_rest(e, 0.0, 0.0), Some(0.4));
    for (onset, rate) in [
        (0.4, -0.5),
        (0.4, -0.1),
        (0.4, 0.05),
        (0.4, 0.3),
        (0.4, 0.6),
        (1e-6, 0.05),
        (1e-6, -0.05),
    ] {
        let pin = BodyState::new([e, 0.0, 0.0], [rate, 0.2, 1.5]);
        let f = joint.forces(&bearing, &pin, Some(onset));
        let ratio = f.pin.x / at_rest.pin.x;
        // The law floors the onset at 1e-4 m/s; the rate counts within ± the floored onset.
        let held = onset.max(1e-4);
        let expected = 1.0 + chi * (rate / held).clamp(-1.0, 1.0);
        eprintln!(
            "δ̇⁻ = {onset:e}, δ̇ = {rate:+}: F/F_e = {ratio:.5}, expected {expected:.5}, elastic \
             share {:.4}",
            f.diagnostics.elastic_force / f.diagnostics.normal_force
        );
        assert!(
            (ratio - expected).abs() < 2e-3 * expected,
            "{ratio} vs {expected}"
        );
        assert!(
            (f.diagnostics.elastic_force / f.diagnostics.normal_force * expected - 1.0).abs()
                < 2e-3,
            "elastic share"
        );
        assert!(f.diagnostics.damping_power > 0.0);
    }
}

#[test]
fn forces_and_moments_balance_and_never_generate_energy() {
    let (normal, friction) = common::lgres_laws(0.9);
    let joint = worn(normal, friction);
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    for _ in 0..200 {
        let (bearing, pin) =
            random_contact(&joint, &mut rng, 0.5, 250f64.to_radians(), 1.5, 1e-7..4e-5);
        let f = joint.forces(&bearing, &pin, Some(rng.random_range(1e-4..0.5)));
        let scale = f.pin.x.hypot(f.pin.y).max(1e-9);
        assert!((f.pin.x + f.bearing.x).abs() < 1e-12 * scale);
        assert!((f.pin.y + f.bearing.y).abs() < 1e-12 * scale);
        // Total moment about the origin.
        let moment = f.bearing.z + bearing.x * f.bearing.y - bearing.y * f.bearing.x
            + f.pin.z
            + pin.x * f.pin.y
            - pin.y * f.pin.x;
        assert!(
            moment.abs() < 1e-9 * scale,
            "moment {moment} for force {scale}"
        );
        assert!(
            f.diagnostics.damping_power >= -1e-12 * scale,
            "{}",
            f.diagnostics.damping_power
        );
        assert!(
            f.diagnostics.friction_power >= -1e-12 * scale,
            "{}",
            f.diagnostics.friction_power
        );
    }
}
