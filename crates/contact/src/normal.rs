//! Normal contact force laws: `F_n(K, δ, δ̇; δ̇⁻)` with exact partials.
//!
//! All laws here have the form `F_n = K δⁿ (1 + χ δ̇ / δ̇⁻)` with a hysteresis factor `χ` that
//! depends on the coefficient of restitution `c_e` (`χ = 0` for pure Hertz), i.e. the damping
//! coefficient is `D = χ K / δ̇⁻`. They are linear in the stiffness `K`, which is why the partial
//! with respect to `K` is simply `F_n / K`: the joint kernel needs it because the stiffness of a
//! worn joint depends on the contact direction.
//!
//! **Onset velocity.** `δ̇⁻` is the normal velocity at the instant the current contact began. It
//! is state the caller keeps (see [`ImpactMemory`]); the laws treat it as a constant parameter,
//! so it carries no partial. A contact that starts with `δ̇⁻ ≈ 0` (a pin settling gently onto
//! the bearing) would make `D` unbounded, so each damped law floors it at
//! `onset_velocity_floor` (default [`DEFAULT_ONSET_VELOCITY_FLOOR`] = 1e-4 m/s): the damping is
//! then at most `χ K δⁿ δ̇ / 1e-4`, large but finite, and the clamp below keeps it from pulling.
//!
//! **Clamp.** With a bounded `δ̇⁻` the damping term turns the force adhesive when the pin
//! separates fast (`δ̇ < −δ̇⁻/χ`). A contact never pulls: every law returns
//! `F_n = max(0, ·)`, with all partials zero where it clamps.

use crate::diagnostics::ContactDiagnostics;
use crate::error::{ContactError, in_range, positive, through_params};

/// Default floor on the onset velocity `δ̇⁻` of the damped laws (m/s).
pub const DEFAULT_ONSET_VELOCITY_FLOOR: f64 = 1e-4;
/// Default Hertz exponent `n` (point/line contact of elastic cylinders as used by the model).
pub const DEFAULT_HERTZ_EXPONENT: f64 = 1.5;

/// Normal force and its partials.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NormalForce {
    /// `F_n ≥ 0` (N).
    pub force: f64,
    /// `∂F_n/∂δ` (N/m).
    pub d_penetration: f64,
    /// `∂F_n/∂δ̇` (N·s/m).
    pub d_velocity: f64,
    /// `∂F_n/∂K` (m^n).
    pub d_stiffness: f64,
    /// The conservative part `F_e` of the force (N), `K δⁿ` here, even where the damped force
    /// clamps to zero: the energy books and the worn-surface force need it.
    pub elastic: f64,
    /// The potential `V` of the conservative part (J), with `∂V/∂δ = F_e`; `K δⁿ⁺¹/(n + 1)`
    /// here. Linear in `K` like the force, so `∂V/∂K = V/K`.
    pub potential: f64,
}

/// A normal contact force law.
///
/// The force must be linear in the stiffness `K` and split into a conservative part `F_e(δ)`
/// with potential `V(δ)` (reported in [`NormalForce`]) and a dissipative rest: a worn joint's
/// stiffness depends on the contact direction, and its energy-consistent force needs `∂V/∂K`.
pub trait NormalLaw {
    /// Force for stiffness `stiffness` (N/m^n), penetration `penetration ≥ 0` (m), penetration
    /// rate `velocity` (m/s) and onset velocity `onset_velocity` (m/s, floored by the law).
    /// Negative penetration gives zero.
    fn evaluate(
        &self,
        stiffness: f64,
        penetration: f64,
        velocity: f64,
        onset_velocity: f64,
    ) -> NormalForce;

