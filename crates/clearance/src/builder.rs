//! A clearance joint assembled from named parts instead of nested constructors.

use contact::{
    CircularProfile, ClearanceJoint, ContactError, ContactModelKind, FrictionLawKind, JointSurface,
    Material, NormalLawKind, SlidingVelocity,
};
use multibody::BodyId;
use wear::{WearError, WearParams, WornJoint};

use crate::{RoundClearanceForce, WornClearanceForce};

/// Why a clearance joint could not be built.
#[derive(Debug, thiserror::Error)]
pub enum ClearanceError {
    /// `contact` rejected the geometry, a material or a law.
    #[error("clearance joint {joint:?}: {source}")]
    Contact {
        /// The joint's name.
        joint: String,
        /// Cause.
        source: ContactError,
    },
    /// `wear` rejected the wear parameters or the surfaces.
    #[error("clearance joint {joint:?}: {source}")]
    Wear {
        /// The joint's name.
        joint: String,
        /// Cause.
        source: WearError,
    },
}

/// One side of a clearance joint: the body carrying it (`None`: ground), the centre of the
/// hole or pin in that body's frame relative to its centroid (m), the nominal radius (m) and
/// the material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointSide {
    /// Carrying body; `None` is ground.
    pub body: Option<BodyId>,
    /// Centre in the body frame, relative to the centroid (m).
    pub centre: [f64; 2],
    /// Nominal radius (m).
    pub radius: f64,
    /// Material.
    pub material: Material,
}

impl JointSide {
    /// A side carried by `body`.
    pub fn on(body: BodyId, centre: [f64; 2], radius: f64, material: Material) -> Self {
        Self {
            body: Some(body),
            centre,
            radius,
            material,
        }
    }

    /// A side fixed to ground at `centre` (global frame).
    pub fn ground(centre: [f64; 2], radius: f64, material: Material) -> Self {
        Self {
            body: None,
            centre,
            radius,
            material,
        }
    }

    fn surface<S>(&self, profile: S) -> JointSurface<S> {
        JointSurface {
            centre: self.centre,
            profile,
            material: self.material,
        }
    }
}

/// Builds a [`RoundClearanceForce`] or a [`WornClearanceForce`] from a bearing side, a pin
/// side and the contact laws; friction is off and both velocities are the material sliding
/// unless set.
///
/// ```
/// use clearance::{ClearanceJointBuilder, JointSide};
/// use contact::{Ambrosio, LankaraniNikravesh, Material};
/// use multibody::BodyId;
///
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let steel = Material::new(207e9, 0.3)?;
/// let joint = ClearanceJointBuilder::new(
///     "B",
///     JointSide::on(BodyId(1), [0.175, 0.0], 0.010, steel),
///     JointSide::on(BodyId(2), [0.0, 0.0], 0.0095, steel),
///     LankaraniNikravesh::new(0.9)?,
/// )
/// .friction(Ambrosio::new(0.1, 1e-4, 1e-3)?);
/// let round = joint.clone().round()?;
/// let worn = joint.wearing(&wear::WearParams::new(1e-8, 0.02, 1000)?)?;
/// assert_eq!(round.bodies(), [Some(BodyId(1)), Some(BodyId(2))]);
/// assert_eq!(worn.stage_wear().map(|w| w.max_depth()), Some(0.0));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct ClearanceJointBuilder {
    name: String,
    bearing: JointSide,
    pin: JointSide,
    normal_law: NormalLawKind,
    friction_law: FrictionLawKind,
    friction_sliding: SlidingVelocity,
    wear_sliding: SlidingVelocity,
    /// `None`: the joint's default ([`contact::joint::default_model`]).
    model: Option<ContactModelKind>,
}

impl ClearanceJointBuilder {
    /// A joint named `name` (it names the element and the errors) between a bearing and a pin
    /// with the normal law `normal_law`.
    pub fn new(
        name: impl Into<String>,
        bearing: JointSide,
        pin: JointSide,
        normal_law: impl Into<NormalLawKind>,
    ) -> Self {
        Self {
            name: name.into(),
            bearing,
            pin,
            normal_law: normal_law.into(),
            friction_law: FrictionLawKind::None,
            friction_sliding: SlidingVelocity::Material,
            wear_sliding: SlidingVelocity::Material,
            model: None,
        }
    }

