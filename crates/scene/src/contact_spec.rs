//! The contact model of a clearance joint as scene data (`clearance_joints[].contact`).

use serde::{Deserialize, Serialize};

use super::ClearanceJointSpec;

/// The contact model of a clearance joint, e.g. `contact = { model = "foundation" }` or
/// `contact = { model = "foundation", layer_modulus = 5e14, width = 0.1, cells = 2000,
/// reference_speed = 0.1 }`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// `foundation` (default), `line-of-centres` or `linear-spring` (the test model).
    #[serde(default)]
    pub model: ContactModelName,
    /// Foundation: layer modulus `k`, Pa/m (pressure per metre of overlap). Default: the layer
    /// that reproduces the conformal Hertz force on round surfaces exactly at an overlap of 4 %
    /// of the clearance (`contact::Foundation::hertz_matched`; `k w ≈ 1.03 E*/√2`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layer_modulus: Option<f64>,
    /// Foundation: how the layer is calibrated when `layer_modulus` is not given: `paper`
    /// (default: the paper's Hertz law on round surfaces, matched at an overlap of 4 % of the
    /// clearance) or `pin-in-hole` (the conformal stiffness of Liu, Zhang & Yang's pin-in-hole
    /// law, proportional to the hinge width; docs/model.md §10.7).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layer: Option<LayerCalibration>,
    /// Foundation: hinge width `w` the layer modulus acts over, m. Default: `wear.width`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width: Option<f64>,
    /// Foundation: nodes on the pin's outline. Default: `wear.cells` (each node a pin cell),
    /// else 1000; with wear a whole multiple of `wear.cells` (finer nodes resolve narrow
    /// contact zones; the outline between cell centres is linear) or a divisor of it (each
    /// node spans whole cells and wears them evenly; not with linearly implicit sub-steps).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cells: Option<usize>,
    /// Foundation: how the layer's energy is integrated over the nodes: `simpson` (default;
    /// needs an even node count) or `trapezoid` (`contact::Quadrature`; docs/model.md §10.1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub quadrature: Option<contact::Quadrature>,
    /// Foundation: a reference impact speed `v_ref` for the layer's damping, m/s (optional).
    /// Each node's damping is the joint's normal law with the impact's onset velocity taken as
    /// at least this: impacts at `v_ref` or faster rebound with the law's restitution, slower
    /// ones are damped less (a constant dissipation coefficient). Default: none, the law's
    /// restitution at every speed (docs/model.md §10.6).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference_speed: Option<f64>,
    /// Linear spring: its stiffness `k`, N/m (required there, refused elsewhere).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness: Option<f64>,
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

/// The contact models a scene can name.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ContactModelName {
    /// The elastic foundation over the true worn outlines.
    #[default]
    Foundation,
    /// One contact point on the line of centres.
    LineOfCentres,
    /// A linear spring on the line of centres, `F = k δ`: the test model of the contact-model
    /// interface (`contact::LinearSpring`), no model of a real joint.
    LinearSpring,
}

impl ContactModelName {
    /// The name as a scene writes it.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Foundation => "foundation",
            Self::LineOfCentres => "line-of-centres",
            Self::LinearSpring => "linear-spring",
        }
    }
}

impl ClearanceJointSpec {
    /// The foundation's node count: `contact.cells`, else `wear.cells` (a node per pin cell),
    /// else [`contact::DEFAULT_FOUNDATION_CELLS`].
    pub fn foundation_nodes(&self) -> usize {
        self.contact
            .cells
            .or(self.wear.map(|w| w.cells))
            .unwrap_or(contact::DEFAULT_FOUNDATION_CELLS)
    }

