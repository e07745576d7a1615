//! The scene format: a planar mechanism with ideal and clearance revolute joints, as TOML —
//! the bottom of the application's data flow (`scene` → `sim`'s run → `output`'s files →
//! `analysis`, `sweep`, `cli`, `python`; the LGRES model's scenes are crate `lgres`'s).
//!
//! A scene is data only. Units are SI throughout (m, kg, s, N, Pa, rad) with one exception made
//! for people who read and write files by hand: initial body angles are given in degrees
//! (`theta_deg`) and stored in radians ([`Angle`]). Every struct rejects unknown keys, so a typo
//! is an error rather than a silently ignored setting.
//!
//! Get a validated scene ([`ValidScene`]) from [`builtin`], [`load_path`] or [`load_str`]; all
//! three resolve `extends` (see below) against a list of named scenes ([`Builtin`]: the LGRES
//! model ships its own, `lgres::scenes::BUILTINS`) and run [`Scene::validate`], so a scene
//! returned by them names only existing bodies, has finite numbers and physically meaningful
//! parameters. A [`ValidScene`] cannot be changed in place: [`ValidScene::edit`] checks the
//! changed copy again, and the run takes only this type.
//! A scene given as "a built-in name or a file path" (the command line, the Python bindings,
//! sweep files) is found and loaded by [`load_named`].
//!
//! ```
//! use scene::{BodyRef, Builtin, builtin, load_str};
//!
//! // A crank turning about a ground pivot, shipped under a name...
//! const CRANK: &str = r#"
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
//! let shipped = [Builtin { name: "crank", summary: "a driven crank", source: CRANK }];
//! let crank = builtin(&shipped, "crank")?;
//! assert_eq!(crank.degrees_of_freedom(), 0);
//! assert_eq!(crank.resolve("crank"), Some(BodyRef::Body(0)));
//!
//! // ...and a variant that extends it and changes one value.
//! let patch = "extends = \"crank\"\n[[bodies]]\nname = \"crank\"\nmass = 0.6\n";
//! let heavy = load_str(patch, "heavy", &shipped)?;
//! assert_eq!(heavy.bodies[0].mass, 0.6);
//! assert!(load_str(patch, "heavy", &[]).is_err()); // no scene named `crank` to extend
//! # Ok::<(), scene::SceneError>(())
//! ```
//!
//! # Variants (`extends`)
//! A scene file may start with `extends = "<name>"` (a built-in scene, or a file path relative
//! to the extending file) and give only what changes. The patch is merged into the base: tables
//! merge key by key, and arrays of tables (`bodies`, `revolute_joints`, …) merge element by
//! element matched on `name`, an unmatched name being appended (a name given twice in one patch
//! is an error). Other values replace, and so do an empty array (`drivers = []` removes the
//! base's) and a table whose `law`, `kind` or contact `model` differs from the base's. This keeps
//! the study variants a few lines each and the reconstructed geometry in one file.
//!
//! # Layout and the lower crates' types
//! The data types are in `types`, loading and `extends` in `extends`, a scene given by name or
//! path in `named`, the named scenes in `builtins`, a clearance joint's contact model (one
//! tagged value, a module per model that builds, words and checks it) in `contact_spec`, the
//! per-field checks in `validate`, the numeric limits in [`limits`] and the rules for names that become file names in
//! [`file_names`]. Contact laws, materials, the sliding choice, the integrator and driven
//! coordinates are `contact`'s and `multibody`'s own serde types, re-exported here; `contact`
//! also reads the spellings of older scene files (`law = "hertz-lankarani-nikravesh"`,
//! `impact_velocity_floor`, `v0`, `v1`) and checks their ranges, which validation reports under
//! the parameter's field path.

#![warn(missing_docs)]

mod builtins;
mod contact_spec;
mod defaults;
mod error;
mod extends;
pub mod file_names;
pub mod limits;
mod named;
mod run_settings;
mod type_errors;
mod types;
mod valid;
mod validate;

pub use builtins::{Builtin, source};
// Every model's scene value, as `contact_spec` declares it: a new model adds nothing here.
pub use contact_spec::*;
pub use error::{Issue, SceneError};
pub use extends::{builtin, from_table, load_path, load_str, merged_table, merged_table_of_file};
pub use named::{LoadError, Loadable, NotFound, load_named};
pub use run_settings::{
    DEFAULT_FORMING_DEPTH, DEFAULT_WEAR_SMOOTHING_DEG, KdCorrelation, RunSettings,
};
pub use types::*;
pub use valid::ValidScene;