    /// Sets the contact model (default: the elastic foundation on 1000 nodes, calibrated as a
    /// scene's default, [`contact::joint::default_model`]). A worn joint on the foundation
    /// model should give it as many nodes as its wear grid has cells, so each node is a pin
    /// cell.
    pub fn contact_model(mut self, model: impl Into<ContactModelKind>) -> Self {
        self.model = Some(model.into());
        self
    }

    /// Sets the friction law (default: none).
    pub fn friction(mut self, law: impl Into<FrictionLawKind>) -> Self {
        self.friction_law = law.into();
        self
    }

    /// Which sliding velocity drives friction and which drives wear (default: the material
    /// one for both; [`SlidingVelocity::Paper`] is the paper's `δ φ̇`).
    pub fn sliding(mut self, friction: SlidingVelocity, wear: SlidingVelocity) -> Self {
        self.friction_sliding = friction;
        self.wear_sliding = wear;
        self
    }

    /// A joint between round surfaces: no wear code involved.
    pub fn round(self) -> Result<RoundClearanceForce, ClearanceError> {
        let joint = self.contact_joint(
            CircularProfile::new(self.bearing.radius),
            CircularProfile::new(self.pin.radius),
        )?;
        Ok(self.element(joint))
    }

    /// A joint on the frozen surfaces of `surfaces` (for example a previous stage's), with no
    /// wear accumulation; add it with [`WornClearanceForce::with_stage_wear`].
    pub fn on_surfaces(self, surfaces: &WornJoint) -> Result<WornClearanceForce, ClearanceError> {
        let joint = self.contact_joint(surfaces.bearing().clone(), surfaces.pin().clone())?;
        Ok(self.element(joint))
    }

    /// A joint on new unworn surfaces of `params.cells` cells that accumulates wear on every
    /// accepted step from t = 0 (read it with [`WornClearanceForce::stage_wear`]).
    ///
    /// Wear is deposited at the two ends of each accepted step. Where contact rests and
    /// slides steadily, BDF takes long steps: bound `SimulationOptions::max_step` so that a
    /// step does not turn the contact point across many cells.
    pub fn wearing(self, params: &WearParams) -> Result<WornClearanceForce, ClearanceError> {
        let surfaces = self.unworn_surfaces(params)?;
        Ok(self
            .on_surfaces(&surfaces)?
            .with_stage_wear(surfaces.start_stage(), 0.0))
    }

    /// The unworn [`WornJoint`] of this joint's radii, wearing by `params` with this builder's
    /// wear sliding velocity: the surfaces a wear-stage run starts from.
    pub fn unworn_surfaces(&self, params: &WearParams) -> Result<WornJoint, ClearanceError> {
        WornJoint::new(params, self.bearing.radius, self.pin.radius)
            .map(|joint| joint.with_sliding(self.wear_sliding))
            .map_err(|source| ClearanceError::Wear {
                joint: self.name.clone(),
                source,
            })
    }

    fn contact_joint<B, P>(
        &self,
        bearing: B,
        pin: P,
    ) -> Result<ClearanceJoint<B, P>, ClearanceError>
    where
        B: contact::SurfaceProfile,
        P: contact::SurfaceProfile,
    {
        ClearanceJoint::new(
            self.bearing.surface(bearing),
            self.pin.surface(pin),
            self.normal_law,
            self.friction_law,
        )
        .map(|joint| {
            let joint = joint.with_friction_sliding(self.friction_sliding);
            match self.model {
                Some(model) => joint.with_model(model),
                None => joint,
            }
        })
        .map_err(|source| ClearanceError::Contact {
            joint: self.name.clone(),
            source,
        })
    }

    fn element<B, P>(&self, joint: ClearanceJoint<B, P>) -> crate::ClearanceForce<B, P>
    where
        B: contact::SurfaceProfile,
        P: contact::SurfaceProfile,
    {
        crate::ClearanceForce::new(self.name.clone(), self.bearing.body, self.pin.body, joint)
    }
}