    /// The hysteresis factor `φ(δ̇) = F_n/(K δⁿ)` (clamped at 0) and `∂φ/∂δ̇`: the damping of a
    /// law whose force is `K δⁿ φ(δ̇)`, applied per node by the foundation contact. Every law
    /// here has that form, so the default reads it off [`evaluate`](Self::evaluate) at
    /// `K = δ = 1`.
    fn hysteresis(&self, velocity: f64, onset_velocity: f64) -> (f64, f64) {
        let unit = self.evaluate(1.0, 1.0, velocity, onset_velocity);
        (unit.force, unit.d_velocity)
    }

    /// The onset velocity the law divides by for a recorded `onset_velocity`: its magnitude,
    /// floored by a damped law (the default, for laws without a floor, is the magnitude). A
    /// normal rate within `±` this value is the range one impact spans.
    fn effective_onset(&self, onset_velocity: f64) -> f64 {
        onset_velocity.abs()
    }
}

/// The shared kernel `F = K δⁿ (1 + damping_rate · δ̇)`, clamped at zero.
#[inline]
fn power_law_with_damping(
    stiffness: f64,
    penetration: f64,
    velocity: f64,
    exponent: f64,
    damping_rate: f64,
) -> NormalForce {
    if penetration <= 0.0 {
        return NormalForce::default();
    }
    let delta_n = penetration.powf(exponent);
    let elastic = stiffness * delta_n;
    let potential = elastic * penetration / (exponent + 1.0);
    let (factor, d_factor) = damping_factor(velocity, damping_rate);
    if factor <= 0.0 {
        return NormalForce {
            elastic,
            potential,
            ..NormalForce::default()
        };
    }
    NormalForce {
        force: elastic * factor,
        d_penetration: exponent * elastic / penetration * factor,
        d_velocity: elastic * d_factor,
        d_stiffness: delta_n * factor,
        elastic,
        potential,
    }
}

/// The damping factor `1 + damping_rate · δ̇` of [`power_law_with_damping`] and its `δ̇`
/// partial, both 0 where it clamps: the laws' [`NormalLaw::hysteresis`], which the foundation
/// asks for per node (the default's `evaluate(1, 1, …)` costs a `powf` for the same numbers).
#[inline]
fn damping_factor(velocity: f64, damping_rate: f64) -> (f64, f64) {
    let factor = 1.0 + damping_rate * velocity;
    if factor <= 0.0 {
        (0.0, 0.0)
    } else {
        (factor, damping_rate)
    }
}

fn validate_exponent(exponent: f64) -> Result<f64, ContactError> {
    // n ≥ 1 keeps ∂F/∂δ bounded at δ = 0, which a stiff integrator needs.
    in_range("exponent", exponent, |n| n >= 1.0, ">= 1")
}

fn validate_restitution(restitution: f64) -> Result<f64, ContactError> {
    in_range(
        "restitution",
        restitution,
        |c| c > 0.0 && c <= 1.0,
        "in (0, 1]",
    )
}

/// Parameters of a damped Hertz law, as written in scene files: [`DampedHertzParams::new`] and
/// the `with_*` methods (new parameters can be added without breaking callers, so it is no literal outside this crate).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
#[non_exhaustive]
pub struct DampedHertzParams {
    /// Coefficient of restitution `c_e ∈ (0, 1]`.
    pub restitution: f64,
    /// Hertz exponent `n ≥ 1` (default 1.5).
    #[serde(default = "default_exponent")]
    pub exponent: f64,
    /// Floor on the onset velocity `δ̇⁻` (m/s, > 0, default 1e-4). Also read as
    /// `impact_velocity_floor`, the name older scene files use.
    #[serde(default = "default_onset_floor", alias = "impact_velocity_floor")]
    pub onset_velocity_floor: f64,
}

fn default_exponent() -> f64 {
    DEFAULT_HERTZ_EXPONENT
}

fn default_onset_floor() -> f64 {
    DEFAULT_ONSET_VELOCITY_FLOOR
}

impl DampedHertzParams {
    /// Defaults (n = 1.5, floor 1e-4 m/s) for restitution `c_e`.
    pub fn new(restitution: f64) -> Self {
        Self {
            restitution,
            exponent: DEFAULT_HERTZ_EXPONENT,
            onset_velocity_floor: DEFAULT_ONSET_VELOCITY_FLOOR,
        }
    }

