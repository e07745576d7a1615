//! Friction laws: the signed tangential force `F_t(v_t, F_n)` along the tangent `t`, with exact
//! partials. The kernel applies `−F_t t` to the pin, so a positive `F_t` opposes a positive
//! sliding velocity `v_t` of the pin on the bearing.

use crate::error::{ContactError, in_range, non_negative, through_params};
use crate::normal::SpeedScale;

/// Friction force and its partials.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrictionForce {
    /// Signed friction force `F_t` along `t` (N).
    pub force: f64,
    /// `∂F_t/∂v_t` (N·s/m).
    pub d_velocity: f64,
    /// `∂F_t/∂F_n` (–).
    pub d_normal_force: f64,
}

/// A friction law.
pub trait FrictionLaw {
    /// Friction for sliding velocity `tangential_velocity` (m/s) under `normal_force ≥ 0` (N).
    fn evaluate(&self, tangential_velocity: f64, normal_force: f64) -> FrictionForce;
}

/// Ambrósio's modified Coulomb law: `F_t = c_f c_d(|v_t|) F_n sgn(v_t)`, with the dynamic
/// correction `c_d` ramping linearly from 0 at `v_0` to 1 at `v_1`.
///
/// The ramp removes Coulomb's jump at `v_t = 0` (which a stiff integrator cannot step over)
/// while keeping the force zero for `|v_t| < v_0`, so stiction is *not* modelled: a pin may creep
/// slower than `v_0`. `∂F_t/∂v_t` is discontinuous at `v_0` and `v_1`; there the partial of the
/// lower-velocity side is returned.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "AmbrosioParams", into = "AmbrosioParams")]
pub struct Ambrosio {
    params: AmbrosioParams,
}

/// Parameters of [`Ambrosio`], as written in scene files ([`AmbrosioParams::new`]).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
#[non_exhaustive]
pub struct AmbrosioParams {
    /// Friction coefficient `c_f ≥ 0`.
    pub coefficient: f64,
    /// Velocity `v_0 ≥ 0` below which friction vanishes (m/s); also read as `v0`.
    #[serde(alias = "v0")]
    pub stick_velocity: f64,
    /// Velocity `v_1 > v_0` above which full Coulomb friction acts (m/s); also read as `v1`.
    #[serde(alias = "v1")]
    pub slip_velocity: f64,
}

impl AmbrosioParams {
    /// Coefficient `c_f` and ramp `v_0 < v_1` (m/s), validated by [`Ambrosio::from_params`].
    pub fn new(coefficient: f64, stick_velocity: f64, slip_velocity: f64) -> Self {
        Self {
            coefficient,
            stick_velocity,
            slip_velocity,
        }
    }
}

impl Ambrosio {
    /// The law with friction coefficient `c_f` and ramp `v_0 < v_1` (m/s).
    pub fn new(
        coefficient: f64,
        stick_velocity: f64,
        slip_velocity: f64,
    ) -> Result<Self, ContactError> {
        Self::from_params(AmbrosioParams {
            coefficient,
            stick_velocity,
            slip_velocity,
        })
    }

    /// The law from its parameters, validated.
    pub fn from_params(params: AmbrosioParams) -> Result<Self, ContactError> {
        non_negative("coefficient", params.coefficient)?;
        non_negative("stick_velocity", params.stick_velocity)?;
        in_range(
            "slip_velocity",
            params.slip_velocity,
            |v1| v1 > params.stick_velocity,
            "> stick_velocity",
        )?;
        Ok(Self { params })
    }

    /// The parameters.
    pub fn params(&self) -> AmbrosioParams {
        self.params
    }
}

impl FrictionLaw for Ambrosio {
    #[inline]
    fn evaluate(&self, tangential_velocity: f64, normal_force: f64) -> FrictionForce {
        let AmbrosioParams {
            coefficient,
            stick_velocity,
            slip_velocity,
        } = self.params;
        let speed = tangential_velocity.abs();
        if speed <= stick_velocity {
            return FrictionForce::default();
        }
        let sign = tangential_velocity.signum();
        let (correction, d_correction) = if speed <= slip_velocity {
            let width = slip_velocity - stick_velocity;
            ((speed - stick_velocity) / width, 1.0 / width)
        } else {
            (1.0, 0.0)
        };
        FrictionForce {
            force: coefficient * correction * normal_force * sign,
            // d|v|/dv = sgn(v), which cancels the sign of the force.
            d_velocity: coefficient * d_correction * normal_force,
            d_normal_force: coefficient * correction * sign,
        }
    }
}

through_params!(Ambrosio, AmbrosioParams);

/// Plain Coulomb friction `F_t = c_f F_n sgn(v_t)` (with `sgn(0) = 0`). Discontinuous at
/// `v_t = 0`: for comparisons and explicit integrators, not for stiff ones.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "CoulombParams", into = "CoulombParams")]
pub struct Coulomb {
    coefficient: f64,
}

/// Parameters of [`Coulomb`], as written in scene files ([`CoulombParams::new`]).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
#[non_exhaustive]
pub struct CoulombParams {
    /// Friction coefficient `c_f ≥ 0`.
    pub coefficient: f64,
}

impl CoulombParams {
    /// Coefficient `c_f` (≥ 0 when validated).
    pub fn new(coefficient: f64) -> Self {
        Self { coefficient }
    }
}

impl Coulomb {
    /// Coulomb friction with coefficient `c_f ≥ 0`.
    pub fn new(coefficient: f64) -> Result<Self, ContactError> {
        Ok(Self {
            coefficient: non_negative("coefficient", coefficient)?,
        })
    }

