//! A scene that has passed [`Scene::validate`], as a type: what the run takes, so it never
//! checks a scene again and cannot be handed one edited after its check.

use std::ops::Deref;

use serde::Serialize;

use super::{Scene, SceneError};

/// A scene every value of which has been checked ([`Scene::validate`]): names resolve, numbers
/// are finite, parameters physically meaningful. It reads as a [`Scene`] (`Deref`) but cannot be
/// changed in place: [`ValidScene::edit`] changes a copy and checks it again, so a value of this
/// type is always one that passed, and the run (`sim::run_scene`) relies on it without checking.
///
/// ```
/// use scene::{Builtin, ValidScene, builtin};
///
/// let text = r#"
/// description = "one body"
/// inertia_convention = "centroidal"
/// gravity = [0.0, -9.81]
/// [[bodies]]
/// name = "b"
/// mass = 1.0
/// inertia = 1.0
/// x = 0.0
/// y = 0.0
/// theta_deg = 0.0
/// [run]
/// period = 1.0
/// "#;
/// let shipped = [Builtin { name: "b", summary: "", source: text }];
/// let scene: ValidScene = builtin(&shipped, "b")?;
/// assert_eq!(scene.bodies[0].mass, 1.0);
/// let heavier = scene.clone().edit("b, heavier", |s| s.bodies[0].mass = 2.0)?;
/// assert_eq!(heavier.bodies[0].mass, 2.0);
/// assert!(scene.edit("b, massless", |s| s.bodies[0].mass = 0.0).is_err());
/// # Ok::<(), scene::SceneError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(transparent)]
pub struct ValidScene(Scene);

impl ValidScene {
    /// `scene` once [`Scene::validate`] passes; `origin` names it in the error.
    pub fn new(scene: Scene, origin: &str) -> Result<Self, SceneError> {
        scene.validate(origin)?;
        Ok(Self(scene))
    }

    /// This scene changed by `change`, checked again; `origin` names the changed scene in the
    /// error (e.g. "lgres with command-line overrides").
    pub fn edit(self, origin: &str, change: impl FnOnce(&mut Scene)) -> Result<Self, SceneError> {
        let mut scene = self.0;
        change(&mut scene);
        Self::new(scene, origin)
    }

    /// The same mechanism with every clearance joint ideal ([`Scene::idealized`]). Valid without
    /// a second check: an ideal joint is held to a subset of an active one's checks, and fewer
    /// active joints only widen the tolerance limits.
    pub fn idealized(&self) -> Self {
        Self(self.0.idealized())
    }

    /// The scene, to change freely; it must pass [`ValidScene::new`] again to be run.
    pub fn into_scene(self) -> Scene {
        self.0
    }
}

impl Deref for ValidScene {
    type Target = Scene;

    fn deref(&self) -> &Scene {
        &self.0
    }
}

impl AsRef<Scene> for ValidScene {
    fn as_ref(&self) -> &Scene {
        &self.0
    }
}