    /// The same parameters with Hertz exponent `exponent` (≥ 1 when validated).
    pub fn with_exponent(mut self, exponent: f64) -> Self {
        self.exponent = exponent;
        self
    }

    /// The same parameters with onset-velocity floor `floor` (m/s, > 0 when validated).
    pub fn with_onset_velocity_floor(mut self, floor: f64) -> Self {
        self.onset_velocity_floor = floor;
        self
    }

    fn validated(self) -> Result<Self, ContactError> {
        validate_restitution(self.restitution)?;
        validate_exponent(self.exponent)?;
        positive("onset_velocity_floor", self.onset_velocity_floor)?;
        Ok(self)
    }
}

/// Defines one damped Hertz law from its hysteresis factor `χ(c_e)`: the three laws differ only
/// there, so they share everything else.
macro_rules! damped_hertz_law {
    ($(#[$doc:meta])* $name:ident, |$ce:ident| $hysteresis:expr) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
        #[serde(try_from = "DampedHertzParams", into = "DampedHertzParams")]
        pub struct $name {
            params: DampedHertzParams,
            hysteresis: f64,
        }

        impl $name {
            /// The law with restitution `c_e ∈ (0, 1]`, exponent 1.5 and onset floor 1e-4 m/s.
            pub fn new(restitution: f64) -> Result<Self, ContactError> {
                Self::from_params(DampedHertzParams::new(restitution))
            }

            /// The law with every parameter given.
            pub fn from_params(params: DampedHertzParams) -> Result<Self, ContactError> {
                let params = params.validated()?;
                let $ce = params.restitution;
                Ok(Self { params, hysteresis: $hysteresis })
            }

            /// The same law with Hertz exponent `exponent ≥ 1`.
            pub fn with_exponent(self, exponent: f64) -> Result<Self, ContactError> {
                Self::from_params(DampedHertzParams { exponent, ..self.params })
            }

            /// The same law with onset-velocity floor `floor > 0` (m/s).
            pub fn with_onset_velocity_floor(self, floor: f64) -> Result<Self, ContactError> {
                Self::from_params(DampedHertzParams { onset_velocity_floor: floor, ..self.params })
            }

            /// The parameters.
            pub fn params(&self) -> DampedHertzParams {
                self.params
            }

            /// Hysteresis factor `χ = D δ̇⁻ / K`.
            pub fn hysteresis_factor(&self) -> f64 {
                self.hysteresis
            }
        }

        impl NormalLaw for $name {
            #[inline]
            fn evaluate(
                &self,
                stiffness: f64,
                penetration: f64,
                velocity: f64,
                onset_velocity: f64,
            ) -> NormalForce {
                // `max` also maps a NaN onset to the floor.
                let onset = onset_velocity.abs().max(self.params.onset_velocity_floor);
                power_law_with_damping(
                    stiffness,
                    penetration,
                    velocity,
                    self.params.exponent,
                    self.hysteresis / onset,
                )
            }

            #[inline]
            fn hysteresis(&self, velocity: f64, onset_velocity: f64) -> (f64, f64) {
                damping_factor(velocity, self.hysteresis / self.effective_onset(onset_velocity))
            }

            #[inline]
            fn effective_onset(&self, onset_velocity: f64) -> f64 {
                // `max` also maps a NaN onset to the floor.
                onset_velocity.abs().max(self.params.onset_velocity_floor)
            }
        }

        through_params!($name, DampedHertzParams);
    };
}

damped_hertz_law!(
    /// Hertz with Lankarani–Nikravesh damping: `D = 3K(1 − c_e²)/(4 δ̇⁻)`. The model's default.
    /// Derived for `c_e` near 1; its effective restitution overshoots slightly (≈ 0.913 at 0.9).
    LankaraniNikravesh,
    |ce| 0.75 * (1.0 - ce * ce)
);

damped_hertz_law!(
    /// Hertz with Hunt–Crossley damping: `D = 3K(1 − c_e)/(2 δ̇⁻)`.
    HuntCrossley,
    |ce| 1.5 * (1.0 - ce)
);

damped_hertz_law!(
    /// Hertz with the damping of Flores et al. (2011): `D = 8K(1 − c_e)/(5 c_e δ̇⁻)`, meant to hold
    /// also for low restitution.
    Flores,
    |ce| 1.6 * (1.0 - ce) / ce
);

/// Undamped Hertz: `F_n = K δⁿ` (elastic, energy-conserving).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "HertzParams", into = "HertzParams")]
pub struct Hertz {
    exponent: f64,
}

/// Parameters of [`Hertz`], as written in scene files ([`HertzParams::new`]).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
#[non_exhaustive]
pub struct HertzParams {
    /// Hertz exponent `n ≥ 1` (default 1.5).
    #[serde(default = "default_exponent")]
    pub exponent: f64,
}

impl HertzParams {
    /// Parameters with Hertz exponent `exponent` (≥ 1 when validated).
    pub fn new(exponent: f64) -> Self {
        Self { exponent }
    }
}

impl Hertz {
    /// Hertz with exponent `exponent ≥ 1`.
    pub fn new(exponent: f64) -> Result<Self, ContactError> {
        Ok(Self {
            exponent: validate_exponent(exponent)?,
        })
    }

    /// The law from its parameters, validated.
    pub fn from_params(params: HertzParams) -> Result<Self, ContactError> {
        Self::new(params.exponent)
    }

    /// The parameters.
    pub fn params(&self) -> HertzParams {
        HertzParams::new(self.exponent)
    }

    /// The exponent `n`.
    pub fn exponent(&self) -> f64 {
        self.exponent
    }
}

impl Default for Hertz {
    fn default() -> Self {
        Self {
            exponent: DEFAULT_HERTZ_EXPONENT,
        }
    }
}

impl NormalLaw for Hertz {
    #[inline]
    fn evaluate(
        &self,
        stiffness: f64,
        penetration: f64,
        velocity: f64,
        _onset: f64,
    ) -> NormalForce {
        power_law_with_damping(stiffness, penetration, velocity, self.exponent, 0.0)
    }

    #[inline]
    fn hysteresis(&self, velocity: f64, _onset: f64) -> (f64, f64) {
        damping_factor(velocity, 0.0)
    }
}

through_params!(Hertz, HertzParams);

/// Any normal law, chosen at run time (scene files). Serialised through [`NormalLawParams`],
/// e.g. `{"law": "lankarani_nikravesh", "restitution": 0.9}`, and validated on load. Generic
/// code that knows its law at compile time can use the law types directly and skip the dispatch.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "NormalLawParams", into = "NormalLawParams")]
pub enum NormalLawKind {
    /// [`LankaraniNikravesh`].
    LankaraniNikravesh(LankaraniNikravesh),
    /// [`HuntCrossley`].
    HuntCrossley(HuntCrossley),
    /// [`Flores`].
    Flores(Flores),
    /// [`Hertz`].
    Hertz(Hertz),
}

/// The parameters of any normal law, as written in scene files (with a `law` tag): plain data a
/// scene can hold and edit before [`NormalLawKind::from_params`] validates it. The tags
/// `hertz-lankarani-nikravesh` and `hunt-crossley` of older scene files are read too.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "law", rename_all = "snake_case")]
pub enum NormalLawParams {
    /// [`LankaraniNikravesh`].
    #[serde(alias = "hertz-lankarani-nikravesh")]
    LankaraniNikravesh(DampedHertzParams),
    /// [`HuntCrossley`].
    #[serde(alias = "hunt-crossley")]
    HuntCrossley(DampedHertzParams),
    /// [`Flores`].
    Flores(DampedHertzParams),
    /// [`Hertz`].
    Hertz(HertzParams),
}

/// A speed below which a law changes behaviour (m/s), with the name of the parameter that
/// sets it: an integrator whose velocity error exceeds it cannot tell the law's regimes apart.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpeedScale {
    /// The parameter, as a scene names it.
    pub parameter: &'static str,
    /// Its value (m/s).
    pub value: f64,
}

