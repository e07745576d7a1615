//! The thin-gap contact: the elastic foundation's layer ([`super::foundation`]) with its overlap
//! in the film-thickness form of a thin clearance, on nodes fixed in the bearing's frame.
//!
//! # Overlap
//! Node `k` is the bearing-frame direction `θ_k = (k + ½) 2π/N`, `n_k = u(θ_k)`,
//! `t_k = u'(θ_k)`. With `ε` the pin centre from the bearing centre in the bearing's frame,
//! `a_k = ε·n_k`, `b_k = ε·t_k`, and `Δ = θ_j − θ_i` the pin's turn relative to the bearing,
//! the pin's outline point on the ray `θ_k` from the bearing centre lies at
//! `ρ_k = a_k + r(β) cos γ` with `r(β) sin γ = −b_k`, `β = θ_k + γ`, `r` the pin's radius at
//! its frame's angle `β − Δ`. With `r_k`, `r'_k`, `κ_k` the pin's radius, slope and
//! curvature at `θ_k − Δ` and `q_k = b_k/r_k`, to second order in `q_k`:
//!
//! `g_k = ρ_k − R_i(θ_k) = a_k + r_k − r'_k q_k − (b_k/2) q_k + κ_k q_k²/2 − R_i(θ_k)`:
//!
//! the pin read at its turn relative to the bearing, shifted along its outline by
//! `γ ≈ −q_k` (the reading shift), the ray's chord through the pin's circle (`−b_k²/(2r_k)`)
//! and the pin's curvature over the shift. Dropping the second-order terms errs by tens of per
//! cent on a worn pin (its slope times `b/r` and `|e|²/(2r)` are of the order of the overlap;
//! without the curvature term, by a few 1e-4). `1/r_k` is `(1 − v_k/R)/R` (`R` the pin's
//! largest radius, `v_k = r_k − R ≤ 0`), first order in `v_k/R`: its error `(v_k/R)²` is a few
//! 1e-5 on a worn pin. What is left, third order, is estimated per node
//! (`ContactDiagnostics::neglected_terms`).
//! The bearing's radius is read at its own nodes (a table); the pin's from an interpolating
//! periodic cubic spline of its radius at the same grid, whose four weights are the same at
//! every node for one turn `Δ` ([`tables::Shift`]), and its curvature `κ` from a cubic spline
//! of its own read by the same weights (so that `∂κ/∂Δ` is C¹): no angle, square root or
//! trigonometric function per node.
//!
//! # Energy, force, damping, friction, wear
//! The foundation's layer, `V = (k w/2) ∫ max(0, g)² ds` over the pin's outline. A ray turning
//! by `dθ` sweeps `(1 + a_k/r_k) dθ` of the pin's outline (its centre is nearer by `a_k`), so
//! the nodes carry the weighed overlap `g̃_k = g_k (1 + a_k/(2r_k))`, whose square has that
//! factor to first order (without it the energy is short by `|e|/R`, about 1 % in the LGRES). As the
//! foundation: `g̃` linear between nodes, each segment's positive part integrated exactly (C¹
//! forces as a zone edge crosses a node), Simpson's rule by Richardson's combination (or the
//! trapezoid), the elastic force exactly `−∇V` with `∇g̃_k = m̃_k·∂ε/∂q + (∂g̃_k/∂Δ) ∂Δ/∂q`.
//! With `ι_k = 1/r_k`, `J_k = 1 + a_k ι_k/2` and `∂ι_k/∂Δ = r'_k/R²` (the radius read at
//! `θ_k − Δ` turns with `Δ`):
//! `m̃_k = J_k (n_k − (r'_k + b_k − κ_k q_k) ι_k t_k) + g_k ι_k n_k/2`,
//! `∂g̃_k/∂Δ = J_k (r''_k q_k − r'_k − (r'_k + b_k/2 − κ_k q_k) b_k r'_k/R² − κ'_k q_k²/2)
//! + g_k a_k r'_k/(2R²)` (`r''` the radius spline's curvature):
//! on the pin a force `−Σ G_k m̃_k` (turned to the global frame) and a moment
//! `−Σ G_k ∂g̃_k/∂Δ`, on the bearing their reaction about its centre. Damping per
//! node with the rate held within the impact's onset velocity, friction per node at the pin's
//! point on the ray along `t̂_k ⟂ m_k`, node loads for wear (the pin's angle `θ_k − Δ`, the
//! bearing's `θ_k`; Simpson's deposits as the trapezoid's scaled to the load).
//!
//! # Window
//! A node can overlap only where
//! `ρ cos(θ_k − φ) > R_i⁻ − R_j⁺ − max|r'| ρ/r⁻ − max(κ, 0) ρ²/(2r⁻²)` (`ρ = |ε|` at
//! angle `φ`): the overlaps of the nodes in that arc, and of the one or two beyond each end
//! whose segments it reaches, are computed in one straight sweep over the tables (packed
//! arithmetic, no branch per node) into the workspace; the forces then visit, in order, only
//! the nodes a positive overlap reaches through a segment, stepping over runs of nodes apart
//! in one search. Free (`ρ` below the bound) none is.

