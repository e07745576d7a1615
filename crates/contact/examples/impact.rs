//! A pin dropped into a fixed bearing with the LGRES joint-A parameters.
//!
//! The bearing (R_i = 0.05 m, clearance 0.5 mm) is fixed; a free 5 kg pin body starts concentric,
//! moving down at 0.1 m/s and sideways at 0.03 m/s, under gravity. Its motion is integrated with
//! classical RK4 at a fixed 0.1 µs step for 30 ms, and each impact is summarised. The measured
//! restitution is the ratio of normal velocities after and before; gravity and friction act
//! during contact, so it need not equal c_e exactly (L–N alone gives ≈ 0.913 for c_e = 0.9).
//!
//! Run with `cargo run --release -p contact --example impact`.

use contact::{
    Ambrosio, BodyState, CircularProfile, ClearanceJoint, ContactDiagnostics, ContactError,
    ImpactMemory, JointSurface, LankaraniNikravesh, LineOfCentres, Material,
};

const STEP: f64 = 1e-7;
const DURATION: f64 = 0.03;
const GRAVITY: f64 = 9.81;
const PIN_MASS: f64 = 5.0;
const PIN_INERTIA: f64 = 5e-3;

/// One impact, from the first to the last step in contact.
#[derive(Default)]
struct Impact {
    start_time: f64,
    impact_velocity: f64,
    peak_force: f64,
    peak_penetration: f64,
    separation_velocity: Option<f64>,
}

/// `(ẋ, ẏ, θ̇, ẍ, ÿ, θ̈)` of the pin body.
type Rate = [f64; 6];

fn advance(pin: &BodyState, rate: &Rate, h: f64) -> BodyState {
    BodyState::new(
        [
            pin.x + h * rate[0],
            pin.y + h * rate[1],
            pin.theta + h * rate[2],
        ],
        [
            pin.vx + h * rate[3],
            pin.vy + h * rate[4],
            pin.omega + h * rate[5],
        ],
    )
}

fn main() -> Result<(), ContactError> {
    let steel = Material::new(200e9, 0.3)?;
    let joint = ClearanceJoint::new(
        JointSurface {
            centre: [0.0, 0.0],
            profile: CircularProfile::new(0.05),
            material: steel,
        },
        JointSurface {
            centre: [0.0, 0.0],
            profile: CircularProfile::new(0.0495),
            material: steel,
        },
        LankaraniNikravesh::new(0.9)?,
        Ambrosio::new(0.15, 1e-4, 1e-3)?,
    )?
    .with_model(LineOfCentres);
    let bearing = BodyState::at_rest(0.0, 0.0, 0.0);
    let mut pin = BodyState::new([0.0, 0.0, 0.0], [0.03, -0.1, 0.0]);

    let rate = |pin: &BodyState, onset: Option<f64>| -> Rate {
        let f = joint.forces(&bearing, pin, onset).pin;
        [
            pin.vx,
            pin.vy,
            pin.omega,
            f.x / PIN_MASS,
            f.y / PIN_MASS - GRAVITY,
            f.z / PIN_INERTIA,
        ]
    };

    let mut memory = ImpactMemory::new();
    let mut previous: ContactDiagnostics = joint.forces(&bearing, &pin, None).diagnostics;
    let mut impacts: Vec<Impact> = Vec::new();
    let steps = (DURATION / STEP).round() as usize;
    for step in 1..=steps {
        let onset = memory.onset_velocity();
        let k1 = rate(&pin, onset);
        let k2 = rate(&advance(&pin, &k1, 0.5 * STEP), onset);
        let k3 = rate(&advance(&pin, &k2, 0.5 * STEP), onset);
        let k4 = rate(&advance(&pin, &k3, STEP), onset);
        let mean: Rate = std::array::from_fn(|m| (k1[m] + 2.0 * k2[m] + 2.0 * k3[m] + k4[m]) / 6.0);
        pin = advance(&pin, &mean, STEP);

        let current = joint
            .forces(&bearing, &pin, memory.onset_velocity())
            .diagnostics;
        memory.update(&previous, &current);
        if current.in_contact && !previous.in_contact {
            impacts.push(Impact {
                start_time: step as f64 * STEP,
                impact_velocity: memory.onset_velocity().unwrap_or(current.normal_velocity),
                ..Impact::default()
            });
        }
        if let Some(impact) = impacts.last_mut() {
            if current.in_contact {
                impact.peak_force = impact.peak_force.max(current.normal_force);
                impact.peak_penetration = impact.peak_penetration.max(current.penetration);
            } else if previous.in_contact {
                impact.separation_velocity = Some(current.normal_velocity);
            }
        }
        previous = current;
    }

    println!(
        "pin (5 kg) dropped into LGRES joint A: R_i = 50 mm, c = 0.5 mm, steel, c_e = 0.9, c_f = 0.15"
    );
    println!(
        "RK4, fixed step {:.0e} s, {:.0} ms simulated",
        STEP,
        DURATION * 1e3
    );
    println!();
    println!(" #   t (ms)   v_impact (m/s)   peak F_n (N)   peak δ (µm)   restitution");
    for (k, impact) in impacts.iter().enumerate() {
        let restitution = impact.separation_velocity.map_or_else(
            || "in contact".to_string(),
            |v| format!("{:.4}", -v / impact.impact_velocity),
        );
        println!(
            "{:2}   {:6.3}   {:14.5}   {:12.1}   {:11.3}   {restitution:>11}",
            k + 1,
            impact.start_time * 1e3,
            impact.impact_velocity,
            impact.peak_force,
            impact.peak_penetration * 1e6,
        );
    }
    if impacts.is_empty() {
        println!("no impact in {:.0} ms", DURATION * 1e3);
    }
    Ok(())
}
