//! The elastic foundation's scene value: its layer, nodes, quadrature and damping speed.

use serde::{Deserialize, Serialize};

use super::super::error::Validator;
use super::super::limits::MAX_LENGTH;
use super::super::{ClearanceJointSpec, MAX_WEAR_CELLS, RunSettings};
use super::model::{ModelSpec, law_with_damping};

/// `contact = { model = "foundation", … }` (or no `model`): an elastic layer over the true
/// outlines (`contact::Foundation`). Every field is optional.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FoundationSpec {
    /// Layer modulus `k`, Pa/m (pressure per metre of overlap). Default: the layer that
    /// reproduces the conformal Hertz force on round surfaces exactly at an overlap of 4 % of
    /// the clearance (`contact::Foundation::hertz_matched`; `k w ≈ 1.03 E*/√2`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layer_modulus: Option<f64>,
    /// How the layer is calibrated when `layer_modulus` is not given: `paper` (default: the
    /// paper's Hertz law on round surfaces, matched at an overlap of 4 % of the clearance) or
    /// `pin-in-hole` (the conformal stiffness of Liu, Zhang & Yang's pin-in-hole law,
    /// proportional to the hinge width; docs/model.md §10.7).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layer: Option<LayerCalibration>,
    /// Hinge width `w` the layer modulus acts over, m. Default: `wear.width`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width: Option<f64>,
    /// Nodes on the pin's outline. Default: `wear.cells` (each node a pin cell), else 1000;
    /// with wear a whole multiple of `wear.cells` (finer nodes resolve narrow contact zones;
    /// the outline between cell centres is linear) or a divisor of it (each node spans whole
    /// cells and wears them evenly; not with linearly implicit sub-steps).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cells: Option<usize>,
    /// How the layer's energy is integrated over the nodes: `simpson` (default; needs an even
    /// node count) or `trapezoid` (`contact::Quadrature`; docs/model.md §10.1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub quadrature: Option<contact::Quadrature>,
    /// A reference impact speed `v_ref` for the layer's damping, m/s (optional). Each node's
    /// damping is the joint's normal law with the impact's onset velocity taken as at least
    /// this: impacts at `v_ref` or faster rebound with the law's restitution, slower ones are
    /// damped less (a constant dissipation coefficient). Default: none, the law's restitution
    /// at every speed (docs/model.md §10.6).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference_speed: Option<f64>,
}

/// How a foundation's layer is calibrated (`contact.layer`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum LayerCalibration {
    /// The paper's Hertz law on round surfaces (`contact::Foundation::hertz_matched`).
    #[default]
    Paper,
    /// Liu, Zhang & Yang's conformal pin-in-hole stiffness (`contact::Foundation::pin_in_hole`).
    PinInHole,
}

impl FoundationSpec {
    /// Stiffest layer (`contact.layer_modulus`), Pa/m: the stiffest solid (diamond, ~1.2e12
    /// Pa) over a layer of 10 µm. Stiffer layers only shorten the integrator's steps (a run of
    /// 1e20 Pa/m took minutes per cycle; 1e300 makes the mass matrix singular).
    pub const MAX_LAYER_MODULUS: f64 = 1e17;

    /// The node count at `joint`: `cells`, else `wear.cells` (a node per pin cell), else
    /// [`contact::DEFAULT_FOUNDATION_CELLS`].
    pub fn nodes(&self, joint: &ClearanceJointSpec) -> usize {
        self.cells
            .or(joint.wear.map(|w| w.cells))
            .unwrap_or(contact::DEFAULT_FOUNDATION_CELLS)
    }

    /// The hinge width at `joint`: `width`, else `wear.width` (validation requires one where
    /// the layer needs it).
    fn hinge_width(&self, joint: &ClearanceJointSpec) -> Option<f64> {
        self.width.or(joint.wear.map(|w| w.width))
    }

    /// The layer of `joint`: given (`layer_modulus` over the hinge width) or calibrated.
    fn layer(
        &self,
        joint: &ClearanceJointSpec,
    ) -> Result<contact::Foundation, contact::ContactError> {
        let width = || {
            self.hinge_width(joint)
                .ok_or(contact::ContactError::NonFinite {
                    parameter: "width",
                    value: f64::NAN,
                })
        };
        let material = |m| contact::Material::try_from(m);
        match (self.layer_modulus, self.layer.unwrap_or_default()) {
            (Some(k), _) => contact::Foundation::with_layer(k, width()?),
            (None, LayerCalibration::PinInHole) => contact::Foundation::pin_in_hole(
                &material(joint.bearing_material)?,
                &material(joint.pin_material)?,
                joint.pin_radius(),
                width()?,
            ),
            (None, LayerCalibration::Paper) => contact::Foundation::hertz_matched(
                &material(joint.bearing_material)?,
                &material(joint.pin_material)?,
                joint.bearing_radius,
                joint.pin_radius(),
                contact::DEFAULT_REFERENCE_OVERLAP,
            ),
        }
    }
}

impl FoundationSpec {
    /// The foundation of `joint`, its defaults filled in: the layer on its nodes, with its
    /// quadrature and damping speed (the thin-gap model's layer too).
    pub(super) fn foundation(
        &self,
        joint: &ClearanceJointSpec,
    ) -> Result<contact::Foundation, contact::ContactError> {
        let mut layer = self
            .layer(joint)?
            .with_quadrature(self.quadrature.unwrap_or_default())?
            .with_cells(self.nodes(joint))?;
        if let Some(speed) = self.reference_speed {
            layer = layer.with_reference_speed(speed)?;
        }
        Ok(layer)
    }

