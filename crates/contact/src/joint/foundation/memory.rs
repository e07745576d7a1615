//! What the foundation's evaluations carry from one to the next
//! ([`FoundationWorkspace`]): the overlap memory that lets an evaluation pass over nodes an
//! earlier one found apart, and the buffer Simpson's wear loads wait in.

use crate::joint::model::NodeLoad;

/// The foundation's workspace: what its evaluations of one joint carry from one to the next.
/// Its caller owns it and hands it to every evaluation of that joint; an empty one (the
/// default) gives the same results, only without passing over any node. Made for a joint by
/// [`crate::ContactModel::workspace`], it is sized for its nodes, so that evaluations allocate
/// nothing (Simpson's wear loads grow their buffer on the first visits only).
#[derive(Clone, Debug, Default)]
pub struct FoundationWorkspace {
    /// The overlap memory (empty: none).
    pub(super) memory: Remembered,
    /// Simpson's wear loads, held until the evaluation's totals are known.
    pub(super) deposits: Vec<NodeLoad>,
}

impl FoundationWorkspace {
    /// A workspace for a foundation of `cells` nodes.
    pub(super) fn for_cells(cells: usize) -> Self {
        Self {
            memory: Remembered::empty(cells),
            deposits: Vec::new(),
        }
    }
}

/// The overlap memory: an earlier plain evaluation's node overlaps and the pose they were found
/// at. Between evaluations a node's gap `g_k = ρ_k − R_i(ψ_k)` changes by at most the distance its point can
/// have moved relative to the bearing, plus the bearing's slope times the angle that distance
/// subtends ([`super::window::NodeWindow::drift`]). A node beyond the bearing's smallest radius (where its
/// overlap is `g_k`) whose remembered gap stays negative by more than that cannot touch, so it
/// is not computed: the forces are the same bit for bit, and the evaluation cheaper while the
/// joint moves little (a step's Newton iterations, the next step). The deepest overlap, a
/// diagnostic, is the same too: a node is passed over only when it surely stays below the
/// memory's deepest node as well ([`Skip`]). While that node surely still overlaps the memory is
/// only read; otherwise, or once an evaluation using it computed more than half the nodes its
/// own did (stale), the evaluation renews it at its own pose, still passing over what the old
/// notes rule out and noting their bounds plus the drift for those nodes. An empty memory (no
/// room for the nodes) is not used.
#[derive(Clone, Debug)]
pub(super) struct Remembered {
    /// The pin centre from the bearing centre in the bearing's frame (m), and the pin's angle
    /// relative to the bearing (rad).
    pub(super) pose: Pose,
    /// Per node, an upper bound on its gap `g_k = ρ_k − R_i(ψ_k)` at `pose` (m: its overlap,
    /// which beyond the bearing's smallest radius is `g_k` and below it `ρ_k − R_i⁻ ≥ g_k`),
    /// valid where `stamp` is `generation` (the nodes that evaluation visited).
    pub(super) overlap: Vec<f64>,
    pub(super) stamp: Vec<u32>,
    pub(super) generation: u32,
    /// The deepest of those that are gaps (m): the node it belongs to is still at least this
    /// deep less the drift.
    pub(super) deepest: f64,
    /// The node of `deepest`: the event function computes it first, so that the bound prunes
    /// the rest at once.
    pub(super) deepest_cell: Option<usize>,
    /// Nodes computed in full then.
    pub(super) computed: usize,
    /// An evaluation using this memory computed more than half as many nodes: renew it.
    pub(super) stale: bool,
}

impl Remembered {
    /// A memory for `cells` nodes that remembers nothing yet.
    pub(super) fn empty(cells: usize) -> Self {
        Self {
            pose: Pose {
                offset: [0.0; 2],
                turn: 0.0,
            },
            overlap: vec![f64::INFINITY; cells],
            stamp: vec![0; cells],
            generation: 0,
            deepest: f64::NEG_INFINITY,
            deepest_cell: None,
            computed: 0,
            stale: false,
        }
    }