mod kernel;
mod layer;
mod tables;

pub use layer::{ThinGap, ThinGapWorkspace};
pub use tables::ThinGapTables;

use super::model::{ContactKernel, ContactModel, ModelState, ValidityMeasure, Visit};
use super::pair::ContactPair;
use super::types::{ContactForces, ContactJacobian, JointState};
use crate::friction::FrictionLaw;
use crate::normal::NormalLaw;
use crate::surface::SurfaceProfile;

impl ContactModel for ThinGap {
    /// The nodes' directions, the bearing's radii there, the pin's spline and the bounds.
    type Tables = ThinGapTables;
    type Workspace = ThinGapWorkspace;

    fn name(&self) -> &'static str {
        "thin-gap"
    }

    fn tables<B: SurfaceProfile, P: SurfaceProfile, N, F>(
        &self,
        pair: &ContactPair<B, P, N, F>,
    ) -> ThinGapTables {
        ThinGapTables::new(
            pair.bearing_profile(),
            pair.pin_profile(),
            self.layer().cells,
        )
    }

    /// Room for every node's wear load and overlap (a window of every node and two beyond
    /// each end).
    fn workspace(&self) -> ThinGapWorkspace {
        let cells = self.layer().cells;
        ThinGapWorkspace::with_room(cells, cells + 4)
    }

    fn nodes(&self) -> Option<usize> {
        Some(self.layer().cells)
    }

    /// The foundation's (a thin layer, resolved zones) and its own: the terms it neglects.
    fn validity_measures(&self) -> &'static [ValidityMeasure] {
        &[
            ValidityMeasure::OverlapRatio,
            ValidityMeasure::ResolutionError,
            ValidityMeasure::NeglectedTerms,
        ]
    }
}

impl<B: SurfaceProfile, P: SurfaceProfile, N: NormalLaw, F: FrictionLaw> ContactKernel<B, P, N, F>
    for ThinGap
{
    fn forces(
        &self,
        pair: &ContactPair<B, P, N, F>,
        state: ModelState<'_, Self>,
        at: JointState,
        visit: Visit,
    ) -> ContactForces {
        kernel::Kernel::new(self, pair, state.tables).forces(state.workspace, at, visit)
    }

    fn forces_and_jacobian(
        &self,
        pair: &ContactPair<B, P, N, F>,
        state: ModelState<'_, Self>,
        at: JointState,
    ) -> (ContactForces, ContactJacobian) {
        kernel::Kernel::new(self, pair, state.tables).forces_and_jacobian(state.workspace, at)
    }

    fn penetration(
        &self,
        pair: &ContactPair<B, P, N, F>,
        state: ModelState<'_, Self>,
        at: JointState,
    ) -> f64 {
        kernel::Kernel::new(self, pair, state.tables).deepest(state.workspace, at)
    }
}
