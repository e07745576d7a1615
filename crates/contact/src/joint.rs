//! The clearance revolute joint: a bearing on one body, a pin on another, and the contact
//! model between them.
//!
//! # Layout
//! [`ClearanceJoint`] is a [`ContactPair`] (module `pair`: the outlines on their bodies, their
//! materials and laws) and a [`ContactModelKind`] (module `kind`), and hands every evaluation
//! to the model. What a model is, the [`ContactModel`] trait, is in `model`; each model is a
//! module implementing it: [`line_of_centres`] (one contact point, Hertz law on the local
//! radii; with its worn-surface kernel `general`), [`foundation`] (an elastic layer over the
//! true outlines: `layer`, `evaluate`, `geometry`, `nodes`, `stream`, `books`) and
//! [`linear_spring`] (the test model of the interface). Below them: `types` (the values an
//! evaluation takes and gives: [`BodyState`], [`JointSurface`], [`JointKinematics`],
//! [`ContactForces`]), `kinematics` (the line of centres at one state, on the pair) and `dual`
//! (the dual numbers of the foundation's Jacobian). Each imports only downwards: `types`,
//! `dual` → `pair` → `kinematics` → `model` → the models → `kind` → `workspace` → this
//! module. A model's state is its own ([`ContactModel::Tables`], kept by the joint;
//! [`ContactModel::Workspace`], kept by the caller in a [`ContactWorkspace`] and passed to each
//! evaluation). docs/architecture.md lists what adding a model takes.

use nalgebra::Vector2;

use crate::error::ContactError;
use crate::friction::{FrictionLaw, FrictionLawKind};
use crate::normal::{NormalLaw, NormalLawKind};
use crate::surface::SurfaceProfile;

mod dual;
pub mod foundation;
mod kind;
mod kinematics;
pub mod line_of_centres;
pub mod linear_spring;
mod model;
mod pair;
pub mod thin_gap;
mod types;
mod workspace;

pub use crate::material::{Material, MaterialParams};
pub use foundation::{
    DEFAULT_FOUNDATION_CELLS, DEFAULT_REFERENCE_OVERLAP, Foundation, FoundationWorkspace,
    NodeWindow, Quadrature,
};
pub use kind::{ContactModelKind, ModelTables, ModelWorkspace};
pub use line_of_centres::LineOfCentres;
pub use linear_spring::LinearSpring;
pub use model::{
    ContactKernel, ContactModel, ModelState, NodeLoad, ShapeLimits, ValidityMeasure, Visit,
};
pub use pair::ContactPair;
pub use thin_gap::{ThinGap, ThinGapTables, ThinGapWorkspace};
pub use types::{
    BodyState, ContactForces, ContactJacobian, JointKinematics, JointState, JointSurface,
    OutlineOverlap, SlidingVelocity,
};
pub use workspace::ContactWorkspace;
use workspace::TablesKey;

/// A clearance revolute joint between a bearing on body *i* and a pin on body *j*.
///
/// Generic over the surface profiles and the laws, so a fixed configuration is statically
/// dispatched; the defaults ([`NormalLawKind`], [`FrictionLawKind`]) dispatch at run time, as
/// the contact model ([`ContactModelKind`]) does.
///
/// It keeps its model's tables for its outlines; what the model's evaluations carry from one
/// to the next is the caller's, a [`ContactWorkspace`] from [`Self::workspace`] passed to the
/// `_in` evaluations. The others evaluate with an empty one: the same results, without what
/// earlier evaluations found.
#[derive(Clone, Debug)]
pub struct ClearanceJoint<B, P, N = NormalLawKind, F = FrictionLawKind> {
    pair: ContactPair<B, P, N, F>,
    /// The elastic foundation (default, as in scenes), the line of centres or another model.
    model: ContactModelKind,
    /// The model's tables for the pair's outlines.
    tables: ModelTables,
    /// Names these tables, so that a workspace filled against other ones is not used with them.
    tables_key: TablesKey,
}

/// Equal joints: the same pair and model (the tables follow from them).
impl<B: PartialEq, P: PartialEq, N: PartialEq, F: PartialEq> PartialEq
    for ClearanceJoint<B, P, N, F>
{
    fn eq(&self, other: &Self) -> bool {
        self.pair == other.pair && self.model == other.model
    }
}

