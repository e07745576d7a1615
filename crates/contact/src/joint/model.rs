//! What a contact model is ([`ContactModel`]): the trait every model of a clearance joint
//! implements, the state it keeps (its tables and its workspace), the validity measures and
//! shape limits a model names, the node loads a node-resolved model reports for wear, and which
//! relative velocity counts as sliding.

use std::fmt::Debug;

use super::pair::ContactPair;
use super::types::{ContactForces, ContactJacobian, JointState, SlidingVelocity};
use crate::surface::SurfaceProfile;

/// A contact model of a clearance joint: how the pin's and the bearing's outlines load each
/// other. A model is a value (its parameters) and one module of this crate implementing this
/// trait; [`super::ContactModelKind`] names the built-in ones for scenes, which choose a model
/// at run time. What a run, its validity checks and its reports need to know of a model they
/// ask it here, never by its name.
///
/// Its evaluations are [`ContactKernel`]'s. The forces must be the exact gradient of an
/// elastic energy plus the law's damping and friction, so that an elastic frictionless joint
/// conserves energy; the Jacobian must be the exact partials of the same forces (a test
/// compares it with finite differences).
///
/// A model's state is its own, in two parts. Its [`Self::Tables`], what it precomputes from a
/// pair's outlines (the foundation's node table and radius bounds), are built once per pair
/// and read by every evaluation; the joint keeps them beside the model. Its
/// [`Self::Workspace`], what its evaluations carry from one to the next (the foundation's
/// overlap memory), belongs to whoever evaluates: each evaluation takes it as an argument, so
/// nothing is shared behind a shared reference. A model that needs neither names `()` for both.
pub trait ContactModel: Copy + Debug + PartialEq + Send + Sync {
    /// What the model precomputes from a pair's outlines, fixed while they are.
    type Tables: Clone + Debug + Send + Sync;

    /// What the model's evaluations of one joint carry from one to the next. The default value
    /// is an empty one: evaluations with it give the same results (they may take longer).
    type Workspace: Clone + Debug + Default + Send;

    /// The model's name in scenes, summaries and reports (kebab-case).
    fn name(&self) -> &'static str;

    /// The model's tables for `pair`: built when a joint takes the model or new profiles.
    fn tables<B: SurfaceProfile, P: SurfaceProfile, N, F>(
        &self,
        pair: &ContactPair<B, P, N, F>,
    ) -> Self::Tables;

    /// A workspace for evaluations of this model, made ready (sized) so that they allocate
    /// nothing; by default the empty one.
    fn workspace(&self) -> Self::Workspace {
        Self::Workspace::default()
    }

    /// How many nodes the model resolves the pin's outline into, when it does: its wear is
    /// then deposited node by node from [`NodeLoad`]s, else from the one contact point of the
    /// diagnostics. None by default: a model of one contact point.
    fn nodes(&self) -> Option<usize> {
        None
    }

    /// The measures by which a response of this model is judged valid, in the order their
    /// verdicts are reported.
    fn validity_measures(&self) -> &'static [ValidityMeasure];

    /// The shape the worn outlines must keep for the model to describe them (`None`, the
    /// default: any). Wear stepping stops a stage where the next sub-step would leave it.
    fn shape_limits(&self) -> Option<ShapeLimits> {
        None
    }
}

/// What a [`ContactModel`] evaluates on a pair of outlines of types `B`, `P` with laws `N`,
/// `F`: the forces, their exact partials and the event function. A model implements it for
/// every pair it can evaluate (the built-in ones for any profiles and laws). Each evaluation
/// reads the model's tables for `pair` and may use its workspace (see [`ContactModel`]).
pub trait ContactKernel<B, P, N, F>: ContactModel {
    /// Generalized forces on both bodies at `at`; every loaded node to `visit` when the model
    /// has nodes.
    fn forces(
        &self,
        pair: &ContactPair<B, P, N, F>,
        state: ModelState<'_, Self>,
        at: JointState,
        visit: Visit,
    ) -> ContactForces;

    /// The forces and their exact partials ([`ContactJacobian`]'s layout).
    fn forces_and_jacobian(
        &self,
        pair: &ContactPair<B, P, N, F>,
        state: ModelState<'_, Self>,
        at: JointState,
    ) -> (ContactForces, ContactJacobian);

