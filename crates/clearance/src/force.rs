//! The clearance force element and its read-only probe.

use std::cell::RefCell;

use contact::{
    BodyState, CircularProfile, ClearanceJoint, ContactDiagnostics, ContactForces, ContactModel,
    ContactWorkspace, FrictionLaw, FrictionLawKind, ImpactMemory, NodeLoad, NormalLaw,
    NormalLawKind, SurfaceProfile,
};
use multibody::{BodyId, ForceElement, ForcePartials};
use wear::{StageWear, WornProfile};

/// A clearance joint whose bearing sits on one body (or ground) and whose pin on another.
///
/// Generic over the surfaces (`B`, `P`) and the laws (`N`, `F`): code that knows its laws at
/// compile time skips the run-time dispatch of the default [`NormalLawKind`]/[`FrictionLawKind`].
#[derive(Debug, Clone)]
pub struct ClearanceForce<
    B = CircularProfile,
    P = CircularProfile,
    N = NormalLawKind,
    F = FrictionLawKind,
> {
    name: String,
    /// Bearing body then pin body; `None` is ground.
    bodies: [Option<BodyId>; 2],
    joint: ClearanceJoint<B, P, N, F>,
    /// What the joint's evaluations carry from one to the next (the foundation's overlap
    /// memory): this element's own, made for its joint. The integrator evaluates the element
    /// through shared references, one call at a time, so each evaluation borrows it in turn.
    workspace: RefCell<ContactWorkspace>,
    /// Onset velocity `δ̇⁻` of the current contact (the L–N damping needs it).
    memory: ImpactMemory,
    /// Diagnostics at the end of the last accepted step.
    last: Option<ContactDiagnostics>,
    /// Wear of the current stage (`None`: wear off).
    wear: Option<StageWear>,
    /// The part of `wear` from steps that start before the split time: compared with the
    /// rest, it tells whether the stage's cycles give a converged wear estimate.
    first_half: Option<(f64, StageWear)>,
    /// Steps that start before this time add no wear: lets a stage skip the start-up transient
    /// of its concentric initial state (docs/model.md §8) while still covering whole drive cycles.
    wear_start: f64,
    /// Energy friction dissipated on the material sliding over accepted steps (J).
    friction_dissipation: f64,
    /// Energy the normal force dissipated beyond its elastic part over accepted steps (J).
    damping_dissipation: f64,
    /// Largest normal force at an accepted step end (N).
    peak_normal_force: f64,
    /// Foundation model with wear on: the loaded nodes at the last accepted step's start and
    /// end (buffers reused from step to step).
    nodes: [Vec<NodeLoad>; 2],
}

/// A clearance joint between round (unworn) surfaces: no wear code involved.
pub type RoundClearanceForce = ClearanceForce<CircularProfile, CircularProfile>;

/// A clearance joint that samples worn surfaces.
pub type WornClearanceForce = ClearanceForce<WornProfile, WornProfile>;