impl<B: SurfaceProfile, P: SurfaceProfile, N: NormalLaw, F: FrictionLaw>
    ClearanceJoint<B, P, N, F>
{
    /// A joint on the elastic foundation, the scenes' default model ([`default_model`]),
    /// validated: finite centres, and profiles that are finite, positive and leave a positive
    /// clearance in every direction (checked on 64 angles per surface: the smallest bearing
    /// radius must exceed the largest pin radius). [`Self::with_model`] chooses another model.
    pub fn new(
        bearing: JointSurface<B>,
        pin: JointSurface<P>,
        normal_law: N,
        friction_law: F,
    ) -> Result<Self, ContactError> {
        let pair = ContactPair::new(bearing, pin, normal_law, friction_law)?;
        let model = default_model(&pair)?;
        Ok(Self::of(pair, model))
    }

    /// The joint of `pair` and `model`, with the model's tables for the pair.
    fn of(pair: ContactPair<B, P, N, F>, model: ContactModelKind) -> Self {
        Self {
            tables: model.tables(&pair),
            tables_key: TablesKey::new(),
            pair,
            model,
        }
    }

    /// The same joint with contact model `model` (default: [`default_model`]).
    pub fn with_model(self, model: impl Into<ContactModelKind>) -> Self {
        Self::of(self.pair, model.into())
    }

    /// A workspace for this joint's evaluations (the `_in` ones), ready so that they allocate
    /// nothing. One per caller that evaluates the joint again and again (an integrator's force
    /// element): the foundation remembers there which nodes were apart, to pass over them next
    /// time.
    pub fn workspace(&self) -> ContactWorkspace {
        ContactWorkspace::new(self.tables_key, self.model.workspace())
    }

    /// The contact model.
    pub fn model(&self) -> ContactModelKind {
        self.model
    }

    /// What the model is evaluated on: outlines, materials, laws.
    pub fn pair(&self) -> &ContactPair<B, P, N, F> {
        &self.pair
    }

    /// Calls `visit` with every loaded node of a model with nodes at the given states (its
    /// pressure and sliding, for Archard wear), and returns the forces; the line-of-centres
    /// model has no nodes and visits none.
    pub fn forces_visiting_nodes(
        &self,
        bearing_body: &BodyState,
        pin_body: &BodyState,
        onset_velocity: Option<f64>,
        visit: &mut dyn FnMut(&NodeLoad),
    ) -> ContactForces {
        self.forces_visiting_nodes_in(
            &mut ContactWorkspace::default(),
            bearing_body,
            pin_body,
            onset_velocity,
            visit,
        )
    }

    /// [`Self::forces_visiting_nodes`] with the joint's `workspace`.
    pub fn forces_visiting_nodes_in(
        &self,
        workspace: &mut ContactWorkspace,
        bearing_body: &BodyState,
        pin_body: &BodyState,
        onset_velocity: Option<f64>,
        visit: &mut dyn FnMut(&NodeLoad),
    ) -> ContactForces {
        let at = JointState::new(bearing_body, pin_body, onset_velocity);
        let state = self.state(workspace);
        self.model.forces(&self.pair, state, at, Some(visit))
    }

    /// The model's state for one evaluation: its tables and `workspace`'s part, which is made
    /// anew for this joint if it was filled for another joint's tables.
    fn state<'s>(
        &'s self,
        workspace: &'s mut ContactWorkspace,
    ) -> ModelState<'s, ContactModelKind> {
        ModelState {
            tables: &self.tables,
            workspace: workspace.for_tables(self.tables_key, || self.model.workspace()),
        }
    }

    /// The same joint with friction driven by `sliding` (default [`SlidingVelocity::Material`]).
    pub fn with_friction_sliding(mut self, sliding: SlidingVelocity) -> Self {
        self.pair.friction_sliding = sliding;
        self
    }

    /// Which sliding velocity the friction law sees.
    pub fn friction_sliding(&self) -> SlidingVelocity {
        self.pair.friction_sliding
    }

    /// The same joint with new surface profiles (e.g. after a wear stage), validated again.
    pub fn with_profiles<B2: SurfaceProfile, P2: SurfaceProfile>(
        self,
        bearing_profile: B2,
        pin_profile: P2,
    ) -> Result<ClearanceJoint<B2, P2, N, F>, ContactError> {
        let pair = self.pair.with_profiles(bearing_profile, pin_profile)?;
        Ok(ClearanceJoint::of(pair, self.model))
    }

    /// The bearing's profile.
    pub fn bearing_profile(&self) -> &B {
        self.pair.bearing_profile()
    }

    /// The pin's profile.
    pub fn pin_profile(&self) -> &P {
        self.pair.pin_profile()
    }

    /// The bearing and pin materials.
    pub fn materials(&self) -> (Material, Material) {
        self.pair.materials()
    }

    /// The normal law.
    pub fn normal_law(&self) -> &N {
        self.pair.normal_law()
    }

    /// The friction law.
    pub fn friction_law(&self) -> &F {
        self.pair.friction_law()
    }

    /// Hertz stiffness `K = 4/(3(ε_i + ε_j)) √(R_i R_j/(R_i − R_j))` for local radii (N/m^1.5).
    pub fn stiffness(&self, bearing_radius: f64, pin_radius: f64) -> f64 {
        self.pair.stiffness(bearing_radius, pin_radius)
    }

    /// The model's event function (m; negative when free): cheap, for root finding. For the
    /// line of centres the penetration `δ`; for the foundation the deepest overlap of the
    /// outlines at its nodes.
    #[inline]
    pub fn penetration(&self, bearing_body: &BodyState, pin_body: &BodyState) -> f64 {
        self.penetration_in(&mut ContactWorkspace::default(), bearing_body, pin_body)
    }

    /// [`Self::penetration`] with the joint's `workspace`.
    #[inline]
    pub fn penetration_in(
        &self,
        workspace: &mut ContactWorkspace,
        bearing_body: &BodyState,
        pin_body: &BodyState,
    ) -> f64 {
        let at = JointState::new(bearing_body, pin_body, None);
        let state = self.state(workspace);
        self.model.penetration(&self.pair, state, at)
    }

    /// Full kinematics of the line of centres at the given states.
    pub fn kinematics(&self, bearing_body: &BodyState, pin_body: &BodyState) -> JointKinematics {
        self.pair.kinematics(bearing_body, pin_body)
    }

    /// Generalized forces on both bodies.
    ///
    /// `onset_velocity` is `δ̇⁻` of the current contact (see [`crate::ImpactMemory`]); `None`
    /// means the contact has just begun and the current normal velocity is used.
    #[inline]
    pub fn forces(
        &self,
        bearing_body: &BodyState,
        pin_body: &BodyState,
        onset_velocity: Option<f64>,
    ) -> ContactForces {
        self.forces_in(
            &mut ContactWorkspace::default(),
            bearing_body,
            pin_body,
            onset_velocity,
        )
    }

    /// [`Self::forces`] with the joint's `workspace`.
    #[inline]
    pub fn forces_in(
        &self,
        workspace: &mut ContactWorkspace,
        bearing_body: &BodyState,
        pin_body: &BodyState,
        onset_velocity: Option<f64>,
    ) -> ContactForces {
        let at = JointState::new(bearing_body, pin_body, onset_velocity);
        let state = self.state(workspace);
        self.model.forces(&self.pair, state, at, None)
    }

    /// Generalized forces and their exact partials (layout: [`ContactJacobian`]).
    ///
    /// `δ̇⁻` is a parameter of the current contact, so it has no partial; with
    /// `onset_velocity = None` the current normal velocity is used as a constant. Where the law
    /// is not differentiable (the friction ramp's corners, the clamp) one side's partial is
    /// returned. Everything lives on the stack.
    pub fn forces_and_jacobian(
        &self,
        bearing_body: &BodyState,
        pin_body: &BodyState,
        onset_velocity: Option<f64>,
    ) -> (ContactForces, ContactJacobian) {
        self.forces_and_jacobian_in(
            &mut ContactWorkspace::default(),
            bearing_body,
            pin_body,
            onset_velocity,
        )
    }

    /// [`Self::forces_and_jacobian`] with the joint's `workspace`.
    pub fn forces_and_jacobian_in(
        &self,
        workspace: &mut ContactWorkspace,
        bearing_body: &BodyState,
        pin_body: &BodyState,
        onset_velocity: Option<f64>,
    ) -> (ContactForces, ContactJacobian) {
        let at = JointState::new(bearing_body, pin_body, onset_velocity);
        let state = self.state(workspace);
        self.model.forces_and_jacobian(&self.pair, state, at)
    }

    /// The true overlap of the two outlines: the largest distance by which a point of the pin's
    /// outline (sampled at `samples` body-frame angles) lies outside the bearing's outline,
    /// measured radially from the bearing centre, and the global direction of that point.
    ///
    /// For round surfaces it equals the penetration `δ` (up to the sampling); on worn ones it
    /// shows contacts the line-of-centres `δ` misses (a pin touching the side of a dent).
    /// Negative when the outlines are apart. Costs two profile samples per point.
    pub fn outline_overlap(
        &self,
        bearing_body: &BodyState,
        pin_body: &BodyState,
        samples: usize,
    ) -> OutlineOverlap {
        let pair = &self.pair;
        let bearing_centre = bearing_body.position() + bearing_body.rotate(&pair.bearing_centre);
        let pin_centre = pin_body.position() + pin_body.rotate(&pair.pin_centre);
        let mut deepest = OutlineOverlap {
            depth: f64::NEG_INFINITY,
            angle: 0.0,
        };
        for k in 0..samples.max(1) {
            let alpha = std::f64::consts::TAU * k as f64 / samples.max(1) as f64;
            let (s, c) = (alpha + pin_body.theta).sin_cos();
            let point = pin_centre + Vector2::new(c, s) * pair.pin_profile.sample(alpha).radius;
            let offset = point - bearing_centre;
            let angle = offset.y.atan2(offset.x);
            let depth = offset.norm()
                - pair
                    .bearing_profile
                    .sample(angle - bearing_body.theta)
                    .radius;
            if depth > deepest.depth {
                deepest = OutlineOverlap { depth, angle };
            }
        }
        deepest
    }
}