    /// The law from its parameters, validated.
    pub fn from_params(params: CoulombParams) -> Result<Self, ContactError> {
        Self::new(params.coefficient)
    }

    /// The parameters.
    pub fn params(&self) -> CoulombParams {
        CoulombParams::new(self.coefficient)
    }

    /// The coefficient `c_f`.
    pub fn coefficient(&self) -> f64 {
        self.coefficient
    }
}

impl FrictionLaw for Coulomb {
    #[inline]
    fn evaluate(&self, tangential_velocity: f64, normal_force: f64) -> FrictionForce {
        let sign = if tangential_velocity == 0.0 {
            0.0
        } else {
            tangential_velocity.signum()
        };
        FrictionForce {
            force: self.coefficient * normal_force * sign,
            d_velocity: 0.0,
            d_normal_force: self.coefficient * sign,
        }
    }
}

through_params!(Coulomb, CoulombParams);

/// No friction.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Frictionless;

impl FrictionLaw for Frictionless {
    #[inline]
    fn evaluate(&self, _tangential_velocity: f64, _normal_force: f64) -> FrictionForce {
        FrictionForce::default()
    }
}

/// Any friction law, chosen at run time (scene files). Serialised through
/// [`FrictionLawParams`], e.g.
/// `{"law": "ambrosio", "coefficient": 0.15, "stick_velocity": 1e-4, "slip_velocity": 1e-3}`
/// or `{"law": "none"}`, and validated on load.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "FrictionLawParams", into = "FrictionLawParams")]
pub enum FrictionLawKind {
    /// [`Ambrosio`].
    Ambrosio(Ambrosio),
    /// [`Coulomb`].
    Coulomb(Coulomb),
    /// [`Frictionless`].
    None,
}

/// The parameters of any friction law, as written in scene files (with a `law` tag): plain
/// data a scene can hold and edit before [`FrictionLawKind::from_params`] validates it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "law", rename_all = "snake_case")]
pub enum FrictionLawParams {
    /// [`Ambrosio`].
    Ambrosio(AmbrosioParams),
    /// [`Coulomb`].
    Coulomb(CoulombParams),
    /// [`Frictionless`].
    None,
}

impl FrictionLawParams {
    /// The law in words for a contact's description, e.g. `Ambrósio friction μ = 0.15`.
    pub fn description(&self) -> String {
        match self {
            Self::Ambrosio(p) => format!("Ambrósio friction μ = {}", p.coefficient),
            Self::Coulomb(p) => format!("Coulomb friction μ = {}", p.coefficient),
            Self::None => "no friction".to_string(),
        }
    }

    /// The speed below which the law changes behaviour: Ambrósio's stick velocity `v_0`.
    pub fn speed_scale(&self) -> Option<SpeedScale> {
        match self {
            Self::Ambrosio(p) => Some(SpeedScale {
                parameter: "stick_velocity",
                value: p.stick_velocity,
            }),
            Self::Coulomb(_) | Self::None => None,
        }
    }

    /// The same law with friction coefficient `coefficient` where it has one (no friction has
    /// none and is returned as it is).
    pub fn with_coefficient(self, coefficient: f64) -> Self {
        match self {
            Self::Ambrosio(p) => Self::Ambrosio(AmbrosioParams { coefficient, ..p }),
            Self::Coulomb(_) => Self::Coulomb(CoulombParams::new(coefficient)),
            Self::None => Self::None,
        }
    }
}

impl FrictionLawKind {
    /// The law from its parameters, validated (the error names the parameter).
    pub fn from_params(params: FrictionLawParams) -> Result<Self, ContactError> {
        Ok(match params {
            FrictionLawParams::Ambrosio(p) => Self::Ambrosio(Ambrosio::from_params(p)?),
            FrictionLawParams::Coulomb(p) => Self::Coulomb(Coulomb::from_params(p)?),
            FrictionLawParams::None => Self::None,
        })
    }

    /// The parameters.
    pub fn params(&self) -> FrictionLawParams {
        match self {
            Self::Ambrosio(law) => FrictionLawParams::Ambrosio(law.params()),
            Self::Coulomb(law) => FrictionLawParams::Coulomb(law.params()),
            Self::None => FrictionLawParams::None,
        }
    }
}

through_params!(FrictionLawKind, FrictionLawParams);

impl FrictionLaw for FrictionLawKind {
    #[inline]
    fn evaluate(&self, tangential_velocity: f64, normal_force: f64) -> FrictionForce {
        match self {
            Self::Ambrosio(law) => law.evaluate(tangential_velocity, normal_force),
            Self::Coulomb(law) => law.evaluate(tangential_velocity, normal_force),
            Self::None => Frictionless.evaluate(tangential_velocity, normal_force),
        }
    }
}

impl<L: FrictionLaw + ?Sized> FrictionLaw for &L {
    #[inline]
    fn evaluate(&self, tangential_velocity: f64, normal_force: f64) -> FrictionForce {
        (**self).evaluate(tangential_velocity, normal_force)
    }
}

impl From<Ambrosio> for FrictionLawKind {
    fn from(law: Ambrosio) -> Self {
        Self::Ambrosio(law)
    }
}

impl From<Coulomb> for FrictionLawKind {
    fn from(law: Coulomb) -> Self {
        Self::Coulomb(law)
    }
}

impl From<Frictionless> for FrictionLawKind {
    fn from(_: Frictionless) -> Self {
        Self::None
    }
}
