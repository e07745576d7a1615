//! How to run a scene: the overrides of its run settings ([`RunOptions`]) and the
//! integrator's options from its solver settings ([`simulation_options`]).

use multibody::{AbsoluteTolerances, Baumgarte, OutputTimes, SimulationOptions};

use scene::Scene;

/// Overrides of the scene's run settings.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Start from worn surfaces, e.g. an earlier run's (crate `output` reads its last-stage
    /// `wear_<joint>_stage<k>.csv` files; see [`crate::surfaces`]). The response run and the
    /// stages then begin from those surfaces.
    pub surfaces: Option<std::sync::Arc<dyn crate::surfaces::SurfaceSource>>,
    /// Simulated cycles per wear stage `K` instead of `run.cycles_per_stage`; the
    /// amplification is rescaled so a stage still stands for `K_scene × amplification` cycles.
    pub cycles_per_stage: Option<u32>,
    /// Trajectories a wear sub-step's `K` cycles are spread over, instead of
    /// `run.trajectories`; they must divide `K`.
    pub trajectories: Option<u32>,
    /// Threads a wear sub-step's trajectories run on (`run.trajectories`; default: the
    /// machine's cores). The results do not depend on it.
    pub threads: Option<usize>,
    /// Skip the response run on the worn surfaces after the stages.
    pub skip_worn_response: bool,
}

/// Simulation options from the scene's solver settings (integrator, rtol, the clearance-scaled
/// absolute tolerances, Baumgarte gains) for a run to `t_end`.
pub fn simulation_options(
    scene: &Scene,
    t_end: f64,
    output: OutputTimes,
    record: bool,
) -> SimulationOptions {
    let tol = scene.tolerances();
    let mut o = SimulationOptions::until(t_end);
    o.integrator = scene.solver.integrator;
    o.formulation = scene.solver.formulation;
    o.rtol = scene.solver.rtol;
    o.atol = AbsoluteTolerances {
        position: tol.position,
        angle: tol.angle,
        velocity: tol.velocity,
        angular_velocity: tol.velocity,
    };
    o.baumgarte = Baumgarte {
        alpha: scene.solver.baumgarte_alpha,
        beta: scene.solver.baumgarte_beta,
    };
    o.output = output;
    o.record_trajectory = record;
    o.max_steps = Some(scene.solver.max_steps.unwrap_or(scene::DEFAULT_MAX_STEPS));
    let wall = scene
        .solver
        .max_wall_time
        .unwrap_or(scene::DEFAULT_MAX_WALL_TIME);
    o.max_wall_time = std::time::Duration::try_from_secs_f64(wall).ok();
    o
}