/// The contact model a joint runs unless given another, the same as a scene's default
/// (`contact` omitted): the elastic foundation on [`DEFAULT_FOUNDATION_CELLS`] nodes whose
/// layer reproduces the conformal Hertz force at [`DEFAULT_REFERENCE_OVERLAP`] of the
/// clearance ([`Foundation::hertz_matched`]), calibrated on the outlines' tightest fit: the
/// bearing's smallest radius and the pin's largest (on round surfaces their radii).
pub fn default_model<B: SurfaceProfile, P: SurfaceProfile, N, F>(
    pair: &ContactPair<B, P, N, F>,
) -> Result<ContactModelKind, ContactError> {
    let (bearing_radius, pin_radius) = tightest_fit(pair.bearing_profile(), pair.pin_profile());
    let (bearing, pin) = pair.materials();
    Ok(Foundation::hertz_matched(
        &bearing,
        &pin,
        bearing_radius,
        pin_radius,
        DEFAULT_REFERENCE_OVERLAP,
    )?
    .into())
}

/// Angles at which [`tightest_fit`] samples a profile that does not bound its radius.
const FIT_SAMPLES: usize = 64;

/// The bearing's smallest radius and the pin's largest: the profiles' own bounds where they
/// give them, else the extremes over [`FIT_SAMPLES`] angles.
fn tightest_fit(bearing: &impl SurfaceProfile, pin: &impl SurfaceProfile) -> (f64, f64) {
    let sampled = |profile: &dyn Fn(f64) -> f64, pick: fn(f64, f64) -> f64, start: f64| {
        (0..FIT_SAMPLES)
            .map(|k| profile(std::f64::consts::TAU * k as f64 / FIT_SAMPLES as f64))
            .fold(start, pick)
    };
    let bearing_radius = bearing.radius_bounds().map_or_else(
        || sampled(&|a| bearing.sample(a).radius, f64::min, f64::INFINITY),
        |(smallest, _)| smallest,
    );
    let pin_radius = pin.radius_bounds().map_or_else(
        || sampled(&|a| pin.sample(a).radius, f64::max, f64::NEG_INFINITY),
        |(_, largest)| largest,
    );
    (bearing_radius, pin_radius)
}
