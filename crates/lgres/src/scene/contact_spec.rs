//! The contact model of a clearance joint as scene data (`clearance_joints[].contact`).

use serde::{Deserialize, Serialize};

use super::ClearanceJoint;

/// The contact model of a clearance joint, e.g. `contact = { model = "foundation" }` or
/// `contact = { model = "foundation", layer_modulus = 5e14, width = 0.1, cells = 2000 }`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// `foundation` (default) or `line-of-centres`.
    #[serde(default)]
    pub model: ContactModelName,
    /// Foundation: layer modulus `k`, Pa/m (pressure per metre of overlap). Default: the layer
    /// that reproduces the conformal Hertz force on round surfaces exactly at an overlap of 4 %
    /// of the clearance (`contact::Foundation::hertz_matched`; `k w ≈ 1.03 E*/√2`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layer_modulus: Option<f64>,
    /// Foundation: hinge width `w` the layer modulus acts over, m. Default: `wear.width`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width: Option<f64>,
    /// Foundation: nodes on the pin's outline. Default: `wear.cells` (each node a pin cell),
    /// else 1000; with wear a whole multiple of `wear.cells` (finer nodes resolve narrow
    /// contact zones; the outline between cell centres is linear).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cells: Option<usize>,
}

impl ContactSpec {
    /// The line-of-centres model (it takes no other field).
    pub fn line_of_centres() -> Self {
        Self {
            model: ContactModelName::LineOfCentres,
            ..Self::default()
        }
    }

    pub(super) fn is_default(&self) -> bool {
        *self == Self::default()
    }
}

/// The contact models a scene can name.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ContactModelName {
    /// The elastic foundation over the true worn outlines.
    #[default]
    Foundation,
    /// One contact point on the line of centres.
    LineOfCentres,
}

impl ClearanceJoint {
    /// The contact model this joint's `contact` table names, with its defaults filled in
    /// (the calibrated layer, `wear.width`, `wear.cells`).
    pub fn contact_model(&self) -> Result<contact::ContactModel, contact::ContactError> {
        let spec = &self.contact;
        if spec.model == ContactModelName::LineOfCentres {
            return Ok(contact::ContactModel::LineOfCentres);
        }
        let layer = match spec.layer_modulus {
            Some(k) => {
                let width = spec
                    .width
                    .or(self.wear.map(|w| w.width))
                    .unwrap_or(f64::NAN);
                contact::Foundation::with_layer(k, width)?
            }
            None => contact::Foundation::hertz_matched(
                &contact::Material::try_from(self.bearing_material)?,
                &contact::Material::try_from(self.pin_material)?,
                self.bearing_radius,
                self.pin_radius(),
                contact::DEFAULT_REFERENCE_OVERLAP,
            )?,
        };
        let cells = spec
            .cells
            .or(self.wear.map(|w| w.cells))
            .unwrap_or(contact::DEFAULT_FOUNDATION_CELLS);
        Ok(contact::ContactModel::Foundation(layer.with_cells(cells)?))
    }
}