impl<B: SurfaceProfile, P: SurfaceProfile, N: NormalLaw, F: FrictionLaw>
    ClearanceForce<B, P, N, F>
{
    /// A clearance force element between `bearing_body` and `pin_body` (`None` = ground); the
    /// joint's surface centres are in those bodies' frames.
    pub fn new(
        name: impl Into<String>,
        bearing_body: Option<BodyId>,
        pin_body: Option<BodyId>,
        joint: ClearanceJoint<B, P, N, F>,
    ) -> Self {
        Self {
            name: name.into(),
            bodies: [bearing_body, pin_body],
            workspace: RefCell::new(joint.workspace()),
            joint,
            memory: ImpactMemory::new(),
            last: None,
            wear: None,
            first_half: None,
            wear_start: f64::NEG_INFINITY,
            friction_dissipation: 0.0,
            damping_dissipation: 0.0,
            peak_normal_force: 0.0,
            nodes: [Vec::new(), Vec::new()],
        }
    }

    /// The underlying contact joint.
    pub fn joint(&self) -> &ClearanceJoint<B, P, N, F> {
        &self.joint
    }

    /// Bearing body then pin body (`None`: ground).
    pub fn bodies(&self) -> [Option<BodyId>; 2] {
        self.bodies
    }

    /// Contact state at `(q, q̇)` with the impact memory of the last accepted step: for
    /// recorders at output times.
    pub fn evaluate(&self, q: &[f64], qd: &[f64]) -> ContactForces {
        let [bearing, pin] = self.states(q, qd);
        self.with_workspace(|workspace| {
            self.joint
                .forces_in(workspace, &bearing, &pin, self.memory.onset_velocity())
        })
    }

    /// Runs `evaluate` with the element's workspace, or with an empty one (the same results)
    /// should it already be in use.
    fn with_workspace<T>(&self, evaluate: impl FnOnce(&mut ContactWorkspace) -> T) -> T {
        match self.workspace.try_borrow_mut() {
            Ok(mut workspace) => evaluate(&mut workspace),
            Err(_) => evaluate(&mut ContactWorkspace::default()),
        }
    }

    /// True overlap of the worn outlines at positions `q` (`samples` points on the pin).
    pub fn outline_overlap(&self, q: &[f64], samples: usize) -> contact::OutlineOverlap {
        let [bearing, pin] = self.states(q, q);
        self.joint.outline_overlap(&bearing, &pin, samples)
    }

    /// Diagnostics at the end of the last accepted step (`None` before the first).
    pub fn last_diagnostics(&self) -> Option<&ContactDiagnostics> {
        self.last.as_ref()
    }

    /// Energy friction dissipated over the accepted steps so far, `∫ F_t v_t dt` on the
    /// material sliding (J; ≥ 0 unless the friction is driven by another velocity than the
    /// material one and then works against it).
    pub fn friction_dissipation(&self) -> f64 {
        self.friction_dissipation
    }

    /// Energy the normal force dissipated beyond its elastic part over the accepted steps so
    /// far, `∫ (F_n − F_e) δ̇ dt` (J; ≥ 0 for a dissipative law).
    pub fn damping_dissipation(&self) -> f64 {
        self.damping_dissipation
    }

    /// Largest normal force at an accepted step end so far (N).
    pub fn peak_normal_force(&self) -> f64 {
        self.peak_normal_force
    }

    /// The wear accumulated in this stage, if wear is on.
    pub fn stage_wear(&self) -> Option<&StageWear> {
        self.wear.as_ref()
    }

    /// Takes the stage's wear buffer out (leaving wear off).
    pub fn take_stage_wear(&mut self) -> Option<StageWear> {
        self.wear.take()
    }

    /// Takes the first half's wear buffer out (see [`WornClearanceForce::with_halves`]).
    pub fn take_first_half(&mut self) -> Option<StageWear> {
        self.first_half.take().map(|(_, wear)| wear)
    }

    /// The onset velocity of the contact under way at the last accepted step: with the state,
    /// what a trajectory carries over to a system rebuilt on updated surfaces.
    pub fn impact_memory(&self) -> ImpactMemory {
        self.memory
    }

    /// Continues a trajectory: the contact under way keeps the onset velocity it had (its
    /// Lankarani–Nikravesh damping would otherwise take the current normal velocity for it).
    pub fn set_impact_memory(&mut self, memory: ImpactMemory) {
        self.memory = memory;
    }

    fn states(&self, q: &[f64], qd: &[f64]) -> [BodyState; 2] {
        self.bodies.map(|body| match body {
            Some(BodyId(k)) => BodyState::new(
                [q[3 * k], q[3 * k + 1], q[3 * k + 2]],
                [qd[3 * k], qd[3 * k + 1], qd[3 * k + 2]],
            ),
            None => BodyState::at_rest(0.0, 0.0, 0.0),
        })
    }

    fn add_body_force(&self, slot: usize, force: [f64; 3], forces: &mut [f64]) {
        if let Some(BodyId(k)) = self.bodies[slot] {
            for (target, value) in forces[3 * k..3 * k + 3].iter_mut().zip(force) {
                *target += value;
            }
        }
    }
}

