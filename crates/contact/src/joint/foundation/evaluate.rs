//! The foundation as a contact model: its forces, their exact Jacobian (the kernel on dual
//! numbers) and its event function, the deepest overlap at the nodes.

use nalgebra::Vector3;

use super::Kernel;
use super::geometry::{Body, offset};
use super::layer::Foundation;
use super::memory::{FoundationWorkspace, Pose, Remembered, Skip};
use super::window::NodeWindow;
use crate::friction::FrictionLaw;
use crate::joint::dual::{body_variables, jacobian};
use crate::joint::model::{ContactKernel, ContactModel, ModelState, ValidityMeasure, Visit};
use crate::joint::pair::ContactPair;
use crate::joint::types::{BodyState, ContactForces, ContactJacobian, JointState};
use crate::normal::NormalLaw;
use crate::surface::SurfaceProfile;

impl<B: SurfaceProfile, P: SurfaceProfile, N: NormalLaw, F: FrictionLaw> Kernel<'_, B, P, N, F> {
    /// Forces of the foundation model at the given states.
    fn foundation_forces(
        &self,
        foundation: &Foundation,
        workspace: &mut FoundationWorkspace,
        at: JointState,
        visit: Visit,
    ) -> ContactForces {
        let out = self.foundation_eval(
            foundation,
            workspace,
            at.bearing.coordinates(),
            at.pin.coordinates(),
            at.onset_velocity,
            visit,
        );
        ContactForces {
            bearing: Vector3::from(out.bearing),
            pin: Vector3::from(out.pin),
            diagnostics: out.diagnostics,
        }
    }

    /// Forces of the foundation model and their exact Jacobian (dual numbers).
    fn foundation_forces_and_jacobian(
        &self,
        foundation: &Foundation,
        workspace: &mut FoundationWorkspace,
        at: JointState,
    ) -> (ContactForces, ContactJacobian) {
        let out = self.foundation_eval(
            foundation,
            workspace,
            body_variables(at.bearing, 0),
            body_variables(at.pin, 3),
            at.onset_velocity,
            None,
        );
        let jacobian = jacobian(&out.bearing, &out.pin);
        let forces = ContactForces {
            bearing: Vector3::new(
                out.bearing[0].value,
                out.bearing[1].value,
                out.bearing[2].value,
            ),
            pin: Vector3::new(out.pin[0].value, out.pin[1].value, out.pin[2].value),
            diagnostics: out.diagnostics,
        };
        (forces, jacobian)
    }

    /// The deepest overlap of the outlines (m; negative when apart): the foundation's event
    /// function. In free flight, the gap between the outlines' radius bounds.
    fn foundation_overlap(
        &self,
        foundation: &Foundation,
        memory: &Remembered,
        bearing_body: &BodyState,
        pin_body: &BodyState,
    ) -> f64 {
        let bearing = Body::new(bearing_body.coordinates());
        let pin = Body::new(pin_body.coordinates());
        let bearing_centre_arm =
            bearing.rotate([self.pair.bearing_centre.x, self.pair.bearing_centre.y]);
        let pin_centre_arm = pin.rotate([self.pair.pin_centre.x, self.pair.pin_centre.y]);
        let e = offset(&pin, &pin_centre_arm, &bearing, &bearing_centre_arm);
        let cells = foundation.cells;
        // The nodes that may overlap (the runs' outer nodes, which cannot, are sampled too).
        let candidates = self.candidates(cells, e, (pin_body.theta, bearing_body.theta), 1);
        let mut deepest = candidates.outside_bound;
        // The overlap memory skips the nodes that cannot beat the deepest so far (read only).
        let memory = self
            .window
            .bearing_slope
            .and(Some(memory))
            .filter(|m| m.overlap.len() == cells);
        let skip = memory.and_then(|m| {
            let now = Pose::new(e, bearing.theta_sin_cos, bearing_body.theta, pin_body.theta);
            Some((Skip::new(m, self.window.drift(m.pose, now)?), m))
        });
        let floor = skip.map_or(f64::NEG_INFINITY, |(skip, _)| skip.floor);
        let runs = &candidates.runs[..candidates.count];
        let n = cells as i64;
        let overlap_of = |cell: usize, deepest: f64, gap_bound: f64| {
            self.overlap_at(
                cell,
                &bearing,
                &pin,
                &bearing_centre_arm,
                bearing_body.theta,
                deepest,
                gap_bound,
            )
        };
        // The memory's deepest node first: when it still overlaps, every node whose bound does
        // not beat it is passed over below without being placed. (The maximum over the
        // candidate runs does not depend on the order in which their nodes come.)
        if let Some(cell) = skip.and_then(|(_, m)| m.deepest_cell)
            && runs
                .iter()
                .any(|&(first, last)| (cell as i64 - first).rem_euclid(n) <= last - first)
            && let Some(g) = overlap_of(cell, deepest, f64::INFINITY)
        {
            deepest = deepest.max(g);
        }
        for k in runs.iter().flat_map(|&(first, last)| first..=last) {
            let cell = k.rem_euclid(n) as usize;
            let gap_bound = skip.map_or(f64::INFINITY, |(skip, m)| skip.gap_bound(m, cell));
            let gap_bound = if gap_bound < floor {
                f64::NEG_INFINITY
            } else {
                gap_bound
            };
            // Once something overlaps, a node beyond the smallest radius cannot beat it past its
            // bound, and one within it not at all (`overlap_at` would say `None` either way).
            if deepest > 0.0 && gap_bound <= deepest {
                continue;
            }
            if let Some(g) = overlap_of(cell, deepest, gap_bound) {
                deepest = deepest.max(g);
            }
        }
        deepest
    }
}