impl NormalLawParams {
    /// The law in words for a contact's description, e.g. `Lankarani–Nikravesh c_e = 0.9`.
    pub fn description(&self) -> String {
        match self {
            Self::LankaraniNikravesh(p) => format!("Lankarani–Nikravesh c_e = {}", p.restitution),
            Self::HuntCrossley(p) => format!("Hunt–Crossley c_e = {}", p.restitution),
            Self::Flores(p) => format!("Flores c_e = {}", p.restitution),
            Self::Hertz(_) => "Hertz (undamped)".to_string(),
        }
    }

    /// The floor on the onset velocity its damping divides by (m/s), for a law that damps
    /// (restitution below 1); `None` for an elastic one.
    pub fn damping_onset_floor(&self) -> Option<f64> {
        match self {
            Self::LankaraniNikravesh(p) | Self::HuntCrossley(p) | Self::Flores(p) => {
                let elastic = p.restitution >= 1.0;
                (!elastic).then_some(p.onset_velocity_floor)
            }
            Self::Hertz(_) => None,
        }
    }

    /// The speed below which the law changes behaviour: a damped law's onset-velocity floor.
    pub fn speed_scale(&self) -> Option<SpeedScale> {
        match self {
            Self::LankaraniNikravesh(p) | Self::HuntCrossley(p) | Self::Flores(p) => {
                Some(SpeedScale {
                    parameter: "onset_velocity_floor",
                    value: p.onset_velocity_floor,
                })
            }
            Self::Hertz(_) => None,
        }
    }