pub use contact::{FrictionLawParams, MaterialParams, NormalLawParams, SlidingVelocity};
pub use multibody::{Coordinate, Formulation, Integrator};

/// Arm (m) converting the default position tolerance into the default angle tolerance.
const REFERENCE_ARM: f64 = 1.0;

/// A body reference resolved against a scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BodyRef {
    /// The fixed frame.
    Ground,
    /// Index into [`Scene::bodies`].
    Body(usize),
}

impl Scene {
    /// Resolve a body name (`ground` included).
    pub fn resolve(&self, name: &str) -> Option<BodyRef> {
        if name == GROUND {
            return Some(BodyRef::Ground);
        }
        self.bodies
            .iter()
            .position(|b| b.name == name)
            .map(BodyRef::Body)
    }

    /// Initial global position of a point given in `body`'s frame (`ground`: the point itself).
    /// `None` if the body does not exist.
    pub fn initial_point(&self, body: &str, local: [f64; 2]) -> Option<[f64; 2]> {
        match self.resolve(body)? {
            BodyRef::Ground => Some(local),
            BodyRef::Body(k) => {
                let b = &self.bodies[k];
                let (s, c) = b.theta.rad().sin_cos();
                Some([
                    b.x + c * local[0] - s * local[1],
                    b.y + s * local[0] + c * local[1],
                ])
            }
        }
    }

    /// Number of constraint equations: 2 per revolute, 1 or 2 per prismatic, 1 per driver, 2 per
    /// clearance joint marked `ideal`, 0 per clearance joint.
    pub fn constraint_count(&self) -> usize {
        2 * self.revolute_joints.len()
            + self
                .prismatic_joints
                .iter()
                .map(|p| 1 + usize::from(p.lock_rotation))
                .sum::<usize>()
            + self.drivers.len()
            + 2 * self.clearance_joints.iter().filter(|c| c.ideal).count()
    }

    /// Degrees of freedom `3·bodies − constraints` (a count, not a rank: redundant constraints
    /// show up only in the assembly check).
    pub fn degrees_of_freedom(&self) -> i64 {
        3 * self.bodies.len() as i64 - self.constraint_count() as i64
    }

    /// Clearance joints that act as contact force elements (not marked `ideal`).
    pub fn active_clearance_joints(&self) -> impl Iterator<Item = &ClearanceJointSpec> {
        self.clearance_joints.iter().filter(|c| !c.ideal)
    }

    /// Duration of one drive cycle, s: `run.period`, else the first driver law with a period.
    pub fn cycle_period(&self) -> Option<f64> {
        self.run
            .period
            .or_else(|| self.drivers.iter().find_map(|d| d.law.period()))
    }

    /// Index of the body whose response is recorded (see [`RunSettings::response_body`]).
    pub fn response_body(&self) -> Option<usize> {
        match &self.run.response_body {
            Some(name) => match self.resolve(name)? {
                BodyRef::Body(k) => Some(k),
                BodyRef::Ground => None,
            },
            None => self
                .bodies
                .iter()
                .position(|b| b.name == "rod3")
                .or(self.bodies.len().checked_sub(1)),
        }
    }

    /// Absolute tolerances with defaults resolved (see [`Solver`]).
    pub fn tolerances(&self) -> Tolerances {
        let position = self.solver.atol_position.unwrap_or_else(|| {
            self.active_clearance_joints()
                .map(|c| c.clearance * DEFAULT_ATOL_POSITION_PER_CLEARANCE)
                .reduce(f64::min)
                .unwrap_or(1e-6)
        });
        Tolerances {
            position,
            angle: self.solver.atol_angle.unwrap_or(position / REFERENCE_ARM),
            velocity: self.solver.atol_velocity,
        }
    }

    /// The same mechanism with every clearance joint made ideal: the reference of the studies.
    pub fn idealized(&self) -> Scene {
        let mut s = self.clone();
        s.clearance_joints.iter_mut().for_each(|c| c.ideal = true);
        s
    }

    /// Serialize back to TOML (angles in degrees), e.g. to record the scene next to outputs.
    pub fn to_toml(&self) -> String {
        // Every field is a plain number, string, array or table, which TOML can always express.
        toml::to_string_pretty(self).unwrap_or_else(|e| format!("# cannot serialize: {e}\n"))
    }
}
