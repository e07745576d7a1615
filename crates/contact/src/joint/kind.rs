//! The built-in contact models as one value a scene can choose at run time, with their state
//! ([`ModelTables`], [`ModelWorkspace`]) as one value each.

use serde::{Deserialize, Serialize};

use super::foundation::Foundation;
use super::line_of_centres::LineOfCentres;
use super::linear_spring::LinearSpring;
use super::model::{ContactKernel, ContactModel, ModelState, ShapeLimits, ValidityMeasure, Visit};
use super::pair::ContactPair;
use super::thin_gap::ThinGap;
use super::types::{ContactForces, ContactJacobian, JointState};
use crate::friction::FrictionLaw;
use crate::normal::NormalLaw;
use crate::surface::SurfaceProfile;

/// Declares [`ContactModelKind`] with one variant per built-in model and implements
/// [`ContactModel`] and [`ContactKernel`] on it by handing every call to the variant's model:
/// a new model is one line here.
macro_rules! contact_models {
    ($($(#[$doc:meta])* $variant:ident($model:ty),)+) => {
        /// Which contact model a clearance joint uses, chosen at run time; one run uses one
        /// model for its unworn and worn responses. Each variant is a model of its own
        /// module, and every call goes to it.
        #[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
        pub enum ContactModelKind {
            $($(#[$doc])* $variant($model),)+
        }

        /// The tables of a [`ContactModelKind`]: its model's, in the variant of that model.
        // One per joint, built with it and read in place: the foundation's kilobyte of sector
        // bounds is not worth a pointer to follow at every evaluation.
        #[allow(clippy::large_enum_variant)]
        #[derive(Clone, Debug)]
        pub enum ModelTables {
            $($(#[$doc])* $variant(<$model as ContactModel>::Tables),)+
        }

        /// The workspace of a [`ContactModelKind`]: its model's, in the variant of that model;
        /// [`ModelWorkspace::Empty`] (the default) or another model's evaluates with an empty
        /// one.
        #[derive(Clone, Debug, Default)]
        pub enum ModelWorkspace {
            /// None yet: evaluations keep nothing.
            #[default]
            Empty,
            $($(#[$doc])* $variant(<$model as ContactModel>::Workspace),)+
        }

        $(impl From<$model> for ContactModelKind {
            fn from(model: $model) -> Self {
                Self::$variant(model)
            }
        })+

        impl ContactModel for ContactModelKind {
            type Tables = ModelTables;
            type Workspace = ModelWorkspace;

            fn name(&self) -> &'static str {
                match self {
                    $(Self::$variant(m) => m.name(),)+
                }
            }

            fn tables<B: SurfaceProfile, P: SurfaceProfile, N, F>(
                &self,
                pair: &ContactPair<B, P, N, F>,
            ) -> ModelTables {
                match self {
                    $(Self::$variant(m) => ModelTables::$variant(m.tables(pair)),)+
                }
            }

            fn workspace(&self) -> ModelWorkspace {
                match self {
                    $(Self::$variant(m) => ModelWorkspace::$variant(m.workspace()),)+
                }
            }

            fn nodes(&self) -> Option<usize> {
                match self {
                    $(Self::$variant(m) => m.nodes(),)+
                }
            }

            fn validity_measures(&self) -> &'static [ValidityMeasure] {
                match self {
                    $(Self::$variant(m) => m.validity_measures(),)+
                }
            }

            fn shape_limits(&self) -> Option<ShapeLimits> {
                match self {
                    $(Self::$variant(m) => m.shape_limits(),)+
                }
            }
        }

        /// Hands the call to the variant's model with its own state: the tables of that model
        /// (built here if `state` holds another's) and its workspace (an empty one if `state`
        /// holds none of that model's).
        macro_rules! dispatch {
            ($self:ident, $pair:ident, $state:ident, |$m:ident, $model_state:ident| $call:expr) => {
                match $self {
                    $(Self::$variant($m) => {
                        let built;
                        let tables = match $state.tables {
                            ModelTables::$variant(tables) => tables,
                            _ => {
                                built = $m.tables($pair);
                                &built
                            }
                        };
                        let mut empty = None;
                        let workspace = match $state.workspace {
                            ModelWorkspace::$variant(workspace) => workspace,
                            _ => empty.insert(Default::default()),
                        };
                        let $model_state = ModelState { tables, workspace };
                        $call
                    })+
                }
            };
        }

        impl<B: SurfaceProfile, P: SurfaceProfile, N: NormalLaw, F: FrictionLaw>
            ContactKernel<B, P, N, F> for ContactModelKind
        {
            #[inline]
            fn forces(
                &self,
                pair: &ContactPair<B, P, N, F>,
                state: ModelState<'_, Self>,
                at: JointState,
                visit: Visit,
            ) -> ContactForces {
                dispatch!(self, pair, state, |m, own| m.forces(pair, own, at, visit))
            }

            fn forces_and_jacobian(
                &self,
                pair: &ContactPair<B, P, N, F>,
                state: ModelState<'_, Self>,
                at: JointState,
            ) -> (ContactForces, ContactJacobian) {
                dispatch!(self, pair, state, |m, own| m.forces_and_jacobian(pair, own, at))
            }

            #[inline]
            fn penetration(
                &self,
                pair: &ContactPair<B, P, N, F>,
                state: ModelState<'_, Self>,
                at: JointState,
            ) -> f64 {
                dispatch!(self, pair, state, |m, own| m.penetration(pair, own, at))
            }
        }
    };
}

contact_models! {
    /// One contact point on the line of centres, Hertz law on the local radii
    /// ([`super::line_of_centres`]); energy-consistent on worn surfaces but valid only while
    /// they stay smooth and shallow.
    LineOfCentres(LineOfCentres),
    /// An elastic layer over the true outlines ([`super::foundation`]).
    Foundation(Foundation),
    /// A linear spring on the line of centres ([`super::linear_spring`]): the test model of
    /// the interface.
    LinearSpring(LinearSpring),
    /// The foundation's layer with the thin-gap overlap on nodes fixed in the bearing's frame
    /// ([`super::thin_gap`]): the film-thickness form with its second-order terms.
    ThinGap(ThinGap),
}