    /// The event function: a signed depth (m) that crosses zero where contact begins and
    /// ends, positive in contact. Cheap: it is evaluated at every step.
    fn penetration(
        &self,
        pair: &ContactPair<B, P, N, F>,
        state: ModelState<'_, Self>,
        at: JointState,
    ) -> f64;
}

/// A model's state as one evaluation sees it: its tables for the pair, read, and the
/// workspace of the joint's evaluations, written.
pub struct ModelState<'s, M: ContactModel> {
    /// What the model precomputed from the pair's outlines.
    pub tables: &'s M::Tables,
    /// What the evaluations carry from one to the next.
    pub workspace: &'s mut M::Workspace,
}

/// Where a model's forces hand each loaded node, if anywhere.
pub type Visit<'v> = Option<&'v mut dyn FnMut(&NodeLoad)>;

/// A measure of whether a contact model describes the contacts of a response, from the
/// diagnostics of its frames ([`crate::ContactDiagnostics`]). The run accumulates them and judges
/// those its model names ([`ContactModel::validity_measures`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ValidityMeasure {
    /// The deepest overlap of the outlines over the nominal clearance: a thin layer describes
    /// a shallow one only.
    OverlapRatio,
    /// The estimated load error from the nodes' resolution of narrow contact zones.
    ResolutionError,
    /// The profile slope `|R_i' − R_j'|/|e|` at loaded frames: one contact point on the line of
    /// centres describes gentle slopes only.
    SlopeRatio,
    /// The worn dent's curvature against what the pin can follow, `(R_j'' − R_i'')/c`.
    Conformity,
    /// Frames with `δ` above 1 % of the clearance that carry no force.
    UnloadedPenetration,
    /// The true overlap of the outlines against `δ` (needs the outline overlap measured).
    OverlapError,
    /// Frames where the outlines overlap but `δ < 0` (needs the outline overlap measured).
    MissedContacts,
    /// The thin-gap model's neglected terms over its overlap
    /// ([`crate::ContactDiagnostics::neglected_terms`]): its overlap holds while the
    /// eccentricity is small against the radius and the outlines are gentle over it.
    NeglectedTerms,
}

impl ValidityMeasure {
    /// Whether judging it needs the true overlap of the outlines, measured apart from the
    /// model ([`super::ClearanceJoint::outline_overlap`]).
    pub fn needs_outline_overlap(self) -> bool {
        matches!(self, Self::OverlapError | Self::MissedContacts)
    }
}

/// Limits on the worn outlines' shape, relative to the nominal clearance `c0`: a model that
/// names them describes the contact only while the outlines keep within them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeLimits {
    /// Largest `(max|R_i'| + max|R_j'|)/c0` (1/rad).
    pub slope: f64,
    /// Largest `(max|R_i''| + max|R_j''|)/c0` (1/rad²; infinite: no limit).
    pub curvature: f64,
}

/// The load of one node of the foundation at one state: what Archard wear needs.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NodeLoad {
    /// The node's index on the pin's outline (its cell, `0..cells`).
    pub cell: usize,
    /// The node's angle in the pin's frame, the centre of its cell (rad).
    pub pin_angle: f64,
    /// Where the node meets the bearing, in the bearing's frame (rad, in `[0, 2π)`).
    pub bearing_angle: f64,
    /// Normal force the node carries, `L_k |m_k|` (N).
    pub normal_force: f64,
    /// The node's outline length on the pin, `R_j0 Δα` (m): pressure is
    /// `normal_force / (arc · w)`.
    pub arc: f64,
    /// Sliding velocity of the pin's material point on the bearing's along the local tangent
    /// (m/s).
    pub material_sliding: f64,
    /// The paper's sliding velocity `d_k φ̇` (m/s).
    pub paper_sliding: f64,
    /// How fast the node's normal force falls as the gap it closes opens evenly, as wear
    /// opens it: `k w · arc · φ · |m_k|` (N/m; the layer's line modulus over the node's arc,
    /// with the damping factor it carries). Wear stepping reads the stiffness of the wear
    /// process from it (`wear`'s linearly implicit sub-steps).
    pub stiffness: f64,
}

impl NodeLoad {
    /// The sliding velocity `choice` reads (m/s).
    pub fn sliding(&self, choice: SlidingVelocity) -> f64 {
        match choice {
            SlidingVelocity::Material => self.material_sliding,
            SlidingVelocity::Paper => self.paper_sliding,
        }
    }
}
