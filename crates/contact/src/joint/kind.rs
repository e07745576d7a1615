//! The built-in contact models as one value a scene can choose at run time.

use serde::{Deserialize, Serialize};

use super::foundation::Foundation;
use super::line_of_centres::LineOfCentres;
use super::linear_spring::LinearSpring;
use super::model::{ContactKernel, ContactModel, ShapeLimits, ValidityMeasure, Visit};
use super::pair::ContactPair;
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

        $(impl From<$model> for ContactModelKind {
            fn from(model: $model) -> Self {
                Self::$variant(model)
            }
        })+

        impl ContactModel for ContactModelKind {
            fn name(&self) -> &'static str {
                match self {
                    $(Self::$variant(m) => m.name(),)+
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

        impl<B: SurfaceProfile, P: SurfaceProfile, N: NormalLaw, F: FrictionLaw>
            ContactKernel<B, P, N, F> for ContactModelKind
        {
            #[inline]
            fn forces(&self, pair: &ContactPair<B, P, N, F>, at: JointState, visit: Visit) -> ContactForces {
                match self {
                    $(Self::$variant(m) => m.forces(pair, at, visit),)+
                }
            }

            fn forces_and_jacobian(
                &self,
                pair: &ContactPair<B, P, N, F>,
                at: JointState,
            ) -> (ContactForces, ContactJacobian) {
                match self {
                    $(Self::$variant(m) => m.forces_and_jacobian(pair, at),)+
                }
            }

            #[inline]
            fn penetration(&self, pair: &ContactPair<B, P, N, F>, at: JointState) -> f64 {
                match self {
                    $(Self::$variant(m) => m.penetration(pair, at),)+
                }
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
}
