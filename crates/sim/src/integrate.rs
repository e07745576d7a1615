//! One integration of a scene for an analysis that measures the integrator itself (the stress
//! battery, the work–precision sweep): built on the surfaces asked for, assembled at t = 0 and
//! integrated once with the scene's solver settings or tolerances scaled from them. What the
//! analysis reads of it comes back as numbers ([`Integrated`]); its failures carry a kind
//! ([`IntegrationErrorKind`]) to classify them by.
//!
//! A run of a scene ([`crate::run_scene`]) is this and more (the ideal mechanism beside it, the
//! recorded response, wear stages); the two share the build ([`crate::build::build`]), the
//! solver settings ([`simulation_options`]) and the ideal mechanism ([`ideal_motion`]).

use std::time::Instant;

use multibody::{
    AbsoluteTolerances, AssemblyError, Frame, Observer, OutputTimes, SimulationError,
    SimulationErrorKind, SimulationOptions, SimulationResult,
};
use scene::{Integrator, Scene, ValidScene};
use wear::{Side, StageWear, WearError, WornJoint, WornProfile};

use crate::build::{BuildError, JointHandle, Surfaces, build, unworn_joints};
use crate::ideal::IdealMechanism;
use crate::{Motion, RunError, simulation_options};

/// How one integration runs, beyond the scene's own settings.
#[derive(Debug, Clone)]
pub struct Integration {
    /// End time, s (the run starts at 0).
    pub t_end: f64,
    /// When the observer sees a frame.
    pub output: OutputTimes,
    /// Keep the energy books (their quadrature costs time per step).
    pub energy_audit: bool,
    /// The accepted-step budget.
    pub max_steps: StepBudget,
    /// The integrator and its tolerances; `None`: the scene's.
    pub tolerances: Option<ScaledTolerances>,
    /// The surfaces of the active clearance joints.
    pub surfaces: StartSurfaces,
}

/// An integrator at a relative tolerance, the absolute tolerances scaled with it: the scene's
/// clearance-scaled tolerances times `rtol / solver.rtol`, so the scene's own settings are the
/// point `rtol = solver.rtol` of a one-parameter family and a loose run is loose in every
/// variable.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScaledTolerances {
    /// The integrator.
    pub integrator: Integrator,
    /// Its relative tolerance.
    pub rtol: f64,
}

impl ScaledTolerances {
    /// The absolute tolerances on `scene`.
    pub fn absolute(&self, scene: &Scene) -> AbsoluteTolerances {
        let tol = scene.tolerances();
        let scale = self.rtol / scene.solver.rtol;
        let velocity = tol.velocity * scale;
        AbsoluteTolerances {
            position: tol.position * scale,
            angle: tol.angle * scale,
            velocity,
            angular_velocity: velocity,
        }
    }
}

/// How many accepted steps an integration may take.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepBudget {
    /// The scene's `solver.max_steps`.
    Scene,
    /// No limit (a reference run that must reach its end).
    Unlimited,
    /// At most this many.
    Steps(usize),
}

/// The surfaces an integration's active clearance joints start from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StartSurfaces {
    /// Round surfaces, no wear code (the response run's set-up).
    Round,
    /// Unworn wear grids where the scene wears, accumulating Archard wear on the accepted
    /// steps from this time (s).
    Wearing {
        /// Start of the accumulation, s.
        accumulate_from: f64,
    },
    /// Frozen worn surfaces, both sides worn to one uniform depth `h = (factor − 1) c0` so
    /// the clearance is `factor × c0` all round (joints without wear stay round).
    UniformlyWorn {
        /// The clearance as a multiple of the nominal one.
        factor: f64,
    },
}

