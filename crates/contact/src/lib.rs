//! Planar clearance revolute joints: kinematics, contact and friction laws, exact Jacobians.
//!
//! A clearance joint is a pin (on body *j*) rattling inside a bearing hole (on body *i*). This
//! crate turns the two bodies' states into the contact forces on them, their exact partial
//! derivatives for an implicit integrator, and the [`ContactDiagnostics`] that wear accumulation
//! and recorders need. It holds no integrator, and its evaluations allocate nothing: they work on
//! small `Copy` data and stack matrices, and what a model keeps is built before (its tables, when
//! the joint is) or owned by the caller (its workspace, [`ContactWorkspace`], made ready by
//! [`ClearanceJoint::workspace`]); `tests/allocation.rs` counts. The equations are those of
//! `docs/model.md` §1–2.
//!
//! # Pieces
//! - [`ClearanceJoint`]: the joint — geometry ([`JointSurface`]: body-fixed centre,
//!   [`SurfaceProfile`], [`Material`]) plus a [`NormalLaw`] and a [`FrictionLaw`].
//!   - [`ClearanceJoint::penetration`]: `δ` only, for event (root) functions;
//!   - [`ClearanceJoint::kinematics`]: eccentricity, `n`, `t`, local radii, contact points,
//!     material-point velocities, `v_n`, `v_t` ([`JointKinematics`]);
//!   - [`ClearanceJoint::forces`]: `(F_x, F_y, M)` on both bodies ([`ContactForces`]);
//!   - [`ClearanceJoint::forces_and_jacobian`]: the same plus the 6×12 [`ContactJacobian`], rows
//!     `[bearing F_x, F_y, M, pin F_x, F_y, M]`, columns
//!     `[x_i, y_i, θ_i, x_j, y_j, θ_j, ẋ_i, ẏ_i, θ̇_i, ẋ_j, ẏ_j, θ̇_j]`;
//!   - each also as `…_in`, with a [`ContactWorkspace`] the caller keeps for the joint: what
//!     the model's evaluations carry from one to the next (the foundation's overlap memory).
//! - Normal laws ([`normal`]): [`LankaraniNikravesh`] (the model's), [`HuntCrossley`],
//!   [`Flores`], undamped [`Hertz`]; clamped at `F_n ≥ 0`, with a floor on the onset velocity
//!   `δ̇⁻` that the caller keeps in an [`ImpactMemory`].
//! - Friction laws ([`friction`]): [`Ambrosio`] (Coulomb with a `v_0`–`v_1` ramp), [`Coulomb`],
//!   [`Frictionless`].
//! - [`NormalLawKind`] and [`FrictionLawKind`]: serde enums for scene files (validated on load);
//!   they implement the traits by dispatch. Concrete law types give static dispatch.
//!
//! Contact models (the [`ContactModel`] trait; [`ContactModelKind`] chooses a built-in one at
//! run time, set with [`ClearanceJoint::with_model`]): the line-of-centres model
//! ([`LineOfCentres`]; one contact point, below), the elastic foundation over the true
//! outlines ([`joint::foundation`], [`Foundation`]; the default here as in scenes,
//! [`joint::default_model`]) and the test model [`LinearSpring`]. The foundation is a
//! Winkler layer pressed by every node of the pin's outline, exact geometry at any
//! eccentricity, several contact zones, its loads per node ([`NodeLoad`],
//! [`ClearanceJoint::forces_visiting_nodes`]) for Archard wear. Each model returns forces, the
//! exact Jacobian and [`ContactDiagnostics`], and names the measures of its validity
//! ([`ValidityMeasure`]) and the shape limits it needs ([`ShapeLimits`]).
//!
//! Worn surfaces: the local radii in the contact direction replace the nominal ones in the
//! penetration and in the conformal Hertz stiffness, and the force is the gradient of the stored
//! energy `K(q) δ(q)ⁿ⁺¹/(n+1)`, so an elastic worn joint conserves energy; see [`joint`] for
//! this treatment, its limits ([`ClearanceJoint::outline_overlap`]) and the choice of sliding
//! velocity ([`SlidingVelocity`]).
//!
//! # Example
//! ```
//! use contact::{
//!     Ambrosio, BodyState, CircularProfile, ClearanceJoint, ImpactMemory, JointSurface,
//!     LankaraniNikravesh, LineOfCentres, Material,
//! };
//!
//! # fn main() -> Result<(), contact::ContactError> {
//! let steel = Material::new(200e9, 0.3)?;
//! // LGRES joint A: bearing radius 50 mm, clearance 0.5 mm, on the paper's one-point
//! // line-of-centres contact (a joint given no model runs the elastic foundation).
//! let joint = ClearanceJoint::new(
//!     JointSurface { centre: [0.0, 0.0], profile: CircularProfile::new(0.05), material: steel },
//!     JointSurface { centre: [0.0, 0.0], profile: CircularProfile::new(0.0495), material: steel },
//!     LankaraniNikravesh::new(0.9)?,
//!     Ambrosio::new(0.15, 1e-4, 1e-3)?,
//! )?
//! .with_model(LineOfCentres);
//! let bearing = BodyState::at_rest(0.0, 0.0, 0.0);
//! // Pin 10 µm into the bottom of the bearing, moving down at 0.1 m/s.
//! let pin = BodyState::new([0.0, -5.1e-4, 0.0], [0.0, -0.1, 0.0]);
//! assert!((joint.penetration(&bearing, &pin) - 1e-5).abs() < 1e-12);
//!
//! let memory = ImpactMemory::new(); // updated by the caller on accepted steps
//! let (forces, jacobian) = joint.forces_and_jacobian(&bearing, &pin, memory.onset_velocity());
//! assert!(forces.pin.y > 0.0); // pushed back up
//! assert_eq!(forces.bearing.y, -forces.pin.y);
//! assert!(jacobian[(4, 4)] < 0.0); // raising the pin lessens the push: ∂F_y,pin/∂y_j < 0
//! # Ok(())
//! # }
//! ```
//!
//! # Measured
//! - Restitution of a head-on two-body impact through the L–N law (RK4, 5e-8 s, test
//!   `tests/impact.rs`): c_e = 0.99 → 0.9901, 0.9 → 0.9132, 0.8 → 0.8471, 0.5 → 0.7252. L–N is
//!   derived for c_e near 1; below ~0.8 prefer [`Flores`].
//! - Kernel cost: `cargo bench -p contact --bench contact_kernel`; figures in
//!   docs/performance.md.

