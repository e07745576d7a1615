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
/// loads wait in until the evaluation's totals are known, and the window's overlaps.
#[derive(Clone, Debug, Default)]
pub struct ThinGapWorkspace {
    pub(in crate::joint) deposits: Vec<NodeLoad>,
    /// The weighed overlaps `g̃_k` and the overlaps `g_k` (m) of the window's nodes, in order.
    pub(in crate::joint) weighed: Vec<f64>,
    pub(in crate::joint) overlaps: Vec<f64>,
}

impl ThinGapWorkspace {
    /// A workspace with room for the overlaps of a window of `nodes` nodes.
    pub(in crate::joint) fn with_room(deposits: usize, nodes: usize) -> Self {
        Self {
            deposits: Vec::with_capacity(deposits),
            weighed: vec![0.0; nodes],
            overlaps: vec![0.0; nodes],
        }
    }
}

/// Calls `f` with room for the weighed overlaps and the overlaps of `nodes` nodes: the
/// workspace's buffers `weighed` and `overlaps` where they are long enough (the joint's
/// workspace), else buffers of its own, on the stack up to [`STACK_NODES`] nodes (an empty
/// workspace: the evaluation allocates nothing) and allocated beyond.
#[inline]
pub(in crate::joint) fn with_overlaps<R>(
    weighed: &mut [f64],
    overlaps: &mut [f64],
    nodes: usize,
    f: impl FnOnce(&mut [f64], &mut [f64]) -> R,
) -> R {
    if weighed.len() >= nodes && overlaps.len() >= nodes {
        return f(&mut weighed[..nodes], &mut overlaps[..nodes]);
    }
    with_own_overlaps(nodes, f)
}

/// Nodes whose overlaps an evaluation with an empty workspace keeps on the stack: a window of
/// every node of 1024 and two beyond each end.
const STACK_NODES: usize = 1028;

#[cold]
#[inline(never)]
fn with_own_overlaps<R>(nodes: usize, f: impl FnOnce(&mut [f64], &mut [f64]) -> R) -> R {
    if nodes <= STACK_NODES {
        let (mut weighed, mut overlaps) = ([0.0; STACK_NODES], [0.0; STACK_NODES]);
        return f(&mut weighed[..nodes], &mut overlaps[..nodes]);
    }
    f(&mut vec![0.0; nodes], &mut vec![0.0; nodes])
}
