//! Planar constrained rigid-body dynamics: bodies, ideal joints, drivers and force elements;
//! assembly, kinematic analysis, and forward dynamics integrated by diffsol.
//!
//! # Model
//! Coordinates are `q = (x_k, y_k, θ_k)` per body (centroid and angle), state `y = (q, q̇)`.
//! A [`Model`] holds [`Body`]s (mass, centroidal inertia, approximate pose), ideal joints
//! (revolute between two [`Anchor`]s — a body-fixed or ground point —, prismatic with or
//! without locked rotation) and driving constraints on a coordinate or a joint
//! ([`DriveTarget`]) following a [`DriveFunction`] with exact derivatives ([`Constant`],
//! [`Ramp`], [`Harmonic`], or your own). Ground is `None` wherever a body or ground is asked
//! for (an [`Anchor`]'s body, [`ForcePartials::add_pair`]); [`Anchor::ground`] is shorthand.
//! Every `add_*` validates at once and returns a [`ModelError`] naming the item.
//! [`System::new`] compiles the model; force elements are added to the system.
//!
//! # Analyses
//! - [`System::assemble`]: Newton position analysis from the model's poses, then consistent
//!   velocities; [`AssemblyError`] names the constraints involved (non-convergence with the
//!   residual, rank loss with the dependent equations).
//! - [`System::kinematics`]: for a mechanism with no degree of freedom left, positions,
//!   velocities, accelerations and multipliers at the requested times, without integration.
//! - [`System::simulate`]: `M q̈ + Φ_qᵀλ = G`, `Φ_q q̈ = γ − 2αΦ̇ − β²Φ` ([`Baumgarte`], α = β
//!   = 50 by default), integrated by diffsol ([`Integrator`]: BDF by default, TR-BDF2,
//!   ESDIRK34, Tsit45) or by this crate's three-stage Radau IIA (`radau`), all through one step
//!   loop, with output at requested times by interpolation. The result carries
//!   [`SolverStatistics`], [`ConstraintDrift`], the multipliers of every frame (joint reactions:
//!   [`System::reaction`]) and an [`EnergyAudit`]. An [`Observer`] sees every output frame and
//!   every accepted step.
//! - [`SimulationOptions::formulation`]: the same dynamics integrated in body coordinates
//!   ([`Formulation::Cartesian`], the paper's augmented system) or in the relative coordinates
//!   of a spanning tree of the ideal joints ([`Formulation::JointCoordinates`]: no multipliers
//!   or drift where the joints form a tree; [`joint_coordinates`]). Outputs are Cartesian
//!   either way.
//!
//! # Force elements
//! Anything that is not an ideal constraint is a [`ForceElement`]: it adds generalized forces
//! and their partials `∂G/∂q`, `∂G/∂q̇` (the exact Jacobian needs them), and may have hooks
//! called on accepted steps, event functions on which steps land, and a potential energy.
//! [`Gravity`] is one; a two-body element (e.g. a clearance joint) reports its 6×12 Jacobian
//! through [`ForcePartials::add_pair`]. A system without some kind of element pays nothing for
//! it. During a run the elements are read by the right-hand side and mutated between steps;
//! afterwards they are back in the system ([`System::element`] returns the concrete type).
//!
//! ```
//! use multibody::*;
//!
//! /// A rotary damper on one body: moment −c θ̇.
//! struct RotaryDamper { body: BodyId, c: f64 }
//!
//! impl ForceElement for RotaryDamper {
//!     fn name(&self) -> &str { "rotary damper" }
//!     fn add_forces(&self, _t: f64, _q: &[f64], qd: &[f64], g: &mut [f64]) {
//!         let k = self.body.coordinate(Coordinate::Theta);
//!         g[k] -= self.c * qd[k];
//!     }
//!     fn add_partials(&self, _t: f64, _q: &[f64], _qd: &[f64], p: &mut ForcePartials<'_>) {
//!         let k = self.body.coordinate(Coordinate::Theta);
//!         p.add_dqd(k, k, -self.c);
//!     }
//! }
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! // A 1 m rod pinned at one end, released horizontal.
//! let mut model = Model::new();
//! let rod = Body::named("rod").with_mass(2.0).with_inertia(2.0 / 12.0).with_pose([0.5, 0.0, 0.0]);
//! let rod = model.add_body(rod)?;
//! model.add_revolute("pin", Anchor::ground(0.0, 0.0), Anchor::on(rod, -0.5, 0.0))?;
//! let gravity = Gravity::new(&model, [0.0, -9.81]);
//! let mut system = System::new(model)?;
//! system.add_element(Box::new(gravity));
//! let damper = system.add_element(Box::new(RotaryDamper { body: rod, c: 0.5 }));
//!
//! let (q, qd) = system.initial_guess();
//! let start = system.assemble(0.0, &q, &qd)?;
//! let options = SimulationOptions::until(1.0).with_output(OutputTimes::Every(0.01));
//! let result = system.simulate(&start, &options, &mut ())?;
//!
//! assert_eq!(result.trajectory.len(), 101);
//! assert!(result.drift.position < 1e-6);
//! let energy = result.energy.expect("audited by default");
//! assert!(energy.relative_residual() < 1e-3);
//! assert!(system.element::<RotaryDamper>(damper).is_some());
//! # Ok(())
//! # }
//! ```
//!
//! # Events and hooks
//! Element event functions are concatenated into diffsol's root function (only if some
//! element has any). When one changes sign, the step is cut back to the root
//! (`state_mut_back`), the outputs and energy quadrature up to it are taken from the
//! interpolant, every element's `on_accepted_step` runs, then the owner's `on_event`; the
//! derivative is re-evaluated and the integrator restarts from that state (BDF at order 1).
//! Roots are detected between step ends, so set [`SimulationOptions::max_step`] when an
//! event could begin and end within one step.
//!
//! # Exact Jacobian, and what it saves
//! Differentiating the augmented system gives
//! `K [dq̈; dλ] = [∂G − ∂(Φ_qᵀλ); ∂γ* − ∂(Φ_q q̈)]` with `K = [M Φ_qᵀ; Φ_q 0]`, so all `2n`
//! columns reuse the one factorization of `K` that the right-hand side needs anyway. `M` is
//! diagonal, so `K` is never formed: both solve through the `m × m` Schur complement
//! `S = Φ_q M⁻¹ Φ_qᵀ` (symmetric positive definite while `Φ_q` has full rank; Cholesky, a
//! pivot below 1e-12 of `S`'s largest diagonal entry is reported as singular): for
//! `K [x; μ] = [a; b]`, `S μ = Φ_q M⁻¹ a − b` and `x = M⁻¹(a − Φ_qᵀμ)`. Each constraint
//! equation supplies its gradient, Hessian and third derivative contracted with `q̇` (simple
//! trigonometric terms for planar point constraints). diffsol's closure API wants
//! Jacobian–vector products and assembles the dense matrix from `2n` of them at one `(t, y)`;
//! the closure caches the dense Jacobian of the last `(t, y)` and answers every product from
//! it (implementing diffsol's equation traits with `jacobian_inplace` would do the same with
//! more code; a probe at this size measured no gain).
//!
//! Without the cache every product would cost at least one augmented solve, so a Jacobian
//! would cost `2n` right-hand sides; with it, one factorization and `2n` triangular solves.
//! Differences pay `2n` factorizations and evaluate every force element `2n` more times, so the
//! saving grows with `n` and with the cost of the elements. Output frames cost one augmented
//! solve each (for `q̈` and `λ`); at a fine output interval they, not the integration, can
//! dominate a run. Measurements: docs/performance.md (`cargo bench -p multibody --bench
//! evaluation`).
//!
//! # The Newton iterations' linear solves
//! The implicit methods factor the iteration matrix `I − cJ` of the `2n` states; with
//! `J = [[0, I], [∂q̈/∂q, ∂q̈/∂q̇]]` its top block row is `[I, −cI]`, so [`SecondOrderLu`]
//! eliminates it and factors only the `n × n` matrix `I − c ∂q̈/∂q̇ − c² ∂q̈/∂q` (an eighth of
//! the LU's work). It checks that form on every factorization and falls back to the full LU
//! without it (its effect on an LGRES drive cycle: docs/performance.md).
//! [`SimulationOptions::linear_solver`] can put faer's sparse LU on that `n × n` matrix
//! ([`SparseSecondOrderLu`], symbolic analysis reused): faster for long mechanisms cut by
//! clearance joints (from ~80 bodies in docs/performance.md's scaling family), slower below.
//!
//! # Tolerances
//! `rtol` 1e-6 and [`AbsoluteTolerances`] per kind of variable (positions, angles, velocities,
//! angular velocities; defaults 1e-8 m, 1e-8 rad, 1e-6 m/s, 1e-6 rad/s). With clearance joints
//! scale the position tolerance to the clearance (docs/model.md §8). diffsol counts Newton failures
//! over the whole run, so by default they are not capped
//! ([`SimulationOptions::max_nonlinear_solver_failures`]); a run that cannot progress still stops on
//! its minimum step, its step budget or its wall-time budget.