    /// The layer in words: its nodes, how it was calibrated, how it damps.
    pub(super) fn describe_layer(&self, joint: &ClearanceJointSpec) -> (String, String) {
        let layer = match (self.layer_modulus, self.layer.unwrap_or_default()) {
            (Some(_), _) => "given",
            (None, LayerCalibration::Paper) => "paper-calibrated",
            (None, LayerCalibration::PinInHole) => "pin-in-hole",
        };
        let damping = match self.reference_speed {
            None => "layer damping per node, its rate held within the impact's onset velocity"
                .to_string(),
            Some(v) => format!(
                "layer damping per node, its rate held within the impact's onset velocity \
                 floored at v_ref = {v} m/s"
            ),
        };
        (
            format!("{} nodes, {layer} layer", self.nodes(joint)),
            law_with_damping(joint, |_| damping),
        )
    }
}

impl ModelSpec for FoundationSpec {
    fn build(
        &self,
        joint: &ClearanceJointSpec,
    ) -> Result<contact::ContactModelKind, contact::ContactError> {
        Ok(self.foundation(joint)?.into())
    }

    fn describe(&self, joint: &ClearanceJointSpec) -> String {
        let (layer, law) = self.describe_layer(joint);
        format!("elastic-foundation contact ({layer}), {law}")
    }

    fn check(&self, v: &mut Validator, p: &str, joint: &ClearanceJointSpec, run: &RunSettings) {
        let q = format!("{p}.contact");
        if let Some(k) = self.layer_modulus {
            v.number(&format!("{q}.layer_modulus"), k, true);
            if self.width.is_none() && joint.wear.is_none() {
                v.push(
                    format!("{q}.width"),
                    "(none)",
                    "a layer_modulus needs the hinge width it acts over: give contact.width \
                     (or wear.width)",
                );
            }
        }
        if let Some(w) = self.width {
            v.number(&format!("{q}.width"), w, true);
        }
        if self.layer.is_some() && self.layer_modulus.is_some() {
            v.push(
                format!("{q}.layer"),
                "…",
                "a layer_modulus sets the layer itself: give one of the two",
            );
        } else if self.layer == Some(LayerCalibration::PinInHole)
            && self.width.is_none()
            && joint.wear.is_none()
        {
            v.push(
                format!("{q}.width"),
                "(none)",
                "the pin-in-hole layer needs the hinge width: give contact.width (or wear.width)",
            );
        }
        if let Some(speed) = self.reference_speed {
            v.number(&format!("{q}.reference_speed"), speed, true);
        }
        if let Some(n) = self.cells {
            self.check_cells(v, &q, joint, run, n);
        }
        // Simpson's quadrature pairs the nodes: their count (contact.cells, else wear.cells,
        // else the default) must be even.
        let nodes = self.nodes(joint);
        if self.quadrature.unwrap_or_default() == contact::Quadrature::Simpson
            && !nodes.is_multiple_of(2)
        {
            let (field, source) = if self.cells.is_some() {
                (format!("{q}.cells"), "contact.cells")
            } else {
                (format!("{p}.wear.cells"), "wear.cells, the nodes' default")
            };
            v.push(
                field,
                nodes,
                format!(
                    "Simpson's quadrature (the default) needs an even node count ({source}): \
                     give an even count or contact.quadrature = \"trapezoid\""
                ),
            );
        }
        if let Some(width) = self.width {
            v.at_most(&format!("{q}.width"), width, MAX_LENGTH, "m");
        }
        if let Some(k) = self.layer_modulus {
            v.at_most(
                &format!("{q}.layer_modulus"),
                k,
                Self::MAX_LAYER_MODULUS,
                "Pa/m (stiffer layers only shorten the integrator's steps)",
            );
        }
    }
}

impl FoundationSpec {
    /// `cells = n` against its range and the joint's wear grid.
    fn check_cells(
        &self,
        v: &mut Validator,
        q: &str,
        joint: &ClearanceJointSpec,
        run: &RunSettings,
        n: usize,
    ) {
        if !(8..=MAX_WEAR_CELLS).contains(&n) {
            v.push(
                format!("{q}.cells"),
                n,
                format!("must lie in 8..={MAX_WEAR_CELLS}"),
            );
        } else if let Some(w) = joint
            .wear
            .filter(|w| w.cells > 0 && !n.is_multiple_of(w.cells) && !w.cells.is_multiple_of(n))
        {
            v.push(
                format!("{q}.cells"),
                n,
                format!(
                    "must be a whole multiple of wear.cells ({}) or divide it: the foundation's \
                     nodes subdivide the pin's wear cells, or span whole ones",
                    w.cells
                ),
            );
        } else if let Some(w) = joint.wear.filter(|w| n < w.cells)
            && run.wear_stepping == wear::WearStepping::LinearlyImplicit
        {
            v.push(
                format!("{q}.cells"),
                n,
                format!(
                    "run.wear_stepping = \"linearly-implicit\" needs at least one node per wear \
                     cell ({}): its contact zones map each node to one cell",
                    w.cells
                ),
            );
        }
    }
}