impl<N, F> ClearanceForce<WornProfile, WornProfile, N, F> {
    /// Accumulates the stage's wear into `stage` on accepted steps that start at or after
    /// `wear_start` (s); `stage` must belong to the joint the profiles came from.
    pub fn with_stage_wear(mut self, stage: StageWear, wear_start: f64) -> Self {
        self.wear = Some(stage);
        self.wear_start = wear_start;
        self
    }

    /// Gathers wear from accepted steps that start at or after `wear_start` (s) instead, and
    /// keeps no halves apart: the wear-stage driver gives each trajectory of an ensemble its
    /// own window.
    pub fn set_wear_window(&mut self, wear_start: f64) {
        self.wear_start = wear_start;
        self.first_half = None;
    }

    /// When wear gathering starts (s; −∞ when it was never set).
    pub fn wear_start(&self) -> f64 {
        self.wear_start
    }

    /// Also keeps the wear of the steps that start before `split` (s) apart, so that the two
    /// halves of a stage's cycles can be compared; `first_half` is an empty record of the
    /// same joint.
    pub fn with_halves(mut self, first_half: StageWear, split: f64) -> Self {
        self.first_half = Some((split, first_half));
        self
    }
}

impl<B, P, N, F> ForceElement for ClearanceForce<B, P, N, F>
where
    B: SurfaceProfile + Send + 'static,
    P: SurfaceProfile + Send + 'static,
    N: NormalLaw + Send + 'static,
    F: FrictionLaw + Send + 'static,
{
    fn name(&self) -> &str {
        &self.name
    }

    fn add_forces(&self, _t: f64, q: &[f64], qd: &[f64], forces: &mut [f64]) {
        let contact = self.evaluate(q, qd);
        if contact.diagnostics.in_contact {
            self.add_body_force(0, contact.bearing.into(), forces);
            self.add_body_force(1, contact.pin.into(), forces);
        }
    }

    fn add_partials(&self, _t: f64, q: &[f64], qd: &[f64], partials: &mut ForcePartials<'_>) {
        let [bearing, pin] = self.states(q, qd);
        let (contact, jacobian) = self.with_workspace(|workspace| {
            self.joint.forces_and_jacobian_in(
                workspace,
                &bearing,
                &pin,
                self.memory.onset_velocity(),
            )
        });
        if !contact.diagnostics.in_contact {
            return;
        }
        // The kernel's 6×12 layout is the one `add_pair` expects; copy it to plain rows.
        let mut rows = [[0.0; 12]; 6];
        for (r, row) in rows.iter_mut().enumerate() {
            for (c, value) in row.iter_mut().enumerate() {
                *value = jacobian[(r, c)];
            }
        }
        partials.add_pair(self.bodies, &rows);
    }

    fn on_accepted_step(&mut self, t_previous: f64, t: f64, q: &[f64], qd: &[f64]) {
        // A model with nodes wears node by node: it needs the pressure of every loaded node,
        // from the same evaluation as the diagnostics.
        let node_wear = self.wear.is_some() && self.joint.model().nodes().is_some();
        let current = if node_wear {
            let [bearing, pin] = self.states(q, qd);
            let mut nodes = std::mem::take(&mut self.nodes[1]);
            nodes.clear();
            let forces = self.joint.forces_visiting_nodes_in(
                self.workspace.get_mut(),
                &bearing,
                &pin,
                self.memory.onset_velocity(),
                &mut |node| nodes.push(*node),
            );
            if self.last.is_none() {
                self.nodes[0].clone_from(&nodes);
            }
            self.nodes[1] = nodes;
            forces.diagnostics
        } else {
            self.evaluate(q, qd).diagnostics
        };
        let previous = self.last.unwrap_or(current);
        self.memory.update(&previous, &current);
        let dt = t - t_previous;
        // Trapezoid over the step, the same quadrature as the wear.
        self.friction_dissipation += 0.5 * dt * (previous.friction_power + current.friction_power);
        self.damping_dissipation += 0.5 * dt * (previous.damping_power + current.damping_power);
        self.peak_normal_force = self.peak_normal_force.max(current.normal_force);
        if t_previous >= self.wear_start
            && let Some(wear) = &mut self.wear
        {
            // The diagnostics come from the kernel, so they are finite and consistent; a
            // rejection here would be a kernel bug, not a user error.
            let first = self
                .first_half
                .as_mut()
                .filter(|(split, _)| t_previous < *split)
                .map(|(_, wear)| wear);
            for wear in std::iter::once(wear).chain(first) {
                let deposited = if node_wear {
                    wear.accumulate_nodes(&self.nodes[0], &self.nodes[1], dt)
                } else {
                    wear.accumulate_step(&previous, &current, dt)
                };
                if let Err(error) = deposited {
                    debug_assert!(
                        false,
                        "wear accumulation rejected kernel diagnostics: {error}"
                    );
                }
            }
        }
        if node_wear {
            self.nodes.swap(0, 1);
        }
        self.last = Some(current);
    }

    fn event_count(&self) -> usize {
        1
    }

    /// `δ`: the integrator lands a step on each contact onset and separation, so the impact
    /// memory records the onset velocity at the crossing rather than somewhere inside a step.
    fn event_functions(&self, _t: f64, q: &[f64], qd: &[f64], values: &mut [f64]) {
        let [bearing, pin] = self.states(q, qd);
        values[0] =
            self.with_workspace(|workspace| self.joint.penetration_in(workspace, &bearing, &pin));
    }
}