    /// Starts remembering at `pose`; the previous generation, whose notes stay readable by
    /// [`Self::bound_in`] until overwritten, unless the counter wrapped and cleared them.
    pub(super) fn renew(&mut self, pose: Pose) -> Option<u32> {
        let previous = self.generation;
        self.generation = self.generation.wrapping_add(1);
        let wrapped = self.generation == 0;
        if wrapped {
            self.stamp.fill(0);
            self.generation = 1;
        }
        self.pose = pose;
        self.deepest = f64::NEG_INFINITY;
        self.deepest_cell = None;
        self.computed = 0;
        self.stale = false;
        (!wrapped).then_some(previous)
    }

    /// Remembers node `cell`'s overlap; `beyond` when the node lies beyond the bearing's
    /// smallest radius, so that the overlap is its gap `g_k`, whose change [`super::window::NodeWindow::drift`]
    /// bounds both ways: only those count for the deepest, which must stay a lower bound on
    /// that node's overlap too.
    pub(super) fn note(&mut self, cell: usize, overlap: f64, beyond: bool) {
        self.overlap[cell] = overlap;
        self.stamp[cell] = self.generation;
        if beyond {
            let deeper = self.deepest.max(overlap);
            if deeper != self.deepest {
                self.deepest_cell = Some(cell);
            }
            self.deepest = deeper;
        }
    }

    /// The bound generation `generation` noted for node `cell` (+∞ when it did not, or when
    /// the node has been noted since).
    #[inline]
    pub(super) fn bound_in(&self, cell: usize, generation: u32) -> f64 {
        if self.stamp[cell] == generation {
            self.overlap[cell]
        } else {
            f64::INFINITY
        }
    }
}

/// What an evaluation may pass over by the overlap memory: a node whose gap stays below
/// `level` by the bound that `generation` noted plus the `drift` since. While the memory's
/// deepest node surely still overlaps (`overlapping`), the level is 0: such a node carries
/// nothing and is not the deepest, wherever it lies. Otherwise the level is that node's lower
/// bound `deepest − drift` (≤ 0), and only a node beyond the bearing's smallest radius is passed
/// over: one within it has an overlap `ρ_k − R_i⁻` that the bound does not cover, so it is
/// found as before.
#[derive(Clone, Copy)]
pub(super) struct Skip {
    pub(super) generation: u32,
    pub(super) drift: f64,
    /// The memory's deepest node's lower bound now, `deepest − drift`: no node whose gap stays
    /// below it can be the deepest.
    pub(super) floor: f64,
    pub(super) level: f64,
    pub(super) overlapping: bool,
}

impl Skip {
    pub(super) fn new(memory: &Remembered, drift: f64) -> Self {
        let floor = memory.deepest - drift;
        Self {
            generation: memory.generation,
            drift,
            floor,
            level: floor.min(0.0),
            overlapping: floor > 0.0,
        }
    }

    /// An upper bound on node `cell`'s gap now (m; +∞ when unknown).
    #[inline]
    pub(super) fn gap_bound(&self, memory: &Remembered, cell: usize) -> f64 {
        memory.bound_in(cell, self.generation) + self.drift
    }
}

/// What a renewal of the overlap memory notes for a node it does not compute in full.
#[derive(Clone, Copy)]
pub(super) enum Noted {
    /// Its overlap `ρ_k − R_i⁻` within the bearing's smallest radius (a bound on its gap).
    Below,
    /// Its gap beyond that radius, exact.
    Gap,
    /// The old notes' bound plus the drift, a bound on its gap now.
    Carried,
    /// Nothing.
    Nothing,
}

#[derive(Clone, Copy, Debug)]
pub(super) struct Pose {
    pub(super) offset: [f64; 2],
    pub(super) turn: f64,
}

impl Pose {
    /// From the offset `e` of the pin centre (global frame), the bearing's angle as its sine and
    /// cosine, and both angles.
    pub(super) fn new(e: [f64; 2], (s, c): (f64, f64), theta_bearing: f64, theta_pin: f64) -> Self {
        Self {
            offset: [c * e[0] + s * e[1], c * e[1] - s * e[0]],
            turn: theta_pin - theta_bearing,
        }
    }
}

/// Rounding allowance of [`super::window::NodeWindow::drift`] (m): the overlaps are computed to ~1e-17 m.
pub(super) const DRIFT_MARGIN: f64 = 1e-12;

impl Default for Remembered {
    /// Remembers nothing and has no room: an evaluation uses no memory.
    fn default() -> Self {
        Self::empty(0)
    }
}