/// What an integration's caller sees at every output frame: the frame and the active
/// clearance joints (their probes are `handle.probe(frame.elements)`).
pub trait FrameObserver {
    /// Called at every output time, in order.
    fn frame(&mut self, frame: &Frame<'_>, joints: &[JointHandle]);
}

impl FrameObserver for () {
    fn frame(&mut self, _frame: &Frame<'_>, _joints: &[JointHandle]) {}
}

/// An integration that reached its end (or stopped early at an event the integrator accepts).
#[derive(Debug)]
pub struct Integrated {
    /// The integrator's result: final state, statistics, drift, energy books.
    pub result: SimulationResult,
    /// The active clearance joints, in scene order.
    pub joints: Vec<JointNumbers>,
    /// Wall time of the integration alone (build and assembly excluded), s.
    pub wall_s: f64,
}

/// What one active clearance joint gathered over an integration.
#[derive(Debug, Clone)]
pub struct JointNumbers {
    /// The joint's name.
    pub name: String,
    /// Largest normal force at an accepted step end, N (`None`: the element is no clearance
    /// force).
    pub peak_normal_force: Option<f64>,
    /// Energy dissipated by friction, J (`None` as above).
    pub friction_dissipation: Option<f64>,
    /// The wear gathered on worn surfaces that accumulate it.
    pub stage_wear: Option<StageWear>,
}

/// Why an integration failed; [`IntegrationError::kind`] classifies it.
#[derive(Debug, thiserror::Error)]
pub enum IntegrationError {
    /// The scene does not make a system (field named).
    #[error(transparent)]
    Build(#[from] BuildError),
    /// The uniformly worn surfaces could not be made.
    #[error(transparent)]
    Wear(#[from] WearError),
    /// The initial poses do not assemble at t = 0.
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    /// The integrator failed or ran out of its budget.
    #[error(transparent)]
    Simulation(#[from] SimulationError),
}

/// Which way an integration failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum IntegrationErrorKind {
    /// The system or its surfaces could not be built.
    Build,
    /// The initial poses do not assemble.
    Assembly,
    /// The integration itself failed, this way.
    Simulation(SimulationErrorKind),
}

impl IntegrationErrorKind {
    /// The error's name as reports print it, e.g. `BuildError`, `SimulationError::StepLimit`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Build => "BuildError",
            Self::Assembly => "AssemblyError",
            Self::Simulation(kind) => match kind {
                SimulationErrorKind::Assembly => "SimulationError::Assembly",
                SimulationErrorKind::InvalidOptions => "SimulationError::InvalidOptions",
                SimulationErrorKind::Evaluation => "SimulationError::Evaluation",
                SimulationErrorKind::Integrator => "SimulationError::Integrator",
                SimulationErrorKind::StepLimit => "SimulationError::StepLimit",
                SimulationErrorKind::WallTimeLimit => "SimulationError::WallTimeLimit",
            },
        }
    }
}

impl IntegrationError {
    /// Which way it failed.
    pub fn kind(&self) -> IntegrationErrorKind {
        match self {
            Self::Build(_) | Self::Wear(_) => IntegrationErrorKind::Build,
            Self::Assembly(_) => IntegrationErrorKind::Assembly,
            Self::Simulation(e) => IntegrationErrorKind::Simulation(e.kind()),
        }
    }
}

impl Integration {
    /// The integrator's options on `scene`.
    pub fn simulation_options(&self, scene: &Scene) -> SimulationOptions {
        let mut options = simulation_options(scene, self.t_end, self.output.clone(), false);
        if let Some(tolerances) = &self.tolerances {
            options.integrator = tolerances.integrator;
            options.rtol = tolerances.rtol;
            options.atol = tolerances.absolute(scene);
        }
        options.energy_audit = self.energy_audit;
        match self.max_steps {
            StepBudget::Scene => {}
            StepBudget::Unlimited => options.max_steps = None,
            StepBudget::Steps(n) => options.max_steps = Some(n),
        }
        options
    }
}

/// Builds `scene` on `integration`'s surfaces, assembles it at t = 0 from the file's initial
/// poses and integrates it once, `observer` seeing every output frame.
pub fn integrate(
    scene: &ValidScene,
    integration: &Integration,
    observer: &mut dyn FrameObserver,
) -> Result<Integrated, IntegrationError> {
    let (worn, accumulate_from) = match integration.surfaces {
        StartSurfaces::Round => (Vec::new(), None),
        StartSurfaces::Wearing { accumulate_from } => {
            (unworn_joints(scene)?, Some(accumulate_from))
        }
        StartSurfaces::UniformlyWorn { factor } => (uniformly_worn(scene, factor)?, None),
    };
    let surfaces = Surfaces {
        worn: &worn,
        accumulate_from,
        split_halves_at: None,
    };
    let mut built = build(scene, surfaces)?;
    let (q0, qd0) = built.system.initial_guess();
    let state = built.system.assemble(0.0, &q0, &qd0)?;
    let options = integration.simulation_options(scene);
    let mut frames = Frames {
        joints: &built.joints,
        observer,
    };
    let started = Instant::now();
    let result = built.system.simulate(&state, &options, &mut frames)?;
    let wall_s = started.elapsed().as_secs_f64();
    let mut joints: Vec<JointNumbers> = built
        .joints
        .iter()
        .map(|h| {
            let probe = h.probe(built.system.elements());
            JointNumbers {
                name: h.name.clone(),
                peak_normal_force: probe.map(|p| p.peak_normal_force()),
                friction_dissipation: probe.map(|p| p.friction_dissipation()),
                stage_wear: None,
            }
        })
        .collect();
    for (h, numbers) in built.joints.iter().zip(&mut joints).filter(|(h, _)| h.worn) {
        numbers.stage_wear = built
            .system
            .element_mut::<clearance::WornClearanceForce>(h.element)
            .and_then(clearance::WornClearanceForce::take_stage_wear);
    }
    Ok(Integrated {
        result,
        joints,
        wall_s,
    })
}

/// The ideal mechanism's motion of `body` at `times` (kinematic analysis from the file's
/// initial poses, every clearance joint ideal): what a response is measured against.
pub fn ideal_motion(scene: &ValidScene, times: &[f64], body: usize) -> Result<Motion, RunError> {
    Ok(IdealMechanism::build(scene)?
        .motion(times, body, None)?
        .motion)
}

/// Hands each output frame to the caller's observer with the joints.
struct Frames<'a> {
    joints: &'a [JointHandle],
    observer: &'a mut dyn FrameObserver,
}

impl Observer for Frames<'_> {
    fn output(&mut self, frame: &Frame<'_>) {
        self.observer.frame(frame, self.joints);
    }
}

/// The unworn joints of `scene` worn to `h = (factor − 1) c0` on both sides.
fn uniformly_worn(scene: &Scene, factor: f64) -> Result<Vec<Option<WornJoint>>, IntegrationError> {
    unworn_joints(scene)?
        .into_iter()
        .map(|joint| {
            let Some(joint) = joint else { return Ok(None) };
            let h = (factor - 1.0) * joint.nominal_clearance();
            let (b, p) = (joint.bearing(), joint.pin());
            let bearing =
                WornProfile::from_depths(Side::Bearing, b.nominal_radius(), vec![h; b.cells()])?;
            let pin = WornProfile::from_depths(Side::Pin, p.nominal_radius(), vec![h; p.cells()])?;
            Ok(Some(WornJoint::from_profiles(
                joint.wear_coefficient(),
                joint.hinge_width(),
                bearing,
                pin,
            )?))
        })
        .collect()
}
