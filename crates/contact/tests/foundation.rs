//! The elastic-foundation contact against laws that can fail: the paper's Hertz force on round
//! surfaces (closed form and an independent quadrature of the exact overlap), the force as the
//! exact gradient of the stored energy on deeply worn outlines, the exact Jacobian against
//! finite differences, Lankarani–Nikravesh damping on round surfaces, balance of forces and
//! moments, dissipation, and smoothness as a contact zone's edge crosses a node.

mod common;

use common::{BEARING_RADIUS, CLEARANCE, off_centre_joint, round_joint, steel};
use contact::{
    Ambrosio, BodyState, ClearanceJoint, ContactModel, Foundation, FrictionLaw, Frictionless,
    Hertz, LankaraniNikravesh, NodeLoad, NormalLaw, Quadrature, RadiusSample, SlidingVelocity,
    SurfaceProfile,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A surface with a smooth Gaussian groove (bearing, `sign = +1`) or flat (pin, `sign = −1`):
/// `R(α) = R₀ + sign · h · exp(−(α − α₀)²/(2σ²))` (α wrapped to the nearest copy of α₀).
#[derive(Clone, Copy, Debug)]
struct Groove {
    base: f64,
    sign: f64,
    depth: f64,
    centre: f64,
    sigma: f64,
}

impl SurfaceProfile for Groove {
    fn sample(&self, angle: f64) -> RadiusSample {
        let tau = std::f64::consts::TAU;
        let x = (angle - self.centre + std::f64::consts::PI).rem_euclid(tau) - std::f64::consts::PI;
        let s2 = self.sigma * self.sigma;
        let bump = self.sign * self.depth * (-x * x / (2.0 * s2)).exp();
        RadiusSample {
            radius: self.base + bump,
            slope: -bump * x / s2,
            curvature: bump * (x * x / s2 - 1.0) / s2,
        }
    }

    fn radius_bounds(&self) -> Option<(f64, f64)> {
        let moved = self.base + self.sign * self.depth;
        Some((self.base.min(moved), self.base.max(moved)))
    }

    /// The Gaussian's steepest slope, `h e^{-1/2}/σ` (its step at ±π, below 1e-20 m for these
    /// grooves, is within the memory's rounding allowance).
    fn slope_bound(&self) -> Option<f64> {
        Some(self.depth / self.sigma * (-0.5f64).exp())
    }
}

/// A profile that counts its samples (the costly part of a node), to see nodes skipped.
#[derive(Clone, Debug)]
struct Counted<S> {
    inner: S,
    samples: std::rc::Rc<std::cell::Cell<usize>>,
}

impl<S: SurfaceProfile> SurfaceProfile for Counted<S> {
    fn sample(&self, angle: f64) -> RadiusSample {
        self.samples.set(self.samples.get() + 1);
        self.inner.sample(angle)
    }
    fn radius_bounds(&self) -> Option<(f64, f64)> {
        self.inner.radius_bounds()
    }
    fn slope_bound(&self) -> Option<f64> {
        self.inner.slope_bound()
    }
}

fn hertz() -> Hertz {
    Hertz::new(1.5).expect("valid exponent")
}

fn foundation<B: SurfaceProfile, P: SurfaceProfile, N: NormalLaw, F: FrictionLaw>(
    joint: ClearanceJoint<B, P, N, F>,
) -> ClearanceJoint<B, P, N, F> {
    joint.with_model(ContactModel::Foundation(Foundation::calibrated(
        &steel(),
        &steel(),
    )))
}

/// A worn joint A: a 1.2 mm groove in the bearing at 250° and a 0.8 mm flat on the pin at 70°,
/// off-centroid centres.
fn worn<N: NormalLaw, F: FrictionLaw>(
    normal: N,
    friction: F,
) -> ClearanceJoint<Groove, Groove, N, F> {
    let bearing = Groove {
        base: BEARING_RADIUS,
        sign: 1.0,
        depth: 1.2e-3,
        centre: 250f64.to_radians(),
        sigma: 0.35,
    };
    let pin = Groove {
        base: BEARING_RADIUS - CLEARANCE,
        sign: -1.0,
        depth: 0.8e-3,
        centre: 70f64.to_radians(),
        sigma: 0.25,
    };
    foundation(off_centre_joint(bearing, pin, normal, friction))
}

/// Pin placed so that its centre is `|e|` from the bearing centre along global angle `phi`,
/// with `|e|` found by bisection so that the deepest overlap is `target` (m).
fn place<B, P, N, F>(
    joint: &ClearanceJoint<B, P, N, F>,
    bearing: BodyState,
    pin_theta: f64,
    phi: f64,
    target: f64,
) -> BodyState
where
    B: SurfaceProfile,
    P: SurfaceProfile,
    N: NormalLaw,
    F: FrictionLaw,
{
    let joint_centres = |e: f64| {
        // Bearing centre in the global frame, then the pin body's centroid from its centre.
        let (s, c) = bearing.theta.sin_cos();
        let bc = [0.04, -0.02];
        let centre = [
            bearing.x + c * bc[0] - s * bc[1],
            bearing.y + s * bc[0] + c * bc[1],
        ];
        let (s, c) = pin_theta.sin_cos();
        let pc = [-0.03, 0.025];
        let arm = [c * pc[0] - s * pc[1], s * pc[0] + c * pc[1]];
        BodyState::at_rest(
            centre[0] + e * phi.cos() - arm[0],
            centre[1] + e * phi.sin() - arm[1],
            pin_theta,
        )
    };
    let (mut lo, mut hi) = (0.0, 5e-3);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if joint.penetration(&bearing, &joint_centres(mid)) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    joint_centres(0.5 * (lo + hi))
}

/// `state` moving like `moving` (its position kept).
fn with_velocity(state: BodyState, moving: BodyState) -> BodyState {
    BodyState::new(
        [state.x, state.y, state.theta],
        [moving.vx, moving.vy, moving.omega],
    )
}

/// A bearing anywhere (moving at up to `speed`, see [`random_body`]) and a pin overlapping it by
/// a depth drawn from `overlap` (m), in a direction within ±`spread` rad of `offset` from the
/// bearing's frame, turned anyhow, and moving at up to `speed` too (at rest for `speed = 0`).
fn random_contact<B, P, N, F>(
    joint: &ClearanceJoint<B, P, N, F>,
    rng: &mut ChaCha8Rng,
    speed: f64,
    offset: f64,
    spread: f64,
    overlap: std::ops::Range<f64>,
) -> (BodyState, BodyState)
where
    B: SurfaceProfile,
    P: SurfaceProfile,
    N: NormalLaw,
    F: FrictionLaw,
{
    let bearing = random_body(rng, speed);
    let phi = bearing.theta + offset + rng.random_range(-spread..spread);
    let pin = place(
        joint,
        bearing,
        rng.random_range(-3.0..3.0),
        phi,
        rng.random_range(overlap),
    );
    if speed > 0.0 {
        (bearing, with_velocity(pin, random_body(rng, speed)))
    } else {
        (bearing, pin)
    }
}

/// A body anywhere within 0.1 m and ±3 rad, moving at up to `speed` m/s and `10 speed` rad/s
/// (at rest for `speed = 0`).
fn random_body(rng: &mut ChaCha8Rng, speed: f64) -> BodyState {
    let spin = 10.0 * speed;
    let mut rate = |limit: f64| {
        if limit > 0.0 {
            rng.random_range(-limit..limit)
        } else {
            0.0
        }
    };
    let velocity = [rate(speed), rate(speed), rate(spin)];
    BodyState::new(
        [
            rng.random_range(-0.1..0.1),
            rng.random_range(-0.1..0.1),
            rng.random_range(-3.0..3.0),
        ],
        velocity,
    )
}

/// The force on the pin of a linear layer over a round pin offset by `e` in a round bearing, by
/// an independent quadrature: the exact overlap along rays from the bearing centre,
/// `d(θ) = e cos θ + √(R_j² − e² sin² θ) − R`, integrated with the measure `R_j dα` of the pin's
/// own outline (α the pin point's polar angle, `dθ/dα` from the same closed form).
fn quadrature_force(line_modulus: f64, e: f64, bearing_radius: f64, pin_radius: f64) -> f64 {
    let n = 400_000;
    let mut force = 0.0;
    for k in 0..n {
        let alpha = -std::f64::consts::PI + (k as f64 + 0.5) * std::f64::consts::TAU / n as f64;
        let p = [e + pin_radius * alpha.cos(), pin_radius * alpha.sin()];
        let rho = p[0].hypot(p[1]);
        let d = rho - bearing_radius;
        if d > 0.0 {
            // Radial direction's x component (the resultant is along x by symmetry).
            force +=
                line_modulus * d * (p[0] / rho) * pin_radius * std::f64::consts::TAU / n as f64;
        }
    }
    force
}

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
        .with_model(ContactModel::Foundation(layer));
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
        ContactModel::Foundation(
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

#[test]
fn elastic_force_is_the_gradient_of_the_stored_energy_on_worn_outlines() {
    let joint = worn(hertz(), Frictionless);
    let mut rng = ChaCha8Rng::seed_from_u64(20);
    let mut worst: f64 = 0.0;
    for sample in 0..40 {
        let (bearing, pin) =
            random_contact(&joint, &mut rng, 0.0, 250f64.to_radians(), 0.8, 2e-6..4e-5);
        let z = common::state_vector(&bearing, &pin);
        let forces = joint.forces(&bearing, &pin, None);
        let energy = |z: &[f64; 12]| {
            let (b, p) = common::states_from(z);
            joint.forces(&b, &p, None).diagnostics.elastic_energy
        };
        let q = [
            forces.bearing.x,
            forces.bearing.y,
            forces.bearing.z,
            forces.pin.x,
            forces.pin.y,
            forces.pin.z,
        ];
        let scale = q.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for col in 0..6 {
            let h = if col % 3 == 2 { 1e-9 } else { 1e-10 };
            let (mut up, mut down) = (z, z);
            up[col] += h;
            down[col] -= h;
            let gradient = (energy(&up) - energy(&down)) / (2.0 * h);
            let error = (q[col] + gradient).abs() / scale;
            worst = worst.max(error);
            assert!(
                error < 1e-5,
                "sample {sample} column {col}: Q {} vs −∂V {}",
                q[col],
                -gradient
            );
        }
    }
    eprintln!("worst |Q + ∇V| / max|Q| over 40 worn states: {worst:.2e}");
}

fn check_jacobian<B, P, N, F>(joint: &ClearanceJoint<B, P, N, F>, seed: u64, phi_offset: f64)
where
    B: SurfaceProfile,
    P: SurfaceProfile,
    N: NormalLaw,
    F: FrictionLaw,
{
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut worst: f64 = 0.0;
    for sample in 0..30 {
        let (bearing, pin) = random_contact(joint, &mut rng, 0.2, phi_offset, 0.8, 2e-6..3e-5);
        let onset = rng.random_range(0.05..0.5);
        let z = common::state_vector(&bearing, &pin);
        let (forces, analytic) = joint.forces_and_jacobian(&bearing, &pin, Some(onset));
        assert!(forces.diagnostics.in_contact);
        let plain = joint.forces(&bearing, &pin, Some(onset));
        assert_eq!(plain.pin, forces.pin, "the f64 and dual evaluations agree");
        let scale = [
            forces.bearing.x,
            forces.bearing.y,
            forces.bearing.z,
            forces.pin.x,
            forces.pin.y,
            forces.pin.z,
        ]
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()));
        for col in 0..12 {
            let h = match col {
                0 | 1 | 3 | 4 => 1e-11,
                2 | 5 => 1e-10,
                _ => 1e-8,
            };
            let (mut up, mut down) = (z, z);
            up[col] += h;
            down[col] -= h;
            let fp = common::generalized_forces(joint, &up, onset);
            let fm = common::generalized_forces(joint, &down, onset);
            for row in 0..6 {
                let numeric = (fp[row] - fm[row]) / (2.0 * h);
                // Scale: the force per unit change of the column's variable at a 1 m arm.
                let column_scale = if col < 6 { scale / 1e-5 } else { scale / 1.0 };
                let error = (analytic[(row, col)] - numeric).abs() / column_scale;
                worst = worst.max(error);
                assert!(
                    error < 2e-4,
                    "sample {sample} ({row}, {col}): analytic {:e} vs FD {numeric:e}",
                    analytic[(row, col)]
                );
            }
        }
    }
    eprintln!("worst Jacobian error (scaled) over 30 states: {worst:.2e}");
}

