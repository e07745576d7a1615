//! How many foundation nodes the contact force needs on worn surfaces, and how close the
//! thin-gap model comes: the elastic-foundation force and moment at random poses, with the
//! pin's outline sampled at a range of node counts, and the thin gap's on half and on all the
//! wear cells, against the foundation on 20 nodes per wear cell (the reference).
//!
//! ```sh
//! cargo run --release -p analysis --example foundation_accuracy -- SURFACES [POSES [SEED]]
//! ```
//!
//! Each count runs with both quadratures (`contact::Quadrature`). `SURFACES` is the folder of an earlier `wearsim run` (its last stage's
//! `wear_<joint>_stage<k>.csv` are read, as `--surfaces` reads them). Each pose turns bearing and
//! pin by random angles, points the eccentricity in a random direction and sets its length so
//! that the reference's deepest overlap is a random 5–30 µm (the worn responses' range), with
//! random velocities of the size a 60-rpm LGRES cycle gives (0.05 m/s, 2 rad/s: damping and
//! friction included). Errors are of the pin's force vector over the reference's magnitude and
//! of its moment about the pin centre over that magnitude times the pin radius; the table gives
//! their median, 95th percentile and maximum per node count, and the nanoseconds an evaluation
//! took (indicative: one process, whatever else runs); the last column is the largest force
//! error over the largest reference force of all poses (the peak load).

use std::path::Path;
use std::time::Instant;

use contact::{
    BodyState, ClearanceJoint, ContactModelKind, FrictionLawKind, JointSurface, Material,
    NormalLawKind, Quadrature, ThinGap,
};
use output::surfaces::load_last_stage;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use sim::build::unworn_joints;
use wear::{WornJoint, WornProfile};

type WornContact = ClearanceJoint<WornProfile, WornProfile, NormalLawKind, FrictionLawKind>;

/// Node counts tried, as multiples of the joint's wear cells (the last, with Simpson's
/// quadrature, is the reference: 10× the 2000 nodes joint B had until 2026-11-26).
const FACTORS: [f64; 6] = [0.125, 0.25, 0.5, 1.0, 2.0, 20.0];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = args
        .first()
        .ok_or("usage: foundation_accuracy SURFACES [POSES [SEED]]")?;
    let poses: usize = args.get(1).map_or(Ok(200), |s| s.parse())?;
    let seed: u64 = args.get(2).map_or(Ok(1), |s| s.parse())?;
    let scene = lgres::scenes::builtin("lgres")?;
    let unworn = unworn_joints(&scene)?;
    let worn = load_last_stage(Path::new(dir), &scene, &unworn)?;
    let active = scene.clearance_joints.iter().filter(|c| !c.ideal);
    for (spec, surfaces) in active.zip(&worn) {
        let Some(surfaces) = surfaces else { continue };
        // The scene's layer, on either model that has one.
        let foundation = match spec.contact_model()? {
            ContactModelKind::Foundation(layer) => layer,
            ContactModelKind::ThinGap(thin) => thin.layer(),
            _ => continue,
        };
        let own = surfaces.pin().cells();
        let contact = |cells: usize,
                       quadrature: Quadrature,
                       thin: bool|
         -> Result<WornContact, Box<dyn std::error::Error>> {
            let layer = foundation.with_quadrature(quadrature)?.with_cells(cells)?;
            let model = if thin {
                ContactModelKind::ThinGap(ThinGap::new(layer))
            } else {
                ContactModelKind::Foundation(layer)
            };
            let joint = ClearanceJoint::new(
                JointSurface {
                    centre: [0.0, 0.0],
                    profile: surfaces.bearing().clone(),
                    material: Material::try_from(spec.bearing_material)?,
                },
                JointSurface {
                    centre: [0.0, 0.0],
                    profile: surfaces.pin().clone(),
                    material: Material::try_from(spec.pin_material)?,
                },
                NormalLawKind::from_params(spec.normal_law)?,
                FrictionLawKind::from_params(spec.friction)?,
            )?
            .with_friction_sliding(spec.sliding.friction)
            .with_model(model);
            Ok(joint)
        };
        let counts: Vec<usize> = FACTORS
            .iter()
            .map(|f| 2 * (own as f64 * f / 2.0).round() as usize)
            .collect();
        let mut joints = Vec::new();
        for &n in &counts[..counts.len() - 1] {
            for quadrature in [Quadrature::Trapezoid, Quadrature::Simpson] {
                joints.push((n, quadrature, "foundation", contact(n, quadrature, false)?));
            }
        }
        for &n in &counts[2..4] {
            joints.push((
                n,
                Quadrature::Simpson,
                "thin-gap",
                contact(n, Quadrature::Simpson, true)?,
            ));
        }
        let reference_nodes = counts[counts.len() - 1];
        let reference = contact(reference_nodes, Quadrature::Simpson, false)?;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let states = sample_poses(&reference, surfaces, poses, &mut rng);
        println!(
            "joint {}: {} poses, nodes {:?} (reference {})",
            spec.name,
            states.len(),
            &counts[..counts.len() - 1],
            reference_nodes
        );
        println!(
            "| model | nodes | quadrature | force error median / 95 % / max | moment error median / 95 % / max | \
             narrowest zone (nodes, min) | ns per evaluation | largest force error / peak load |"
        );
        println!("|---|---:|---|---|---|---:|---:|---:|");
        let truth: Vec<_> = states
            .iter()
            .map(|(b, p)| reference.forces(b, p, Some(0.1)))
            .collect();
        let radius = surfaces.pin().nominal_radius();
        let peak = truth
            .iter()
            .map(|t| t.pin.x.hypot(t.pin.y))
            .fold(0.0, f64::max);
        for (n, quadrature, model, joint) in &joints {
            let mut largest: f64 = 0.0;
            let started = Instant::now();
            let mut force_errors = Vec::with_capacity(states.len());
            let mut moment_errors = Vec::with_capacity(states.len());
            for ((b, p), t) in states.iter().zip(&truth) {
                let f = joint.forces(b, p, Some(0.1));
                let scale = t.pin.x.hypot(t.pin.y);
                let error = (f.pin.x - t.pin.x).hypot(f.pin.y - t.pin.y);
                largest = largest.max(error);
                force_errors.push(error / scale);
                let moment = |forces: &contact::ContactForces| {
                    // About the pin centre (at the pin body's origin here).
                    forces.pin.z
                };
                moment_errors.push((moment(&f) - moment(t)).abs() / (scale * radius));
            }
            let nanos = started.elapsed().as_nanos() as f64 / states.len() as f64;
            let narrowest = states
                .iter()
                .filter_map(|(b, p)| {
                    let d = joint.forces(b, p, Some(0.1)).diagnostics;
                    (d.narrowest_zone_cells > 0).then_some(d.narrowest_zone_cells)
                })
                .min()
                .unwrap_or(0);
            println!(
                "| {model} | {n} | {quadrature:?} | {} | {} | {narrowest} | {nanos:.0} | {:.3} % |",
                quantiles(&mut force_errors),
                quantiles(&mut moment_errors),
                100.0 * largest / peak
            );
        }
        println!();
    }
    Ok(())
}