/// A read-only view of a clearance element, whatever its surfaces.
pub trait ClearanceProbe {
    /// Contact state at `(q, q̇)` (see [`ClearanceForce::evaluate`]).
    fn contact(&self, q: &[f64], qd: &[f64]) -> contact::ContactForces;
    /// Energy dissipated by friction over accepted steps, J.
    fn friction_dissipation(&self) -> f64;
    /// Energy dissipated by the normal force's damping over accepted steps, J.
    fn damping_dissipation(&self) -> f64;
    /// Largest normal force at an accepted step end, N.
    fn peak_normal_force(&self) -> f64;
    /// Contact state at the end of the last accepted step.
    fn last_diagnostics(&self) -> Option<&ContactDiagnostics>;
    /// True overlap of the two outlines at `q` (see `contact::ClearanceJoint::outline_overlap`).
    fn outline_overlap(&self, q: &[f64], samples: usize) -> contact::OutlineOverlap;
}

impl<B, P, N, F> ClearanceProbe for ClearanceForce<B, P, N, F>
where
    B: SurfaceProfile,
    P: SurfaceProfile,
    N: NormalLaw,
    F: FrictionLaw,
{
    fn contact(&self, q: &[f64], qd: &[f64]) -> contact::ContactForces {
        self.evaluate(q, qd)
    }
    fn friction_dissipation(&self) -> f64 {
        ClearanceForce::friction_dissipation(self)
    }
    fn damping_dissipation(&self) -> f64 {
        ClearanceForce::damping_dissipation(self)
    }
    fn peak_normal_force(&self) -> f64 {
        ClearanceForce::peak_normal_force(self)
    }
    fn last_diagnostics(&self) -> Option<&ContactDiagnostics> {
        ClearanceForce::last_diagnostics(self)
    }
    fn outline_overlap(&self, q: &[f64], samples: usize) -> contact::OutlineOverlap {
        ClearanceForce::outline_overlap(self, q, samples)
    }
}

/// `element` as a probe if it is a clearance joint on round or worn surfaces with the
/// run-time laws ([`RoundClearanceForce`] or [`WornClearanceForce`]): how recorders read the
/// joints of a system's elements, or of an observer frame's, without knowing which wear.
pub fn as_probe(element: &dyn ForceElement) -> Option<&dyn ClearanceProbe> {
    let any: &dyn std::any::Any = element;
    if let Some(round) = any.downcast_ref::<RoundClearanceForce>() {
        return Some(round);
    }
    any.downcast_ref::<WornClearanceForce>()
        .map(|worn| worn as &dyn ClearanceProbe)
}
