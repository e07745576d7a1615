//! The elastic material of a contact surface (Young's modulus and Poisson's ratio), as scene
//! files write it.

use crate::error::{ContactError, in_range, positive};

/// Isotropic linear-elastic material of a contact surface.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "MaterialParams", into = "MaterialParams")]
pub struct Material {
    params: MaterialParams,
}

/// Parameters of a [`Material`], as written in scene files ([`MaterialParams::new`]).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
#[non_exhaustive]
pub struct MaterialParams {
    /// Young's modulus `E > 0` (Pa).
    pub youngs_modulus: f64,
    /// Poisson's ratio `ν ∈ (−1, 0.5)`.
    pub poisson_ratio: f64,
}

impl MaterialParams {
    /// Young's modulus `E` (Pa) and Poisson's ratio `ν`, validated by [`Material::try_from`].
    pub fn new(youngs_modulus: f64, poisson_ratio: f64) -> Self {
        Self {
            youngs_modulus,
            poisson_ratio,
        }
    }
}

impl Material {
    /// A material with Young's modulus `E > 0` (Pa) and Poisson's ratio `ν ∈ (−1, 0.5)`.
    pub fn new(youngs_modulus: f64, poisson_ratio: f64) -> Result<Self, ContactError> {
        positive("youngs_modulus", youngs_modulus)?;
        in_range(
            "poisson_ratio",
            poisson_ratio,
            |nu| nu > -1.0 && nu < 0.5,
            "in (-1, 0.5)",
        )?;
        Ok(Self {
            params: MaterialParams {
                youngs_modulus,
                poisson_ratio,
            },
        })
    }

    /// The parameters.
    pub fn params(&self) -> MaterialParams {
        self.params
    }

    /// Compliance `ε = (1 − ν²)/E` (1/Pa).
    pub fn compliance(&self) -> f64 {
        let MaterialParams {
            youngs_modulus,
            poisson_ratio,
        } = self.params;
        (1.0 - poisson_ratio * poisson_ratio) / youngs_modulus
    }
}

impl TryFrom<MaterialParams> for Material {
    type Error = ContactError;
    fn try_from(params: MaterialParams) -> Result<Self, ContactError> {
        Self::new(params.youngs_modulus, params.poisson_ratio)
    }
}

impl From<Material> for MaterialParams {
    fn from(material: Material) -> Self {
        material.params
    }
}