/// `median / 95 % / max` of `values` in per cent.
fn quantiles(values: &mut [f64]) -> String {
    values.sort_by(f64::total_cmp);
    let at = |q: f64| values[((values.len() - 1) as f64 * q).round() as usize] * 100.0;
    format!("{:.3} / {:.3} / {:.3} %", at(0.5), at(0.95), at(1.0))
}

/// Random poses whose deepest overlap on `reference` is 5–30 µm.
fn sample_poses(
    reference: &WornContact,
    surfaces: &WornJoint,
    count: usize,
    rng: &mut ChaCha8Rng,
) -> Vec<(BodyState, BodyState)> {
    let reach = surfaces.nominal_clearance()
        + surfaces
            .bearing()
            .depth()
            .iter()
            .fold(0.0_f64, |a, &b| a.max(b))
        + surfaces
            .pin()
            .depth()
            .iter()
            .fold(0.0_f64, |a, &b| a.max(b))
        + 1e-4;
    let mut states = Vec::with_capacity(count);
    while states.len() < count {
        let theta_bearing = rng.random_range(-std::f64::consts::PI..std::f64::consts::PI);
        let theta_pin = rng.random_range(-std::f64::consts::PI..std::f64::consts::PI);
        let direction = rng.random_range(-std::f64::consts::PI..std::f64::consts::PI);
        let target = rng.random_range(5e-6..30e-6);
        let bearing = BodyState::new(
            [0.0, 0.0, theta_bearing],
            [0.0, 0.0, rng.random_range(-2.0..2.0)],
        );
        let velocity = [rng.random_range(-0.05..0.05), rng.random_range(-0.05..0.05)];
        let omega = rng.random_range(-2.0..2.0);
        let pin_at = |e: f64| {
            BodyState::new(
                [e * direction.cos(), e * direction.sin(), theta_pin],
                [velocity[0], velocity[1], omega],
            )
        };
        // The deepest overlap grows with the eccentricity along a fixed direction: bisect.
        let (mut low, mut high) = (0.0, reach);
        if reference.penetration(&bearing, &pin_at(high)) < target {
            continue;
        }
        for _ in 0..60 {
            let mid = 0.5 * (low + high);
            if reference.penetration(&bearing, &pin_at(mid)) < target {
                low = mid;
            } else {
                high = mid;
            }
        }
        states.push((bearing, pin_at(high)));
    }
    states
}
