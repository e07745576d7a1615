//! Run settings given outside the scene file (the command line's `--cycles`, `--stages`, …,
//! or the Python bindings' keyword arguments), applied the same way by every front end.
//!
//! ```
//! use sim::overrides::RunOverrides;
//!
//! # const CRANK: &str = r#"
//! description = "A driven crank"
//! inertia_convention = "centroidal"
//! gravity = [0.0, -9.81]
//!
//! [[bodies]]
//! name = "crank"
//! mass = 0.3
//! inertia = 1e-4
//! x = 0.025
//! y = 0.0
//! theta_deg = 0.0
//!
//! [[revolute_joints]]
//! name = "O"
//! body = "crank"
//! point = [-0.025, 0.0]
//! other = "ground"
//! other_point = [0.0, 0.0]
//!
//! [[drivers]]
//! name = "speed"
//! target = { kind = "body-coordinate", body = "crank", coordinate = "theta" }
//! law = { kind = "ramp", value = 0.0, rate = 6.283 }
//! "#;
//! let scene = scene::load_str(CRANK, "crank", &[])?;
//! let o = RunOverrides { cycles: Some(1), stages: Some(0), ..Default::default() };
//! let scene = o.apply(scene, "crank with command-line overrides")?;
//! assert_eq!((scene.run.cycles, scene.run.wear_stages), (1, 0));
//! assert_eq!(o.run_options().cycles_per_stage, Some(sim::overrides::QUICK_CYCLES_PER_STAGE));
//! # Ok::<(), scene::SceneError>(())
//! ```

use crate::RunOptions;
use scene::{Scene, SceneError, ValidScene};

/// Simulated cycles per wear stage `K` when none is given: quick (the amplification is
/// rescaled so a stage still stands for as many cycles, see [`RunOptions::cycles_per_stage`]).
pub const QUICK_CYCLES_PER_STAGE: u32 = 2;

/// Trajectories of a wear sub-step when neither they nor `K` are given: the quick `K`'s cycles
/// each on its own trajectory, in parallel ([`scene::RunSettings::trajectories`]).
pub const QUICK_TRAJECTORIES: u32 = 2;

/// Overrides of a scene's run settings; `None` keeps the scene's value.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunOverrides {
    /// Drive cycles of the response run (`run.cycles`).
    pub cycles: Option<u32>,
    /// Wear stages (`run.wear_stages`).
    pub stages: Option<u32>,
    /// Relative tolerance (`solver.rtol`).
    pub rtol: Option<f64>,
    /// Accepted-step budget of each simulation (`solver.max_steps`).
    pub max_steps: Option<usize>,
    /// Wall-time budget of each simulation, s (`solver.max_wall_time`).
    pub max_wall_time: Option<f64>,
    /// Simulated cycles per wear stage (default [`QUICK_CYCLES_PER_STAGE`]).
    pub cycles_per_stage: Option<u32>,
    /// Trajectories per wear sub-step (`run.trajectories`); default [`QUICK_TRAJECTORIES`]
    /// when `cycles_per_stage` is not given either, else the scene's.
    pub trajectories: Option<u32>,
    /// Error-controlled wear sub-steps at this tolerance (`run.wear_tolerance`, e.g. 0.05).
    pub wear_tolerance: Option<f64>,
    /// Threads the trajectories run on (default: the machine's cores); results do not depend
    /// on it.
    pub threads: Option<usize>,
}

impl RunOverrides {
    /// The scene field each override sets, by the name a sweep file's `[run]` table gives it
    /// (`cycles_per_stage` and `trajectories` are the run's: [`crate::scene_as_run`]).
    pub const SCENE_FIELDS: [(&'static str, &'static str); 8] = [
        ("cycles", "run.cycles"),
        ("stages", "run.wear_stages"),
        ("rtol", "solver.rtol"),
        ("max_steps", "solver.max_steps"),
        ("max_wall_time", "solver.max_wall_time"),
        ("cycles_per_stage", "run.cycles_per_stage"),
        ("trajectories", "run.trajectories"),
        ("wear_tolerance", "run.wear_tolerance"),
    ];

    /// The scene fields every run with these overrides replaces, as in [`Self::SCENE_FIELDS`]:
    /// those given, and `run.trajectories` whenever [`Self::run_options`] sets the trajectories
    /// (also when not given, with `cycles_per_stage` not given either). A scene value there
    /// never runs, so a sweep must not vary it. `cycles_per_stage` is not among them: the
    /// scene's `K` still sets what a stage stands for (`K × amplification`).
    pub fn replaced_fields(&self) -> Vec<(&'static str, &'static str)> {
        let replaced = [
            self.cycles.is_some(),
            self.stages.is_some(),
            self.rtol.is_some(),
            self.max_steps.is_some(),
            self.max_wall_time.is_some(),
            false,
            self.run_options().trajectories.is_some(),
            self.wear_tolerance.is_some(),
        ];
        Self::SCENE_FIELDS
            .into_iter()
            .zip(replaced)
            .filter_map(|(field, replaced)| replaced.then_some(field))
            .collect()
    }

    /// `scene` with the overridden fields set, checked again if that changed it; `origin` names
    /// the scene and where the overrides came from (e.g. "lgres with command-line overrides").
    pub fn apply(&self, scene: ValidScene, origin: &str) -> Result<ValidScene, SceneError> {
        let mut edited = Scene::clone(&scene);
        self.set(&mut edited);
        if edited == *scene {
            Ok(scene)
        } else {
            ValidScene::new(edited, origin)
        }
    }

    fn set(&self, scene: &mut Scene) {
        if let Some(c) = self.cycles {
            scene.run.cycles = c;
        }
        if let Some(s) = self.stages {
            scene.run.wear_stages = s;
        }
        if let Some(r) = self.rtol {
            scene.solver.rtol = r;
        }
        if let Some(n) = self.max_steps {
            scene.solver.max_steps = Some(n);
        }
        if let Some(t) = self.max_wall_time {
            scene.solver.max_wall_time = Some(t);
        }
        if let Some(m) = self.trajectories {
            scene.run.trajectories = m;
        }
        if let Some(t) = self.wear_tolerance {
            scene.run.wear_tolerance = Some(t);
        }
    }

    /// The options of [`crate::run_scene`]: `K` defaults to [`QUICK_CYCLES_PER_STAGE`]
    /// and, with it, the trajectories to [`QUICK_TRAJECTORIES`].
    pub fn run_options(&self) -> RunOptions {
        RunOptions {
            cycles_per_stage: Some(self.cycles_per_stage.unwrap_or(QUICK_CYCLES_PER_STAGE)),
            trajectories: self
                .trajectories
                .or((self.cycles_per_stage.is_none()).then_some(QUICK_TRAJECTORIES)),
            threads: self.threads,
            ..RunOptions::default()
        }
    }
}