#![warn(missing_docs)]

pub mod diagnostics;
pub mod error;
pub mod friction;
pub mod joint;
pub mod material;
pub mod normal;
pub mod surface;

pub use diagnostics::ContactDiagnostics;
pub use error::ContactError;
pub use friction::{
    Ambrosio, AmbrosioParams, Coulomb, CoulombParams, FrictionForce, FrictionLaw, FrictionLawKind,
    FrictionLawParams, Frictionless,
};
pub use joint::{
    BodyState, ClearanceJoint, ContactForces, ContactJacobian, ContactKernel, ContactModel,
    ContactModelKind, ContactPair, ContactWorkspace, DEFAULT_FOUNDATION_CELLS,
    DEFAULT_REFERENCE_OVERLAP, Foundation, JointKinematics, JointState, JointSurface,
    LineOfCentres, LinearSpring, Material, MaterialParams, ModelState, NodeLoad, OutlineOverlap,
    Quadrature, ShapeLimits, SlidingVelocity, ThinGap, ValidityMeasure,
};
pub use normal::{
    DEFAULT_HERTZ_EXPONENT, DEFAULT_ONSET_VELOCITY_FLOOR, DampedHertzParams, Flores, Hertz,
    HertzParams, HuntCrossley, ImpactMemory, LankaraniNikravesh, NormalForce, NormalLaw,
    NormalLawKind, NormalLawParams, SpeedScale,
};
pub use surface::{CircularProfile, RadiusSample, SurfaceProfile, floor, wrap_angle};