    /// The contact model this joint's `contact` table names, with its defaults filled in
    /// (the calibrated layer, `wear.width`, `wear.cells`).
    pub fn contact_model(&self) -> Result<contact::ContactModelKind, contact::ContactError> {
        let spec = &self.contact;
        match spec.model {
            ContactModelName::LineOfCentres => return Ok(contact::LineOfCentres.into()),
            ContactModelName::LinearSpring => {
                let stiffness = spec.stiffness.unwrap_or(f64::NAN);
                return Ok(contact::LinearSpring::new(stiffness)?.into());
            }
            ContactModelName::Foundation => {}
        }
        let width = spec
            .width
            .or(self.wear.map(|w| w.width))
            .unwrap_or(f64::NAN);
        let layer = match (spec.layer_modulus, spec.layer.unwrap_or_default()) {
            (Some(k), _) => contact::Foundation::with_layer(k, width)?,
            (None, LayerCalibration::PinInHole) => contact::Foundation::pin_in_hole(
                &contact::Material::try_from(self.bearing_material)?,
                &contact::Material::try_from(self.pin_material)?,
                self.pin_radius(),
                width,
            )?,
            (None, LayerCalibration::Paper) => contact::Foundation::hertz_matched(
                &contact::Material::try_from(self.bearing_material)?,
                &contact::Material::try_from(self.pin_material)?,
                self.bearing_radius,
                self.pin_radius(),
                contact::DEFAULT_REFERENCE_OVERLAP,
            )?,
        };
        let mut layer = layer
            .with_quadrature(spec.quadrature.unwrap_or_default())?
            .with_cells(self.foundation_nodes())?;
        if let Some(speed) = spec.reference_speed {
            layer = layer.with_reference_speed(speed)?;
        }
        Ok(contact::ContactModelKind::Foundation(layer))
    }
}

impl ClearanceJointSpec {
    /// The contact that runs at this joint in words: model, normal law and the damping it
    /// applies, friction. Printed beside the scene's description and in the report, so that
    /// every result names the laws behind it.
    pub fn contact_description(&self) -> String {
        use contact::NormalLawParams as N;
        let (law, damped) = match &self.normal_law {
            N::LankaraniNikravesh(p) => {
                (format!("Lankarani–Nikravesh c_e = {}", p.restitution), true)
            }
            N::HuntCrossley(p) => (format!("Hunt–Crossley c_e = {}", p.restitution), true),
            N::Flores(p) => (format!("Flores c_e = {}", p.restitution), true),
            N::Hertz(_) => ("Hertz (undamped)".to_string(), false),
        };
        let elastic = matches!(
            &self.normal_law,
            N::LankaraniNikravesh(p) | N::HuntCrossley(p) | N::Flores(p) if p.restitution >= 1.0
        );
        let damping = |speed: &str| {
            if damped && !elastic {
                format!("{law}, {speed}")
            } else {
                format!("{law}, no damping")
            }
        };
        let friction = match &self.friction {
            contact::FrictionLawParams::Ambrosio(p) => {
                format!("Ambrósio friction μ = {}", p.coefficient)
            }
            contact::FrictionLawParams::Coulomb(p) => {
                format!("Coulomb friction μ = {}", p.coefficient)
            }
            contact::FrictionLawParams::None => "no friction".to_string(),
        };
        let spec = &self.contact;
        let normal = match spec.model {
            ContactModelName::LineOfCentres => format!(
                "line-of-centres contact, {}",
                damping(&match &self.normal_law {
                    N::LankaraniNikravesh(p) | N::HuntCrossley(p) | N::Flores(p) => format!(
                        "damping on the impact's onset velocity (floor {} m/s)",
                        p.onset_velocity_floor
                    ),
                    N::Hertz(_) => String::new(),
                })
            ),
            ContactModelName::LinearSpring => format!(
                "linear-spring contact (k = {} N/m; no damping, no friction: the test model of \
                 the contact-model interface)",
                spec.stiffness.unwrap_or(f64::NAN)
            ),
            ContactModelName::Foundation => format!(
                "elastic-foundation contact ({} nodes, {} layer), {}",
                self.foundation_nodes(),
                match (spec.layer_modulus, spec.layer.unwrap_or_default()) {
                    (Some(_), _) => "given",
                    (None, LayerCalibration::Paper) => "paper-calibrated",
                    (None, LayerCalibration::PinInHole) => "pin-in-hole",
                },
                damping(&match spec.reference_speed {
                    None => "layer damping per node, its rate held within the impact's onset \
                             velocity"
                        .to_string(),
                    Some(v) => format!(
                        "layer damping per node, its rate held within the impact's onset \
                         velocity floored at v_ref = {v} m/s"
                    ),
                })
            ),
        };
        format!("{normal}; {friction}")
    }
}