#![warn(missing_docs)]

mod constraints;
pub mod drive;
mod dynamics;
mod error;
mod force;
mod formulation;
mod iteration;
pub mod joint_coordinates;
mod linalg;
mod model;
mod radau;
mod sparse_iteration;
mod state;
mod system;
mod trajectory;

pub use constraints::ConstraintOwner;
pub use drive::{Constant, DriveFunction, Harmonic, Ramp};
pub use dynamics::{
    ConstraintDrift, EnergyAudit, EventRecord, Frame, Integrator, JacobianMethod, LinearSolverKind,
    Observer, OutputTimes, SimulationOptions, SimulationResult, SolverStatistics,
};
pub use error::{
    AssemblyError, EvaluationError, KinematicsError, ModelError, SimulationError,
    SimulationErrorKind,
};
pub use force::{ElementId, ForceElement, ForcePartials, Gravity};
pub use formulation::{Equations, Formulation};
pub use iteration::SecondOrderLu;
pub use model::{
    Anchor, Body, BodyId, Coordinate, DriveTarget, Driver, DriverId, Joint, JointId, Model,
    RotationLock,
};
pub use sparse_iteration::SparseSecondOrderLu;
pub use state::{AbsoluteTolerances, State};
pub use system::evaluator::Evaluator;
pub use system::partials::{PartialEntry, PartialsCheck};
pub use system::{Baumgarte, System};
pub use trajectory::Trajectory;
