//! A [`ValidScene`] → a [`multibody::System`] with gravity, ideal joints, drivers and one
//! [`ClearanceForce`] per active clearance joint.
//!
//! Clearance joints flagged `ideal` become ideal revolutes. An active joint is round
//! ([`RoundClearanceForce`](clearance::RoundClearanceForce), no wear code at all) unless the caller hands it a [`WornJoint`];
//! then it samples that joint's surfaces, frozen for the run, and optionally accumulates a
//! stage's wear. Errors name the scene field at fault.

use contact::{ContactError, ContactModel, FrictionLawKind, JointSurface, NormalLawKind};
use multibody::{
    Anchor, Body, BodyId, DriveFunction, DriveTarget, ElementId, Gravity, JointId, Model,
    ModelError, RotationLock, System,
};
use wear::{WearError, WearParams, WornJoint};

use clearance::{ClearanceForce, ClearanceProbe};
use scene::{BodyRef, ClearanceJointSpec, DriverTarget, Scene, TimeLaw, ValidScene};

/// Why a scene could not be turned into a system; `field` is the scene path at fault.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// `multibody` rejected a body, joint or driver.
    #[error("{field}: {source}")]
    Model {
        /// Scene field, e.g. `bodies[2]`.
        field: String,
        /// Cause.
        source: ModelError,
    },
    /// `contact` rejected a clearance joint's material, law or geometry.
    #[error("{field}: {source}")]
    Contact {
        /// Scene field, e.g. `clearance_joints[0].normal_law`.
        field: String,
        /// Cause.
        source: ContactError,
    },
    /// `wear` rejected a clearance joint's wear settings or surfaces.
    #[error("{field}: {source}")]
    Wear {
        /// Scene field, e.g. `clearance_joints[1].wear`.
        field: String,
        /// Cause.
        source: WearError,
    },
    /// A body or joint name does not resolve (validation refuses such a scene first).
    #[error("{field}: no body or joint named {name:?}")]
    Unresolved {
        /// Scene field.
        field: String,
        /// The name.
        name: String,
    },
    /// The worn surfaces given do not match the scene's active clearance joints.
    #[error("{given} worn-surface slots given for {expected} active clearance joints")]
    SurfaceCount {
        /// Active clearance joints in the scene.
        expected: usize,
        /// Slots given.
        given: usize,
    },
}

/// One active clearance joint of a built system.
#[derive(Debug, Clone)]
pub struct JointHandle {
    /// Joint name from the scene.
    pub name: String,
    /// Index into [`Scene::clearance_joints`].
    pub scene_index: usize,
    /// The force element in the system.
    pub element: ElementId,
    /// Whether it samples worn surfaces ([`WornClearanceForce`](clearance::WornClearanceForce)) or round ones.
    pub worn: bool,
    /// Nominal radial clearance `c0`, m.
    pub clearance: f64,
    /// Its contact model: what the run's validity checks and reports ask about it.
    pub model: contact::ContactModelKind,
}

impl JointHandle {
    /// Whether the model's validity needs the true outline overlap, measured apart from it.
    pub fn measures_outline_overlap(&self) -> bool {
        self.model
            .validity_measures()
            .iter()
            .any(|m| m.needs_outline_overlap())
    }

    /// The element among `elements` (a system's, or an observer frame's) as a probe.
    pub fn probe<'a>(
        &self,
        elements: &'a [Box<dyn multibody::ForceElement>],
    ) -> Option<&'a dyn ClearanceProbe> {
        clearance::as_probe(elements.get(self.element.0)?.as_ref())
    }
}

/// A system built from a scene, with the handles of its clearance joints.
#[derive(Debug)]
pub struct BuiltScene {
    /// The mechanism; elements: gravity first, then the clearance joints.
    pub system: System,
    /// Active clearance joints in scene order.
    pub joints: Vec<JointHandle>,
}

/// Worn surfaces of the active clearance joints and whether to accumulate a stage's wear.
#[derive(Debug, Clone, Copy, Default)]
pub struct Surfaces<'a> {
    /// One slot per active clearance joint (scene order), or empty for all round; `None` in a
    /// slot: that joint stays round.
    pub worn: &'a [Option<WornJoint>],
    /// Accumulate the stage's wear on worn joints for accepted steps starting at or after this
    /// time (s); `None`: no accumulation.
    pub accumulate_from: Option<f64>,
    /// Also keep the wear of the steps starting before this time apart (the first half of
    /// the stage's cycles), for the convergence check of a stage.
    pub split_halves_at: Option<f64>,
}

