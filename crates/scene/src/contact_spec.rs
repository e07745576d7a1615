//! The contact model of a clearance joint as scene data (`clearance_joints[].contact`): one
//! tagged value per model, `model = "…"` choosing the variant and the rest of the table being
//! that model's own fields (serde refuses any other, naming it). Each variant is a module
//! here that builds its model, words it and checks its fields ([`model::ModelSpec`]); a new
//! model is its module and one line in the `contact_specs!` list below.

use serde::{Deserialize, Deserializer, Serialize};

use super::error::Validator;
use super::{ClearanceJointSpec, RunSettings};

mod foundation;
mod line_of_centres;
mod linear_spring;
mod model;
mod thin_gap;

pub use foundation::{FoundationSpec, LayerCalibration};
pub use line_of_centres::LineOfCentresSpec;
pub use linear_spring::LinearSpringSpec;
pub use thin_gap::ThinGapSpec;

use model::ModelSpec;

/// Declares [`ContactSpec`] with one variant per model (its `model` tag, its fields' type),
/// the tag-required form serde reads it through, and the dispatch to each variant's
/// [`ModelSpec`].
macro_rules! contact_specs {
    ($($(#[$doc:meta])* $variant:ident($spec:ty) = $tag:literal,)+) => {
        /// The contact model of a clearance joint, e.g. `contact = { model = "foundation" }`
        /// or `contact = { model = "foundation", layer_modulus = 5e14, width = 0.1, cells =
        /// 2000, reference_speed = 0.1 }`; `model` omitted is the foundation
        /// ([`ContactSpec::default`]).
        #[derive(Debug, Clone, Copy, PartialEq, Serialize)]
        #[serde(tag = "model")]
        pub enum ContactSpec {
            $($(#[$doc])* #[serde(rename = $tag)] $variant($spec),)+
        }

        /// [`ContactSpec`] as serde reads it once its tag is filled in.
        #[derive(Deserialize)]
        #[serde(tag = "model")]
        enum Tagged {
            $(#[serde(rename = $tag)] $variant($spec),)+
        }

        impl From<Tagged> for ContactSpec {
            fn from(tagged: Tagged) -> Self {
                match tagged {
                    $(Tagged::$variant(spec) => Self::$variant(spec),)+
                }
            }
        }

        $(impl From<$spec> for ContactSpec {
            fn from(spec: $spec) -> Self {
                Self::$variant(spec)
            }
        })+

        impl ContactSpec {
            /// The model's name as a scene writes it (`model = "…"`).
            pub fn name(&self) -> &'static str {
                match self {
                    $(Self::$variant(_) => $tag,)+
                }
            }

            fn spec(&self) -> &dyn ModelSpec {
                match self {
                    $(Self::$variant(spec) => spec,)+
                }
            }
        }
    };
}

contact_specs! {
    /// The elastic foundation over the true worn outlines (the default).
    Foundation(FoundationSpec) = "foundation",
    /// One contact point on the line of centres.
    LineOfCentres(LineOfCentresSpec) = "line-of-centres",
    /// A linear spring on the line of centres, `F = k δ`: the test model of the contact-model
    /// interface (`contact::LinearSpring`), no model of a real joint.
    LinearSpring(LinearSpringSpec) = "linear-spring",
    /// The foundation's layer with the thin-gap overlap on nodes in the bearing's frame.
    ThinGap(ThinGapSpec) = "thin-gap",
}

/// The foundation with every field defaulted: what a scene that names no model runs.
impl Default for ContactSpec {
    fn default() -> Self {
        Self::Foundation(FoundationSpec::default())
    }
}

/// A table without `model` is the default model's: serde's internally tagged enums refuse a
/// missing tag, so the tag is filled in before the variant is read (whose unknown fields
/// serde still refuses by name).
impl<'de> Deserialize<'de> for ContactSpec {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let mut table = toml::Table::deserialize(deserializer)?;
        let model = table
            .entry("model")
            .or_insert_with(|| Self::default().name().into())
            .clone();
        // The model is named beside serde's words, which say only what the table lacks or
        // holds too many of ("unknown field `cells`, there are no fields"); a choice given
        // another type is named with what it takes (`super::type_errors`).
        let tagged = toml::Value::Table(table.clone()).try_into::<Tagged>();
        tagged.map(Self::from).map_err(|e| {
            // A tag of another type is `model`'s; inside the tagged table serde keeps no path.
            let field = if model.is_str() { "" } else { "model" };
            let message = super::type_errors::readable_in::<Tagged>(e.message(), &table, field);
            let field = if field.is_empty() {
                String::new()
            } else {
                format!("{field}: ")
            };
            serde::de::Error::custom(format!("{field}{message} (model = {model})"))
        })
    }
}

impl ContactSpec {
    /// The line-of-centres model (it takes no other field).
    pub fn line_of_centres() -> Self {
        Self::LineOfCentres(LineOfCentresSpec {})
    }

    pub(super) fn is_default(&self) -> bool {
        *self == Self::default()
    }

    /// Checks the model's fields against the joint `joint` (at field path `p`) and the run's
    /// settings: each problem named by field, value and why.
    pub(super) fn check(
        &self,
        v: &mut Validator,
        p: &str,
        joint: &ClearanceJointSpec,
        run: &RunSettings,
    ) {
        self.spec().check(v, p, joint, run);
    }
}

impl ClearanceJointSpec {
    /// The contact model this joint's `contact` table names, with its defaults filled in
    /// from the joint (the foundation's calibrated layer, `wear.width`, `wear.cells`).
    pub fn contact_model(&self) -> Result<contact::ContactModelKind, contact::ContactError> {
        self.contact.spec().build(self)
    }

    /// The contact that runs at this joint in words: model, normal law and the damping it
    /// applies, friction. Printed beside the scene's description and in the report, so that
    /// every result names the laws behind it.
    pub fn contact_description(&self) -> String {
        format!(
            "{}; {}",
            self.contact.spec().describe(self),
            self.friction.description()
        )
    }
}
