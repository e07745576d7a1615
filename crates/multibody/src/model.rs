//! The mechanism as data: bodies, ideal joints and driving constraints.
//!
//! Every `add_*` method validates its input at once and names the culprit in the error, so a
//! model that was built without error can always be compiled into a [`crate::System`].

use crate::drive::DriveFunction;
use crate::error::ModelError;

/// Index of a moving body; its coordinates are `q[3k..3k+3] = (x, y, θ)` of the centroid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BodyId(pub usize);

impl BodyId {
    /// Index into `q` of coordinate `coordinate` of this body.
    pub fn coordinate(self, coordinate: Coordinate) -> usize {
        3 * self.0 + coordinate as usize
    }
}

/// Index of a joint in the order joints were added.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct JointId(pub usize);

/// Index of a driving constraint in the order drivers were added.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct DriverId(pub usize);

/// One of a body's three coordinates; `x`, `y`, `theta` in scene files.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Coordinate {
    /// Global x of the centroid (m).
    X = 0,
    /// Global y of the centroid (m).
    Y = 1,
    /// Angle of the body frame from the global x axis, counter-clockwise (rad).
    Theta = 2,
}

/// A rigid body with its centroidal mass properties and an (approximate) initial state.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// Name used in error messages and reports.
    pub name: String,
    /// Mass (kg).
    pub mass: f64,
    /// Moment of inertia about the centroid, normal to the plane (kg m²).
    pub inertia: f64,
    /// Initial guess `(x, y, θ)` (m, m, rad); assembly corrects it onto the constraints.
    pub pose: [f64; 3],
    /// Initial guess `(ẋ, ẏ, θ̇)` (m/s, m/s, rad/s); assembly projects it onto the velocity
    /// constraints.
    pub velocity: [f64; 3],
}

impl Body {
    /// A body named `name`, at rest at the origin, whose mass and inertia are still to be given
    /// with [`Body::with_mass`] and [`Body::with_inertia`] ([`Model::add_body`] rejects a body
    /// without them): `Body::named("rod").with_mass(2.0).with_inertia(0.17).with_pose([x, y, θ])`
    /// reads without a reference to the argument order.
    pub fn named(name: impl Into<String>) -> Self {
        Self::new(name, f64::NAN, f64::NAN, [0.0; 3])
    }

    /// The same body with mass `mass` (kg).
    pub fn with_mass(mut self, mass: f64) -> Self {
        self.mass = mass;
        self
    }

    /// The same body with centroidal moment of inertia `inertia` (kg m²).
    pub fn with_inertia(mut self, inertia: f64) -> Self {
        self.inertia = inertia;
        self
    }

    /// The same body with initial pose guess `(x, y, θ)` (m, m, rad).
    pub fn with_pose(mut self, pose: [f64; 3]) -> Self {
        self.pose = pose;
        self
    }

    /// A body at rest at `pose`, from its mass (kg) and centroidal inertia (kg m²).
    pub fn new(name: impl Into<String>, mass: f64, inertia: f64, pose: [f64; 3]) -> Self {
        Self {
            name: name.into(),
            mass,
            inertia,
            pose,
            velocity: [0.0; 3],
        }
    }

    /// The same body with an initial velocity guess `(ẋ, ẏ, θ̇)` (m/s, m/s, rad/s).
    pub fn with_velocity(mut self, velocity: [f64; 3]) -> Self {
        self.velocity = velocity;
        self
    }
}

/// A point fixed to a body (in its centroidal frame) or to the ground (in the global frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Anchor {
    /// The carrying body; `None` is ground, as everywhere a body-or-ground is asked for.
    pub body: Option<BodyId>,
    /// Position in the body's centroidal frame, or global for ground (m).
    pub point: [f64; 2],
}

impl Anchor {
    /// A point fixed in the global frame.
    pub fn ground(x: f64, y: f64) -> Self {
        Self {
            body: None,
            point: [x, y],
        }
    }

    /// A point at `(s_x, s_y)` in the centroidal frame of `body`.
    pub fn on(body: BodyId, s_x: f64, s_y: f64) -> Self {
        Self {
            body: Some(body),
            point: [s_x, s_y],
        }
    }
}

/// Whether a prismatic joint also locks the relative rotation of slider and base.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RotationLock {
    /// The slider may turn (a pin in a slot): one equation.
    Free,
    /// `θ_slider − θ_base` is held at the given angle (a true slider): two equations.
    At(f64),
}