#[test]
fn jacobian_matches_finite_differences_on_worn_outlines() {
    let (normal, friction) = common::lgres_laws(0.9);
    check_jacobian(&worn(normal, friction), 7, 250f64.to_radians());
    let paper = worn(normal, friction).with_friction_sliding(SlidingVelocity::Paper);
    check_jacobian(&paper, 8, 250f64.to_radians());
    let round = foundation(common::worn_joint());
    check_jacobian(&round, 9, 0.0);
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

#[test]
fn force_is_smooth_as_a_zone_edge_crosses_a_node() {
    // Press the pin in from 5 to 6 µm: the contact arc grows and nodes enter it. The force is
    // C¹, so its stiffness ∂F/∂x_j (from the exact Jacobian) changes smoothly; a node entering
    // with the plain nodal sum would make it jump by the node's stiffness, about 2 % of it.
    let joint = foundation(round_joint([0.0, 0.0], [0.0, 0.0], hertz(), Frictionless));
    let bearing = BodyState::at_rest(0.0, 0.0, 0.0);
    let samples = 2000;
    let stiffness: Vec<f64> = (0..=samples)
        .map(|k| {
            let e = CLEARANCE + 5e-6 + 1e-6 * k as f64 / samples as f64;
            let pin = BodyState::at_rest(e, 0.0, 0.123);
            joint.forces_and_jacobian(&bearing, &pin, None).1[(3, 3)]
        })
        .collect();
    let mut jumps: Vec<f64> = stiffness.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    jumps.sort_by(f64::total_cmp);
    let (median, largest) = (jumps[jumps.len() / 2], jumps[jumps.len() - 1]);
    let node_stiffness = Foundation::calibrated(&steel(), &steel()).line_modulus()
        * (BEARING_RADIUS - CLEARANCE)
        * std::f64::consts::TAU
        / 1000.0;
    eprintln!(
        "∂F/∂x from {:.3e} to {:.3e} N/m over 1 µm: largest change between samples {largest:.3e},          median {median:.3e}; one node's stiffness {node_stiffness:.3e}",
        stiffness[0], stiffness[samples]
    );
    assert!(
        largest < 3.0 * median,
        "a jump: {largest} against a median {median}"
    );
    assert!(largest < 1e-2 * node_stiffness);
}

#[test]
fn a_dent_splits_the_contact_into_two_zones_and_nodes_carry_the_load() {
    // A bearing with a narrow dent where the pin presses: two zones either side of it.
    #[derive(Clone, Copy)]
    struct Ridge;
    impl SurfaceProfile for Ridge {
        fn sample(&self, angle: f64) -> RadiusSample {
            let x = (angle + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI;
            let s2: f64 = 0.02f64.powi(2);
            let bump = 25e-6 * (-x * x / (2.0 * s2)).exp();
            RadiusSample {
                radius: BEARING_RADIUS + 10e-6 + bump,
                slope: -bump * x / s2,
                curvature: bump * (x * x / s2 - 1.0) / s2,
            }
        }
        fn radius_bounds(&self) -> Option<(f64, f64)> {
            Some((BEARING_RADIUS + 10e-6, BEARING_RADIUS + 35e-6))
        }
    }
    let joint = foundation(
        ClearanceJoint::new(
            contact::JointSurface {
                centre: [0.0, 0.0],
                profile: Ridge,
                material: steel(),
            },
            contact::JointSurface {
                centre: [0.0, 0.0],
                profile: contact::CircularProfile::new(BEARING_RADIUS - CLEARANCE),
                material: steel(),
            },
            hertz(),
            Ambrosio::new(0.15, 1e-4, 1e-3).expect("valid"),
        )
        .expect("valid"),
    );
    let bearing = BodyState::at_rest(0.0, 0.0, 0.0);
    let pin = BodyState::new([CLEARANCE + 10e-6 + 12e-6, 0.0, 0.0], [0.0, 0.0, 4.0]);
    let mut loads: Vec<NodeLoad> = Vec::new();
    let f = joint.forces_visiting_nodes(&bearing, &pin, None, &mut |n| loads.push(*n));
    let d = f.diagnostics;
    eprintln!(
        "dent: {} zones, {} cells in contact, narrowest {} cells, F_n {:.1} N",
        d.contact_zones, d.contact_cells, d.narrowest_zone_cells, d.normal_force
    );
    assert_eq!(d.contact_zones, 2);
    assert!(d.narrowest_zone_cells >= 3);
    // Two symmetric zones of n nodes: Simpson's resolution estimate is 0.24/n².
    let n = f64::from(d.narrowest_zone_cells);
    assert!((d.resolution_error - 0.24 / (n * n)).abs() < 1e-3 * d.resolution_error);
    // The node loads add up to the resultant's magnitude along x (symmetric zones).
    let total: f64 = loads.iter().map(|n| n.normal_force).sum();
    assert!(
        (total / d.normal_force - 1.0).abs() < 0.05,
        "{total} vs {}",
        d.normal_force
    );
    // Spinning pin: every loaded node slides at about ω R_j.
    for n in &loads {
        assert!((n.material_sliding - 4.0 * (BEARING_RADIUS - CLEARANCE)).abs() < 0.01);
    }
    // Free flight: no node, no force.
    let free = joint.forces(&bearing, &BodyState::at_rest(1e-5, 0.0, 0.0), None);
    assert!(!free.diagnostics.in_contact && free.pin.norm() == 0.0);
    assert!(free.diagnostics.penetration < 0.0);
}

/// The validity measure `resolution_error` (0.96/n² per zone of `n` nodes, weighted by load)
/// against the error the nodes actually make, measured against the quadrature of the exact
/// overlap: a 1 µm overlap on 125–2000 nodes, so zones of 2.5 to 40 nodes, at 16 placements of
/// the zone between nodes. Measured: 15.2 % against 17.3 % estimated at 2.5 nodes, then within
/// 5 % of each other (3.89/3.84 % at 5 nodes, 0.245/0.234 % at 20); so the estimate may neither
/// understate nor overstate the mean error by more than 1.25×, and doubling the nodes must cut
/// the error 3.5–4.5-fold (3.9–4.0 measured: why `contact.cells` may subdivide the wear cells).
#[test]
fn the_resolution_estimate_matches_the_error_the_nodes_make() {
    let line_modulus = Foundation::calibrated(&steel(), &steel()).line_modulus();
    let (ri, rj) = (BEARING_RADIUS, BEARING_RADIUS - CLEARANCE);
    let delta = 1e-6;
    let e = CLEARANCE + delta;
    let quadrature = quadrature_force(line_modulus, e, ri, rj);
    let bearing = BodyState::at_rest(0.0, 0.0, 0.0);
    let mut previous: Option<f64> = None;
    for nodes in [125, 250, 500, 1000, 2000] {
        let joint = round_joint([0.0, 0.0], [0.0, 0.0], hertz(), Frictionless).with_model(
            ContactModel::Foundation(
                Foundation::calibrated(&steel(), &steel())
                    .with_quadrature(Quadrature::Trapezoid)
                    .and_then(|f| f.with_cells(nodes))
                    .expect("valid"),
            ),
        );
        let (mut measured, mut estimated, mut width) = (0.0, 0.0, 0.0);
        let placements = 16;
        for p in 0..placements {
            // Zone centres from one node to the next.
            let phi = (p as f64 + 0.5) / placements as f64 * std::f64::consts::TAU / nodes as f64;
            let pin = BodyState::at_rest(e * phi.cos(), e * phi.sin(), 0.0);
            let f = joint.forces(&bearing, &pin, None);
            measured += (f.pin.x.hypot(f.pin.y) / quadrature - 1.0).abs() / placements as f64;
            estimated += f.diagnostics.resolution_error / placements as f64;
            width += f64::from(f.diagnostics.narrowest_zone_cells) / placements as f64;
        }
        eprintln!(
            "{nodes:5} nodes: zones of {width:.1} nodes, measured error {:.3} %, estimated {:.3} %",
            100.0 * measured,
            100.0 * estimated
        );
        assert!(
            measured <= 1.25 * estimated && estimated <= 1.25 * measured,
            "{nodes} nodes: measured {measured:e}, estimated {estimated:e}"
        );
        if let Some(coarser) = previous {
            let gain = coarser / measured;
            assert!(
                (3.5..=4.5).contains(&gain),
                "{nodes} nodes: error cut {gain:.2}×"
            );
        }
        previous = Some(measured);
    }
}

/// Simpson's quadrature ([`Quadrature::Simpson`], the default) on the same zones as the test
/// above (a 1 µm overlap on 126–2000 nodes, 16 placements): its error against the exact
/// overlap's quadrature stays within its own resolution estimate (`0.24/n²` per zone of `n`
/// nodes, a quarter of the trapezoid's) at every placement, and from zones of 10 nodes on it
/// is below a 40th of the trapezoid's error on the same nodes. Measured (Simpson's worst /
/// its estimate / the trapezoid's mean): 3.26 / 4.33 / 14.9 % at 126 nodes (zones of 2.5),
/// 0.48 / 0.96 / 3.89 % at 250, 0.012 / 0.24 / 0.98 % at 500, 0.0018 / 0.06 / 0.24 % at 1000,
/// 0.0004 / 0.015 / 0.061 % at 2000.
#[test]
fn simpsons_quadrature_is_within_its_resolution_estimate() {
    let line_modulus = Foundation::calibrated(&steel(), &steel()).line_modulus();
    let (ri, rj) = (BEARING_RADIUS, BEARING_RADIUS - CLEARANCE);
    let delta = 1e-6;
    let e = CLEARANCE + delta;
    let quadrature = quadrature_force(line_modulus, e, ri, rj);
    let bearing = BodyState::at_rest(0.0, 0.0, 0.0);
    for nodes in [126, 250, 500, 1000, 2000] {
        let layer = Foundation::calibrated(&steel(), &steel())
            .with_cells(nodes)
            .expect("valid");
        assert_eq!(layer.quadrature(), Quadrature::Simpson);
        let trapezoid = layer.with_quadrature(Quadrature::Trapezoid).expect("valid");
        let joint = |layer| {
            round_joint([0.0, 0.0], [0.0, 0.0], hertz(), Frictionless)
                .with_model(ContactModel::Foundation(layer))
        };
        let (simpson, trapezoid) = (joint(layer), joint(trapezoid));
        let (mut measured, mut estimated, mut worst, mut ratio) = (0.0, 0.0, 0.0_f64, 0.0_f64);
        let mut trapezoid_error = 0.0;
        let placements = 16;
        for p in 0..placements {
            let phi = (p as f64 + 0.5) / placements as f64 * std::f64::consts::TAU / nodes as f64;
            let pin = BodyState::at_rest(e * phi.cos(), e * phi.sin(), 0.0);
            let f = simpson.forces(&bearing, &pin, None);
            let error = (f.pin.x.hypot(f.pin.y) / quadrature - 1.0).abs();
            measured += error / placements as f64;
            worst = worst.max(error);
            ratio = ratio.max(error / f.diagnostics.resolution_error);
            estimated += f.diagnostics.resolution_error / placements as f64;
            let t = trapezoid.forces(&bearing, &pin, None);
            trapezoid_error +=
                (t.pin.x.hypot(t.pin.y) / quadrature - 1.0).abs() / placements as f64;
        }
        eprintln!(
            "{nodes:5} nodes: Simpson's error {:.4} % (worst {:.4} %, worst/estimate {ratio:.2}), \
             estimate {:.4} %, trapezoid's {:.4} %",
            100.0 * measured,
            100.0 * worst,
            100.0 * estimated,
            100.0 * trapezoid_error
        );
        assert!(ratio <= 1.0, "{nodes} nodes: worst/estimate {ratio}");
        if nodes >= 500 {
            assert!(
                worst <= trapezoid_error / 40.0,
                "{nodes} nodes: {worst:e} against the trapezoid's {trapezoid_error:e}"
            );
        }
    }
}

/// The overlap memory (an earlier evaluation's overlaps skip the nodes that cannot have reached
/// the bearing since) changes no result: along a random walk on the worn outlines — Newton-sized
/// moves of 10 nm, step-sized ones of 1 µm, jumps into contact up to 30 µm deep or to within
/// 0.2 µm of it in the groove —
/// one joint evaluated again and again gives the forces, diagnostics, loaded nodes, Jacobian and
/// event function (deepest overlap) of a fresh copy without memory, bit for bit; and its plain
/// evaluations sample the bearing at most 40 % as often (measured 25 %; it was 53 % while the
/// walk's states near but out of contact, a third of them, were evaluated in full).
#[test]
fn the_overlap_memory_changes_no_result_and_skips_nodes() {
    let (normal, friction) = common::lgres_laws(0.9);
    let groove = worn(normal, friction);
    let samples = std::rc::Rc::new(std::cell::Cell::new(0));
    let bearing_profile = Counted {
        inner: *groove.bearing_profile(),
        samples: samples.clone(),
    };
    let pin_profile = *groove.pin_profile();
    let joint = groove
        .with_profiles(bearing_profile, pin_profile)
        .expect("valid profiles");
    let mut rng = ChaCha8Rng::seed_from_u64(77);
    let (mut bearing, mut pin) =
        random_contact(&joint, &mut rng, 0.2, 250f64.to_radians(), 0.8, 2e-6..3e-5);
    let (mut with_memory, mut fresh) = (0, 0);
    let counted = |count: &mut usize, f: &mut dyn FnMut()| {
        let before = samples.get();
        f();
        *count += samples.get() - before;
    };
    let mut contacts = 0;
    for step in 0..600 {
        let roll: f64 = rng.random_range(0.0..1.0);
        if roll < 0.1 {
            // Apart, within 0.2 µm, in the groove: nodes beyond the bearing's smallest radius
            // are visited though none touches, and the deepest is one of them.
            let (spread, overlap) = if roll < 0.04 {
                (0.2, -2e-7..0.0)
            } else {
                (1.2, 0.0..3e-5)
            };
            (bearing, pin) =
                random_contact(&joint, &mut rng, 0.2, 250f64.to_radians(), spread, overlap);
        } else {
            let size = if roll < 0.8 { 1e-8 } else { 1e-6 };
            let mut nudge = |v: f64, scale: f64| v + rng.random_range(-scale..scale);
            pin = BodyState::new(
                [
                    nudge(pin.x, size),
                    nudge(pin.y, size),
                    nudge(pin.theta, 10.0 * size),
                ],
                [pin.vx, pin.vy, pin.omega],
            );
            bearing = BodyState::new(
                [
                    nudge(bearing.x, size),
                    nudge(bearing.y, size),
                    nudge(bearing.theta, 10.0 * size),
                ],
                [bearing.vx, bearing.vy, bearing.omega],
            );
        }
        let onset = Some(0.1);
        let evaluate = |joint: &ClearanceJoint<_, _, _, _>, count: &mut usize| {
            let mut out = String::new();
            counted(count, &mut || {
                let depth = joint.penetration(&bearing, &pin);
                let forces = joint.forces(&bearing, &pin, onset);
                let mut loads: Vec<NodeLoad> = Vec::new();
                let visited =
                    joint.forces_visiting_nodes(&bearing, &pin, onset, &mut |n| loads.push(*n));
                out = format!("{:?} {forces:?} {loads:?} {visited:?}", depth.to_bits());
            });
            // The Jacobian (dual numbers) does not use the memory, but is evaluated in between.
            let (dual, jacobian) = joint.forces_and_jacobian(&bearing, &pin, onset);
            format!("{out} {dual:?} {jacobian:?}")
        };
        let remembered = evaluate(&joint, &mut with_memory);
        let from_scratch = evaluate(&joint.clone(), &mut fresh);
        if remembered != from_scratch {
            let at = remembered
                .bytes()
                .zip(from_scratch.bytes())
                .position(|(a, b)| a != b)
                .unwrap_or(0);
            let around = |text: &str| {
                text.get(at.saturating_sub(80)..)
                    .unwrap_or(text)
                    .chars()
                    .take(160)
                    .collect::<String>()
            };
            panic!(
                "step {step}: results differ with the memory:\n  with    …{}\n  without …{}",
                around(&remembered),
                around(&from_scratch)
            );
        }
        contacts += usize::from(joint.forces(&bearing, &pin, onset).diagnostics.in_contact);
    }
    let ratio = with_memory as f64 / fresh as f64;
    eprintln!(
        "overlap memory: {with_memory} bearing samples against {fresh} without it ({:.0} %), \
         600 states, {contacts} in contact",
        100.0 * ratio
    );
    assert!(contacts > 300, "{contacts} of 600 states in contact");
    assert!(
        ratio < 0.4,
        "the memory skipped too few nodes: {:.0} %",
        100.0 * ratio
    );
}