    /// The same law with restitution `c_e` where it has one (an undamped law has none and is
    /// returned as it is).
    pub fn with_restitution(self, restitution: f64) -> Self {
        match self {
            Self::LankaraniNikravesh(p) => {
                Self::LankaraniNikravesh(DampedHertzParams { restitution, ..p })
            }
            Self::HuntCrossley(p) => Self::HuntCrossley(DampedHertzParams { restitution, ..p }),
            Self::Flores(p) => Self::Flores(DampedHertzParams { restitution, ..p }),
            Self::Hertz(p) => Self::Hertz(p),
        }
    }
}

impl NormalLawKind {
    /// The law from its parameters, validated (the error names the parameter).
    pub fn from_params(params: NormalLawParams) -> Result<Self, ContactError> {
        Ok(match params {
            NormalLawParams::LankaraniNikravesh(p) => {
                Self::LankaraniNikravesh(LankaraniNikravesh::from_params(p)?)
            }
            NormalLawParams::HuntCrossley(p) => Self::HuntCrossley(HuntCrossley::from_params(p)?),
            NormalLawParams::Flores(p) => Self::Flores(Flores::from_params(p)?),
            NormalLawParams::Hertz(p) => Self::Hertz(Hertz::from_params(p)?),
        })
    }

    /// The parameters.
    pub fn params(&self) -> NormalLawParams {
        match self {
            Self::LankaraniNikravesh(law) => NormalLawParams::LankaraniNikravesh(law.params()),
            Self::HuntCrossley(law) => NormalLawParams::HuntCrossley(law.params()),
            Self::Flores(law) => NormalLawParams::Flores(law.params()),
            Self::Hertz(law) => NormalLawParams::Hertz(law.params()),
        }
    }
}

through_params!(NormalLawKind, NormalLawParams);