/// An ideal joint.
#[derive(Debug, Clone, PartialEq)]
pub enum Joint {
    /// The two anchors coincide.
    Revolute {
        /// Name used in error messages, reports and constraint labels.
        name: String,
        /// Anchor on the first body.
        i: Anchor,
        /// Anchor on the second body.
        j: Anchor,
    },
    /// Anchor `slider` stays on the line through `base` along `axis` (given in the base's
    /// frame, or globally for ground).
    Prismatic {
        /// Name used in error messages, reports and constraint labels.
        name: String,
        /// A point on the sliding line.
        base: Anchor,
        /// Unit direction of the line ([`Model::add_prismatic`] normalizes it).
        axis: [f64; 2],
        /// The point that slides along the line.
        slider: Anchor,
        /// Whether the relative rotation is locked too.
        rotation: RotationLock,
    },
}

impl Joint {
    /// The joint's name.
    pub fn name(&self) -> &str {
        match self {
            Joint::Revolute { name, .. } | Joint::Prismatic { name, .. } => name,
        }
    }

    pub(crate) fn kind(&self) -> &'static str {
        match self {
            Joint::Revolute { .. } => "revolute",
            Joint::Prismatic { .. } => "prismatic",
        }
    }
}

/// What a driving constraint prescribes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DriveTarget {
    /// One coordinate of a body: `q_k = f(t)`.
    Coordinate(BodyId, Coordinate),
    /// The relative angle of a revolute joint: `θ_j − θ_i = f(t)` (ground angle 0).
    JointAngle(JointId),
    /// The slide of a prismatic joint: `u·(P_slider − P_base) = f(t)`, `u` the unit axis.
    JointSlide(JointId),
}

/// A driving constraint.
pub struct Driver {
    /// Name used in error messages, reports and constraint labels.
    pub name: String,
    /// The coordinate or joint variable prescribed.
    pub target: DriveTarget,
    /// Its prescribed value as a function of time, with exact derivatives.
    pub function: Box<dyn DriveFunction>,
}

impl std::fmt::Debug for Driver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Driver")
            .field("name", &self.name)
            .field("target", &self.target)
            .finish_non_exhaustive()
    }
}

/// A planar mechanism under construction.
#[derive(Debug, Default)]
pub struct Model {
    pub(crate) bodies: Vec<Body>,
    pub(crate) joints: Vec<Joint>,
    pub(crate) drivers: Vec<Driver>,
}

fn finite2(p: [f64; 2]) -> bool {
    p.iter().all(|v| v.is_finite())
}

impl Model {
    /// An empty model.
    pub fn new() -> Self {
        Self::default()
    }