/// The unworn [`WornJoint`] of every active clearance joint (scene order); `None` where the
/// scene has no wear or `K_d = 0`, so those joints allocate nothing.
pub fn unworn_joints(scene: &Scene) -> Result<Vec<Option<WornJoint>>, BuildError> {
    scene
        .clearance_joints
        .iter()
        .enumerate()
        .filter(|(_, c)| !c.ideal)
        .map(|(k, c)| {
            let Some(w) = c.wear else { return Ok(None) };
            let field = format!("clearance_joints[{k}].wear");
            let wrap = |source| BuildError::Wear {
                field: field.clone(),
                source,
            };
            let params = WearParams::new(w.k_d, w.width, w.cells).map_err(wrap)?;
            let joint =
                WornJoint::if_wearing(&params, c.bearing_radius, c.pin_radius()).map_err(wrap)?;
            Ok(joint.map(|j| j.with_sliding(c.sliding.wear)))
        })
        .collect()
}

/// The scene's time law as a drive function (its own exact derivatives).
struct SceneLaw(TimeLaw);

impl DriveFunction for SceneLaw {
    fn value(&self, t: f64) -> f64 {
        self.0.eval(t)[0]
    }
    fn velocity(&self, t: f64) -> f64 {
        self.0.eval(t)[1]
    }
    fn acceleration(&self, t: f64) -> f64 {
        self.0.eval(t)[2]
    }
}

fn model_err(field: impl Into<String>) -> impl FnOnce(ModelError) -> BuildError {
    let field = field.into();
    move |source| BuildError::Model { field, source }
}

/// Builds the system of `scene` with the given surfaces.
pub fn build(scene: &ValidScene, surfaces: Surfaces<'_>) -> Result<BuiltScene, BuildError> {
    let scene: &Scene = scene;
    let active = scene.active_clearance_joints().count();
    if !surfaces.worn.is_empty() && surfaces.worn.len() != active {
        return Err(BuildError::SurfaceCount {
            expected: active,
            given: surfaces.worn.len(),
        });
    }
    let mut model = Model::new();
    for (k, b) in scene.bodies.iter().enumerate() {
        let body = Body::new(&b.name, b.mass, b.inertia, [b.x, b.y, b.theta.rad()])
            .with_velocity([b.velocity[0], b.velocity[1], b.omega]);
        model
            .add_body(body)
            .map_err(model_err(format!("bodies[{k}]")))?;
    }
    let anchor = |field: &str, name: &str, point: [f64; 2]| -> Result<Anchor, BuildError> {
        match scene.resolve(name) {
            Some(BodyRef::Ground) => Ok(Anchor::ground(point[0], point[1])),
            Some(BodyRef::Body(k)) => Ok(Anchor::on(BodyId(k), point[0], point[1])),
            None => Err(BuildError::Unresolved {
                field: field.to_string(),
                name: name.to_string(),
            }),
        }
    };
    let mut revolute_ids: Vec<(&str, JointId)> = Vec::new();
    for (k, j) in scene.revolute_joints.iter().enumerate() {
        let p = format!("revolute_joints[{k}]");
        let i = anchor(&format!("{p}.body"), &j.body, j.point)?;
        let o = anchor(&format!("{p}.other"), &j.other, j.other_point)?;
        let id = model.add_revolute(&j.name, i, o).map_err(model_err(p))?;
        revolute_ids.push((&j.name, id));
    }
    for (k, c) in scene
        .clearance_joints
        .iter()
        .enumerate()
        .filter(|(_, c)| c.ideal)
    {
        let p = format!("clearance_joints[{k}]");
        let i = anchor(
            &format!("{p}.bearing_body"),
            &c.bearing_body,
            c.bearing_point,
        )?;
        let o = anchor(&format!("{p}.pin_body"), &c.pin_body, c.pin_point)?;
        model.add_revolute(&c.name, i, o).map_err(model_err(p))?;
    }
    for (k, j) in scene.prismatic_joints.iter().enumerate() {
        let p = format!("prismatic_joints[{k}]");
        let base = anchor(&format!("{p}.other"), &j.other, j.other_point)?;
        let slider = anchor(&format!("{p}.body"), &j.body, j.point)?;
        let angle = |name: &str| match scene.resolve(name) {
            Some(BodyRef::Body(b)) => scene.bodies[b].theta.rad(),
            _ => 0.0,
        };
        let rotation = if j.lock_rotation {
            RotationLock::At(angle(&j.body) - angle(&j.other))
        } else {
            RotationLock::Free
        };
        model
            .add_prismatic(&j.name, base, j.direction, slider, rotation)
            .map_err(model_err(p))?;
    }
    for (k, d) in scene.drivers.iter().enumerate() {
        let p = format!("drivers[{k}]");
        let target = match &d.target {
            DriverTarget::BodyCoordinate { body, coordinate } => {
                let Some(BodyRef::Body(b)) = scene.resolve(body) else {
                    return Err(BuildError::Unresolved {
                        field: format!("{p}.target.body"),
                        name: body.clone(),
                    });
                };
                DriveTarget::Coordinate(BodyId(b), *coordinate)
            }
            DriverTarget::JointAngle { joint } => {
                let Some((_, id)) = revolute_ids.iter().find(|(n, _)| n == joint) else {
                    return Err(BuildError::Unresolved {
                        field: format!("{p}.target.joint"),
                        name: joint.clone(),
                    });
                };
                DriveTarget::JointAngle(*id)
            }
        };
        model
            .add_driver(&d.name, target, Box::new(SceneLaw(d.law.clone())))
            .map_err(model_err(p))?;
    }
    let gravity = Gravity::new(&model, scene.gravity);
    let mut system = System::new(model).map_err(model_err("bodies"))?;
    system.add_element(Box::new(gravity));

    let mut joints = Vec::with_capacity(active);
    let actives = scene
        .clearance_joints
        .iter()
        .enumerate()
        .filter(|(_, c)| !c.ideal);
    for (slot, (k, c)) in actives.enumerate() {
        let p = format!("clearance_joints[{k}]");
        let bearing = body_id(scene, &format!("{p}.bearing_body"), &c.bearing_body)?;
        let pin = body_id(scene, &format!("{p}.pin_body"), &c.pin_body)?;
        let round = round_joint(c, &p)?;
        let model = round.model();
        let worn = surfaces.worn.get(slot).and_then(Option::as_ref);
        let element = match worn {
            None => system.add_element(Box::new(ClearanceForce::new(&c.name, bearing, pin, round))),
            Some(w) => {
                let joint = round
                    .with_profiles(w.bearing().clone(), w.pin().clone())
                    .map_err(|source| BuildError::Contact {
                        field: format!("{p} (worn surfaces)"),
                        source,
                    })?;
                let mut force = ClearanceForce::new(&c.name, bearing, pin, joint);
                if let Some(t0) = surfaces.accumulate_from {
                    // The contact zones only where the stepping reads them.
                    let zones = scene.run.wear_stepping == wear::WearStepping::LinearlyImplicit;
                    force = force.with_stage_wear(w.start_stage().gathering_zones(zones), t0);
                    if let Some(split) = surfaces.split_halves_at {
                        force = force.with_halves(w.start_stage(), split);
                    }
                }
                system.add_element(Box::new(force))
            }
        };
        joints.push(JointHandle {
            name: c.name.clone(),
            scene_index: k,
            element,
            worn: worn.is_some(),
            clearance: c.clearance,
            model,
        });
    }
    Ok(BuiltScene { system, joints })
}