impl NormalLaw for NormalLawKind {
    #[inline]
    fn evaluate(&self, stiffness: f64, penetration: f64, velocity: f64, onset: f64) -> NormalForce {
        match self {
            Self::LankaraniNikravesh(law) => law.evaluate(stiffness, penetration, velocity, onset),
            Self::HuntCrossley(law) => law.evaluate(stiffness, penetration, velocity, onset),
            Self::Flores(law) => law.evaluate(stiffness, penetration, velocity, onset),
            Self::Hertz(law) => law.evaluate(stiffness, penetration, velocity, onset),
        }
    }

    #[inline]
    fn hysteresis(&self, velocity: f64, onset: f64) -> (f64, f64) {
        match self {
            Self::LankaraniNikravesh(law) => law.hysteresis(velocity, onset),
            Self::HuntCrossley(law) => law.hysteresis(velocity, onset),
            Self::Flores(law) => law.hysteresis(velocity, onset),
            Self::Hertz(law) => law.hysteresis(velocity, onset),
        }
    }

    #[inline]
    fn effective_onset(&self, onset: f64) -> f64 {
        match self {
            Self::LankaraniNikravesh(law) => law.effective_onset(onset),
            Self::HuntCrossley(law) => law.effective_onset(onset),
            Self::Flores(law) => law.effective_onset(onset),
            Self::Hertz(law) => law.effective_onset(onset),
        }
    }
}

impl<L: NormalLaw + ?Sized> NormalLaw for &L {
    #[inline]
    fn evaluate(&self, stiffness: f64, penetration: f64, velocity: f64, onset: f64) -> NormalForce {
        (**self).evaluate(stiffness, penetration, velocity, onset)
    }

    #[inline]
    fn hysteresis(&self, velocity: f64, onset: f64) -> (f64, f64) {
        (**self).hysteresis(velocity, onset)
    }

    #[inline]
    fn effective_onset(&self, onset: f64) -> f64 {
        (**self).effective_onset(onset)
    }
}

/// The onset velocity `δ̇⁻` of the current contact: the memory a damped law needs.
///
/// Call [`ImpactMemory::update`] on every accepted step (or at a located `δ = 0` event) with the
/// diagnostics before and after it. When the joint goes from free to contact, the normal velocity
/// at the crossing is interpolated linearly in penetration between the two states (exact when the
/// step ends on the event); while in contact the value is kept; on separation it is forgotten.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ImpactMemory {
    onset_velocity: Option<f64>,
}

impl ImpactMemory {
    /// No contact recorded yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// The recorded onset velocity, `None` when no contact is under way (or it started before
    /// any step was seen). Pass it to the joint kernel.
    pub fn onset_velocity(&self) -> Option<f64> {
        self.onset_velocity
    }

    /// Advances the memory over one accepted step from `previous` to `current`.
    pub fn update(&mut self, previous: &ContactDiagnostics, current: &ContactDiagnostics) {
        if !current.in_contact {
            self.onset_velocity = None;
        } else if !previous.in_contact || self.onset_velocity.is_none() {
            self.onset_velocity = Some(crossing_velocity(previous, current));
        }
    }
}

/// Normal velocity where the penetration crosses zero between two states (linear in δ).
fn crossing_velocity(previous: &ContactDiagnostics, current: &ContactDiagnostics) -> f64 {
    let span = current.penetration - previous.penetration;
    if previous.in_contact || span <= 0.0 {
        return current.normal_velocity;
    }
    let fraction = (-previous.penetration / span).clamp(0.0, 1.0);
    previous.normal_velocity + fraction * (current.normal_velocity - previous.normal_velocity)
}

/// Each law converts into [`NormalLawKind`], so APIs that store the run-time choice accept
/// `impl Into<NormalLawKind>`.
macro_rules! into_normal_kind {
    ($($law:ident),*) => {$(
        impl From<$law> for NormalLawKind {
            fn from(law: $law) -> Self {
                Self::$law(law)
            }
        }
    )*};
}
into_normal_kind!(LankaraniNikravesh, HuntCrossley, Flores, Hertz);