    /// The bodies, in the order of their [`BodyId`]s.
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// The ideal joints, in the order of their [`JointId`]s.
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }

    /// The drivers, in the order of their [`DriverId`]s.
    pub fn drivers(&self) -> &[Driver] {
        &self.drivers
    }

    /// Number of coordinates, `3 × bodies`.
    pub fn coordinate_count(&self) -> usize {
        3 * self.bodies.len()
    }

    /// Adds a body after checking its mass, inertia and initial state.
    pub fn add_body(&mut self, body: Body) -> Result<BodyId, ModelError> {
        if !(body.mass.is_finite() && body.mass > 0.0) {
            return Err(ModelError::InvalidMass {
                body: body.name,
                value: body.mass,
            });
        }
        if !(body.inertia.is_finite() && body.inertia > 0.0) {
            return Err(ModelError::InvalidInertia {
                body: body.name,
                value: body.inertia,
            });
        }
        if !body
            .pose
            .iter()
            .chain(&body.velocity)
            .all(|v| v.is_finite())
        {
            return Err(ModelError::NonFiniteBodyState { body: body.name });
        }
        self.bodies.push(body);
        Ok(BodyId(self.bodies.len() - 1))
    }

    /// Checks the two anchors of `joint` in order (a body that exists, a finite point; `what`
    /// names the anchor in the error), then that they are on different bodies.
    fn check_ends(
        &self,
        joint: &str,
        ends: [(&Anchor, &'static str); 2],
    ) -> Result<(), ModelError> {
        for (anchor, what) in ends {
            if let Some(BodyId(index)) = anchor.body
                && index >= self.bodies.len()
            {
                return Err(ModelError::MissingBody {
                    owner: "joint",
                    name: joint.to_string(),
                    index,
                    count: self.bodies.len(),
                });
            }
            if !finite2(anchor.point) {
                return Err(ModelError::NonFiniteJointGeometry {
                    joint: joint.to_string(),
                    what,
                    x: anchor.point[0],
                    y: anchor.point[1],
                });
            }
        }
        check_distinct(joint, ends[0].0.body, ends[1].0.body)
    }

    /// Adds a revolute joint making the anchors `i` and `j` coincide.
    pub fn add_revolute(
        &mut self,
        name: impl Into<String>,
        i: Anchor,
        j: Anchor,
    ) -> Result<JointId, ModelError> {
        let name = name.into();
        self.check_ends(&name, [(&i, "anchor i"), (&j, "anchor j")])?;
        self.joints.push(Joint::Revolute { name, i, j });
        Ok(JointId(self.joints.len() - 1))
    }

    /// Adds a prismatic joint: `slider` stays on the line through `base` along `axis`.
    pub fn add_prismatic(
        &mut self,
        name: impl Into<String>,
        base: Anchor,
        axis: [f64; 2],
        slider: Anchor,
        rotation: RotationLock,
    ) -> Result<JointId, ModelError> {
        let name = name.into();
        self.check_ends(&name, [(&base, "base anchor"), (&slider, "slider anchor")])?;
        if !finite2(axis) {
            return Err(ModelError::NonFiniteJointGeometry {
                joint: name,
                what: "axis",
                x: axis[0],
                y: axis[1],
            });
        }
        let length = axis[0].hypot(axis[1]);
        if length <= 0.0 {
            return Err(ModelError::ZeroAxis {
                joint: name,
                x: axis[0],
                y: axis[1],
            });
        }
        if let RotationLock::At(angle) = rotation
            && !angle.is_finite()
        {
            return Err(ModelError::NonFiniteJointGeometry {
                joint: name,
                what: "locked angle",
                x: angle,
                y: 0.0,
            });
        }
        self.joints.push(Joint::Prismatic {
            name,
            base,
            axis: [axis[0] / length, axis[1] / length],
            slider,
            rotation,
        });
        Ok(JointId(self.joints.len() - 1))
    }

    /// Adds a driving constraint `target = function(t)`.
    pub fn add_driver(
        &mut self,
        name: impl Into<String>,
        target: DriveTarget,
        function: Box<dyn DriveFunction>,
    ) -> Result<DriverId, ModelError> {
        let name = name.into();
        match target {
            DriveTarget::Coordinate(BodyId(index), _) => {
                if index >= self.bodies.len() {
                    return Err(ModelError::MissingBody {
                        owner: "driver",
                        name,
                        index,
                        count: self.bodies.len(),
                    });
                }
            }
            DriveTarget::JointAngle(JointId(index)) | DriveTarget::JointSlide(JointId(index)) => {
                let Some(joint) = self.joints.get(index) else {
                    return Err(ModelError::MissingJoint {
                        driver: name,
                        index,
                        count: self.joints.len(),
                    });
                };
                let fits = matches!(
                    (target, joint),
                    (DriveTarget::JointAngle(_), Joint::Revolute { .. })
                        | (DriveTarget::JointSlide(_), Joint::Prismatic { .. })
                );
                if !fits {
                    return Err(ModelError::WrongJointKind {
                        driver: name,
                        joint: joint.name().to_string(),
                        target: if matches!(target, DriveTarget::JointAngle(_)) {
                            "the angle"
                        } else {
                            "the slide"
                        },
                        kind: joint.kind(),
                    });
                }
            }
        }
        let start = [
            function.value(0.0),
            function.velocity(0.0),
            function.acceleration(0.0),
        ];
        if let Some(value) = start.into_iter().find(|v| !v.is_finite()) {
            return Err(ModelError::NonFiniteDrive {
                driver: name,
                value,
            });
        }
        self.drivers.push(Driver {
            name,
            target,
            function,
        });
        Ok(DriverId(self.drivers.len() - 1))
    }

    /// Initial guesses `(q, q̇)` read from the bodies.
    pub fn initial_guess(&self) -> (Vec<f64>, Vec<f64>) {
        let q = self.bodies.iter().flat_map(|b| b.pose).collect();
        let qd = self.bodies.iter().flat_map(|b| b.velocity).collect();
        (q, qd)
    }
}

fn check_distinct(joint: &str, a: Option<BodyId>, b: Option<BodyId>) -> Result<(), ModelError> {
    let what = match (a, b) {
        (None, None) => "ground to ground",
        (Some(x), Some(y)) if x == y => "a body to itself",
        _ => return Ok(()),
    };
    Err(ModelError::DegenerateJoint {
        joint: joint.to_string(),
        what,
    })
}