/// No shape limits (the default): the layer follows any outline.
impl ContactModel for Foundation {
    /// The node table and the outlines' radius bounds by sector.
    type Tables = NodeWindow;
    /// The overlap memory and the buffer of Simpson's wear loads.
    type Workspace = FoundationWorkspace;

    fn name(&self) -> &'static str {
        "foundation"
    }

    fn tables<B: SurfaceProfile, P: SurfaceProfile, N, F>(
        &self,
        pair: &ContactPair<B, P, N, F>,
    ) -> NodeWindow {
        NodeWindow::new(pair.bearing_profile(), pair.pin_profile(), self.cells)
    }

    /// Room for an overlap memory of every node.
    fn workspace(&self) -> FoundationWorkspace {
        FoundationWorkspace::for_cells(self.cells)
    }

    fn nodes(&self) -> Option<usize> {
        Some(self.cells)
    }

    /// A thin layer describes shallow overlaps only, and the nodes must resolve the zones.
    /// Unloaded overlapping frames have no limit here: on the foundation they only show the
    /// damped law's own clamp (a pin leaving faster than `1/χ` times its onset velocity), not a
    /// shape the model misreads.
    fn validity_measures(&self) -> &'static [ValidityMeasure] {
        &[
            ValidityMeasure::OverlapRatio,
            ValidityMeasure::ResolutionError,
        ]
    }
}

impl<B: SurfaceProfile, P: SurfaceProfile, N: NormalLaw, F: FrictionLaw> ContactKernel<B, P, N, F>
    for Foundation
{
    fn forces(
        &self,
        pair: &ContactPair<B, P, N, F>,
        state: ModelState<'_, Self>,
        at: JointState,
        visit: Visit,
    ) -> ContactForces {
        let kernel = Kernel {
            pair,
            window: state.tables,
        };
        kernel.foundation_forces(self, state.workspace, at, visit)
    }

    fn forces_and_jacobian(
        &self,
        pair: &ContactPair<B, P, N, F>,
        state: ModelState<'_, Self>,
        at: JointState,
    ) -> (ContactForces, ContactJacobian) {
        let kernel = Kernel {
            pair,
            window: state.tables,
        };
        kernel.foundation_forces_and_jacobian(self, state.workspace, at)
    }

    fn penetration(
        &self,
        pair: &ContactPair<B, P, N, F>,
        state: ModelState<'_, Self>,
        at: JointState,
    ) -> f64 {
        // The deepest overlap of the outlines at the nodes.
        let kernel = Kernel {
            pair,
            window: state.tables,
        };
        kernel.foundation_overlap(self, &state.workspace.memory, at.bearing, at.pin)
    }
}
