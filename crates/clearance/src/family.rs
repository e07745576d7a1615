//! A family of mechanisms of any size, for measuring how the cost of a run grows with the
//! number of bodies (docs/performance.md, "How cost grows with size").
//!
//! [`chain`] builds a hanging ladder of parallelogram four-bar loops: rockers hang from ground
//! pivots `spacing` apart, and couplers join the lower ends of neighbouring rockers. Bodies
//! alternate rocker, coupler, rocker, …; with an even count the last coupler hangs free from
//! the last rocker (a pendulum). The first rocker is driven, `θ = −π/2 + a (1 − cos ωt)`, and
//! gravity acts. Counting the joints along the chain (each rocker's ground pivot, then the pin
//! to the next body), every `k`-th one is a clearance joint (a [`RoundClearanceForce`]) instead
//! of an ideal revolute: a clearance between two bodies cuts the chain of constraints, so the
//! mechanism is a row of rigidly connected parts coupled by contact, the structure that makes
//! the Cartesian iteration matrix block-banded; a clearance at a pivot opens a loop. The ideal
//! joints that remain close loops, which the joint-coordinate formulation keeps as constraints.

use crate::RoundClearanceForce;
use contact::{
    Ambrosio, CircularProfile, ClearanceJoint, ContactError, FrictionLawKind, JointSurface,
    LankaraniNikravesh, LineOfCentres, Material, NormalLawKind,
};
use multibody::{
    Anchor, Body, BodyId, Coordinate, DriveTarget, Gravity, Harmonic, Model, ModelError, System,
};

/// Why a family member could not be built.
#[derive(Debug, thiserror::Error)]
pub enum FamilyError {
    /// Too few bodies, or a clearance period below 2.
    #[error(
        "a chain needs at least 2 bodies and a clearance period of at least 2, got {bodies} bodies and period {period}"
    )]
    Size {
        /// Bodies asked for.
        bodies: usize,
        /// Every how many joints a clearance joint was asked for.
        period: usize,
    },
    /// `multibody` rejected a body, joint or driver.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// `contact` rejected a clearance joint.
    #[error(transparent)]
    Contact(#[from] ContactError),
}

/// Dimensions and materials of the chain (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChainParams {
    /// Distance between neighbouring ground pivots, and coupler length (m).
    pub spacing: f64,
    /// Rocker length (m).
    pub rocker: f64,
    /// Mass of every link (kg); inertia that of a slender rod.
    pub mass: f64,
    /// Drive amplitude `a` (rad).
    pub amplitude: f64,
    /// Drive angular frequency `ω` (rad/s).
    pub omega: f64,
    /// Bearing radius of the clearance joints (m).
    pub bearing_radius: f64,
    /// Radial clearance of the clearance joints (m).
    pub clearance: f64,
}

impl Default for ChainParams {
    /// 0.2 m links of 1 kg swinging ±0.15 rad at 1 Hz; 10 mm steel bearings with 0.1 mm of
    /// clearance (the LGRES's order of magnitude).
    fn default() -> Self {
        Self {
            spacing: 0.2,
            rocker: 0.2,
            mass: 1.0,
            amplitude: 0.15,
            omega: 2.0 * std::f64::consts::PI,
            bearing_radius: 0.01,
            clearance: 1e-4,
        }
    }
}

/// A built chain: the system (gravity and clearance elements added) and what it contains.
pub struct Chain {
    /// The mechanism, unassembled.
    pub system: System,
    /// Ideal revolute joints.
    pub revolutes: usize,
    /// Clearance joints (force elements).
    pub clearances: usize,
}

/// A joint of the chain: name, bearing body (`None`: ground) and its anchor, pin body and its
/// anchor.
type JointSpec = (String, Option<BodyId>, [f64; 2], BodyId, [f64; 2]);

/// The chain of `bodies` bodies with a clearance at every `period`-th joint (module docs).
pub fn chain(bodies: usize, period: usize, params: &ChainParams) -> Result<Chain, FamilyError> {
    if bodies < 2 || period < 2 {
        return Err(FamilyError::Size { bodies, period });
    }
    let ChainParams {
        spacing: l,
        rocker: h,
        mass,
        ..
    } = *params;
    let down = -std::f64::consts::FRAC_PI_2;
    let mut model = Model::new();
    let mut ids = Vec::with_capacity(bodies);
    for j in 0..bodies {
        let x = (j / 2) as f64 * l;
        let body = if j % 2 == 0 {
            Body::new(
                format!("rocker {}", j / 2),
                mass,
                mass * h * h / 12.0,
                [x, -h / 2.0, down],
            )
        } else if j + 1 < bodies {
            Body::new(
                format!("coupler {}", j / 2 + 1),
                mass,
                mass * l * l / 12.0,
                [x + l / 2.0, -h, 0.0],
            )
        } else {
            Body::new(
                "pendulum",
                mass,
                mass * l * l / 12.0,
                [x, -h - l / 2.0, down],
            )
        };
        ids.push(model.add_body(body)?);
    }
    // Joints in chain order: (name, bearing anchor on the earlier body or ground, pin anchor).
    let mut joints: Vec<JointSpec> = Vec::new();
    for j in 0..bodies {
        let id = ids[j];
        if j % 2 == 0 {
            joints.push((
                format!("pivot {}", j / 2),
                None,
                [(j / 2) as f64 * l, 0.0],
                id,
                [-h / 2.0, 0.0],
            ));
        }
        if j > 0 {
            let previous = ids[j - 1];
            let (on_previous, on_this) = if j % 2 == 1 {
                ([h / 2.0, 0.0], [-l / 2.0, 0.0])
            } else {
                ([l / 2.0, 0.0], [h / 2.0, 0.0])
            };
            joints.push((format!("pin {j}"), Some(previous), on_previous, id, on_this));
        }
    }
    let mut clearances = Vec::new();
    let mut revolutes = 0;
    for (k, (name, bearing, at, pin, on)) in joints.into_iter().enumerate() {
        if (k + 1) % period == 0 {
            clearances.push((name, bearing, at, pin, on));
            continue;
        }
        let base = match bearing {
            None => Anchor::ground(at[0], at[1]),
            Some(b) => Anchor::on(b, at[0], at[1]),
        };
        model.add_revolute(name, base, Anchor::on(pin, on[0], on[1]))?;
        revolutes += 1;
    }
    let drive = Harmonic {
        offset: down,
        amplitude: params.amplitude,
        omega: params.omega,
    };
    model.add_driver(
        "drive",
        DriveTarget::Coordinate(ids[0], Coordinate::Theta),
        Box::new(drive),
    )?;
    let gravity = Gravity::new(&model, [0.0, -9.81]);
    let mut system = System::new(model)?;
    system.add_element(Box::new(gravity));
    let steel = Material::new(207e9, 0.3)?;
    let count = clearances.len();
    for (name, bearing, at, pin, on) in clearances {
        let joint = ClearanceJoint::new(
            JointSurface {
                centre: at,
                profile: CircularProfile::new(params.bearing_radius),
                material: steel,
            },
            JointSurface {
                centre: on,
                profile: CircularProfile::new(params.bearing_radius - params.clearance),
                material: steel,
            },
            NormalLawKind::LankaraniNikravesh(LankaraniNikravesh::new(0.5)?),
            FrictionLawKind::Ambrosio(Ambrosio::new(0.1, 1e-4, 1e-3)?),
        )?
        .with_model(LineOfCentres);
        system.add_element(Box::new(RoundClearanceForce::new(
            name,
            bearing,
            Some(pin),
            joint,
        )));
    }
    Ok(Chain {
        system,
        revolutes,
        clearances: count,
    })
}
