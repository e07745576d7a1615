//! The thin-gap model's parameters ([`ThinGap`]: the foundation's layer) and its workspace.

use serde::{Deserialize, Serialize};

use crate::joint::foundation::Foundation;
use crate::joint::model::NodeLoad;

/// The thin-gap contact model: the foundation's layer (its modulus, nodes, quadrature and
/// damping speed) with the thin-gap overlap on nodes fixed in the bearing's frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ThinGap {
    layer: Foundation,
}

impl ThinGap {
    /// The thin-gap model of a foundation's layer.
    pub fn new(layer: Foundation) -> Self {
        Self { layer }
    }

    /// The layer: modulus, nodes, quadrature, damping speed.
    pub fn layer(&self) -> Foundation {
        self.layer
    }
}

/// What the thin-gap model's evaluations carry from one to the next: the buffer Simpson's wear
/// loads wait in until the evaluation's totals are known.
#[derive(Clone, Debug, Default)]
pub struct ThinGapWorkspace {
    pub(in crate::joint) deposits: Vec<NodeLoad>,
}