fn body_id(scene: &Scene, field: &str, name: &str) -> Result<Option<BodyId>, BuildError> {
    match scene.resolve(name) {
        Some(BodyRef::Ground) => Ok(None),
        Some(BodyRef::Body(k)) => Ok(Some(BodyId(k))),
        None => Err(BuildError::Unresolved {
            field: field.to_string(),
            name: name.to_string(),
        }),
    }
}

/// The contact joint of a scene's clearance joint with round surfaces.
fn round_joint(
    c: &ClearanceJointSpec,
    p: &str,
) -> Result<contact::ClearanceJoint<contact::CircularProfile, contact::CircularProfile>, BuildError>
{
    let err = |field: &str| {
        let field = format!("{p}.{field}");
        move |source| BuildError::Contact { field, source }
    };
    let material =
        |m: contact::MaterialParams, f: &str| contact::Material::try_from(m).map_err(err(f));
    let normal = NormalLawKind::from_params(c.normal_law).map_err(err("normal_law"))?;
    let friction = FrictionLawKind::from_params(c.friction).map_err(err("friction"))?;
    contact::ClearanceJoint::new(
        JointSurface {
            centre: c.bearing_point,
            profile: contact::CircularProfile::new(c.bearing_radius),
            material: material(c.bearing_material, "bearing_material")?,
        },
        JointSurface {
            centre: c.pin_point,
            profile: contact::CircularProfile::new(c.pin_radius()),
            material: material(c.pin_material, "pin_material")?,
        },
        normal,
        friction,
    )
    .map_err(err("clearance"))
    .and_then(|joint| {
        let model = c.contact_model().map_err(err("contact"))?;
        Ok(joint
            .with_friction_sliding(c.sliding.friction)
            .with_model(model))
    })
}
