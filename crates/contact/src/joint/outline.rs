//! The bounds the foundation's node search works within: each outline's radius bounds by
//! sector, the pin's node table, and the overlap memory that lets an evaluation pass over
//! nodes an earlier one found apart. Fixed while the profiles are; the kernel
//! ([`super::foundation`]) reads them.

use std::f64::consts::TAU;

use crate::surface::{RadiusSample, SurfaceProfile, floor};

/// Bounds on the two outlines, fixed while the profiles are: the visited-node window needs
/// them. Computed once per joint from [`SurfaceProfile::radius_bounds`], with the pin's node
/// table.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct OutlineBounds {
    /// Smallest bearing radius (m; 0 when unknown: every node is visited).
    pub(super) bearing_min: f64,
    /// The bearing's sample, the same at every angle, when it is round.
    pub(super) round_bearing: Option<RadiusSample>,
    /// Largest pin radius (m; infinite when unknown).
    pub(super) pin_max: f64,
    /// Smallest pin radius at a node (m).
    pub(super) pin_min: f64,
    /// Outline length per node, `R_j0 2π/N` (m), `R_j0` the pin's largest radius.
    pub(super) node_arc: f64,
    /// Smallest bearing radius over each of [`BLOCKS`] equal sectors of its frame (m).
    pub(super) bearing_block_min: [f64; BLOCKS],
    /// The smallest of `bearing_block_min` (m): no sector's bound is below it.
    pub(super) bearing_floor: f64,
    /// Largest pin radius at the nodes of each sector of the pin's frame (m).
    pub(super) pin_block_max: [f64; BLOCKS],
    /// Each node's offset from the pin centre in the pin's frame, `r_k u(α_k)` (m): the pin's
    /// profile is fixed while the joint is, so its spline and the node's `sin_cos` are
    /// evaluated once here instead of once per node per evaluation. With it, the node's angle
    /// `α_k`.
    pub(super) pin_nodes: Vec<([f64; 2], f64)>,
    /// Largest `|r_k u(α_k)|` over the nodes (m).
    pub(super) node_reach: f64,
    /// [`SurfaceProfile::slope_bound`] of the bearing (m/rad; `None`: no [`OverlapMemory`]).
    pub(super) bearing_slope: Option<f64>,
    /// An earlier plain evaluation's overlaps (reset with the profiles, as it depends on them).
    pub(super) memory: OverlapMemory,
}

/// An earlier plain evaluation's node overlaps and the pose they were found at. Between
/// evaluations a node's gap `g_k = ρ_k − R_i(ψ_k)` changes by at most the distance its point can
/// have moved relative to the bearing, plus the bearing's slope times the angle that distance
/// subtends ([`OutlineBounds::drift`]). A node beyond the bearing's smallest radius (where its
/// overlap is `g_k`) whose remembered gap stays negative by more than that cannot touch, so it
/// is not computed: the forces are the same bit for bit, and the evaluation cheaper while the
/// joint moves little (a step's Newton iterations, the next step). The deepest overlap, a
/// diagnostic, is the same too: a node is passed over only when it surely stays below the
/// memory's deepest node as well ([`Skip`]). While that node surely still overlaps the memory is
/// only read; otherwise, or once an evaluation using it computed more than half the nodes its
/// own did (stale), the evaluation renews it at its own pose, still passing over what the old
/// notes rule out and noting their bounds plus the drift for those nodes.
///
/// Interior mutability behind `&self` (the forces are evaluated through shared references):
/// the evaluation takes the memory out and puts it back, so concurrent evaluations of one
/// joint only miss it. It is not part of the joint's value: clones start empty and equality
/// ignores it.
#[derive(Default)]
pub(super) struct OverlapMemory(std::sync::Mutex<Option<Box<Remembered>>>);

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
    pub(super) fn empty(cells: usize) -> Box<Self> {
        Box::new(Self {
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
        })
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
    /// smallest radius, so that the overlap is its gap `g_k`, whose change [`OutlineBounds::drift`]
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

#[derive(Clone, Copy)]
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

/// Rounding allowance of [`OutlineBounds::drift`] (m): the overlaps are computed to ~1e-17 m.
pub(super) const DRIFT_MARGIN: f64 = 1e-12;

impl OverlapMemory {
    pub(super) fn take(&self) -> Option<Box<Remembered>> {
        self.0.lock().unwrap_or_else(|p| p.into_inner()).take()
    }

    pub(super) fn put(&self, remembered: Box<Remembered>) {
        *self.0.lock().unwrap_or_else(|p| p.into_inner()) = Some(remembered);
    }
}

impl Clone for OverlapMemory {
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl std::fmt::Debug for OverlapMemory {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("OverlapMemory")
    }
}

impl PartialEq for OverlapMemory {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

/// Sectors of 5.6° in which the outlines' radius bounds are kept, to skip the parts of the pin
/// that cannot reach the bearing.
pub(super) const BLOCKS: usize = 64;
/// Angle of a sector (rad).
pub(super) const BLOCK: f64 = TAU / BLOCKS as f64;
impl OutlineBounds {
    pub(super) fn new<B: SurfaceProfile, P: SurfaceProfile>(
        bearing: &B,
        pin: &P,
        cells: usize,
    ) -> Self {
        let bearing_min = bearing.radius_bounds().map_or(0.0, |(lo, _)| lo);
        let pin_bounds = pin.radius_bounds();
        // The node weight needs a radius even where the bounds are unknown: the largest sample.
        let pin_reference = pin_bounds.map_or_else(
            || {
                (0..cells)
                    .map(|k| pin.sample(node_angle(k, cells)).radius)
                    .fold(0.0, f64::max)
            },
            |(_, hi)| hi,
        );
        let mut pin_block_max = [f64::NEG_INFINITY; BLOCKS];
        let mut pin_min = f64::INFINITY;
        let mut pin_nodes = Vec::with_capacity(cells);
        for k in 0..cells {
            let alpha = node_angle(k, cells);
            let radius = pin.sample(alpha).radius;
            let block = ((alpha / BLOCK) as usize).min(BLOCKS - 1);
            pin_block_max[block] = pin_block_max[block].max(radius);
            pin_min = pin_min.min(radius);
            let (s, c) = alpha.sin_cos();
            pin_nodes.push(([radius * c, radius * s], alpha));
        }
        let bearing_block_min = std::array::from_fn(|b| {
            let start = b as f64 * BLOCK;
            bearing
                .radius_bounds_between(start, start + BLOCK)
                .map_or(0.0, |(lo, _)| lo)
        });
        Self {
            bearing_min,
            round_bearing: bearing.is_round().then(|| bearing.sample(0.0)),
            pin_max: pin_bounds.map_or(f64::INFINITY, |(_, hi)| hi),
            pin_min,
            node_arc: pin_reference * TAU / cells as f64,
            bearing_block_min,
            bearing_floor: bearing_block_min
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min),
            pin_block_max,
            node_reach: pin_nodes
                .iter()
                .map(|(p, _)| p[0].hypot(p[1]))
                .fold(0.0, f64::max),
            pin_nodes,
            // On a round bearing a node beyond its radius overlaps: nothing to skip.
            bearing_slope: bearing
                .slope_bound()
                .filter(|s| s.is_finite() && !bearing.is_round()),
            memory: OverlapMemory::default(),
        }
    }

    /// A bound on how much the gap `ρ_k − R_i(ψ_k)` of any node at pose `then` can differ at
    /// pose `now` (m), or `None` without a slope bound for the bearing. A node point moves
    /// relative to the bearing by at most `b = |Δe| + r⁺ |Δθ|`: its distance from the bearing
    /// centre by at most `b`, its direction (it was at least `ρ⁻ = min(R_i⁻, r⁻ − |e|)` from the
    /// centre, `r⁻` the pin's smallest node radius) by at most `asin(b/ρ⁻)`, along which the
    /// bearing radius changes by at most its slope bound times that.
    pub(super) fn drift(&self, then: Pose, now: Pose) -> Option<f64> {
        let slope = self.bearing_slope?;
        let moved = (now.offset[0] - then.offset[0]).hypot(now.offset[1] - then.offset[1])
            + self.node_reach * (now.turn - then.turn).abs();
        let nearest = self
            .bearing_min
            .min(self.pin_min - then.offset[0].hypot(then.offset[1]));
        let turned = if moved < nearest {
            (moved / nearest).asin()
        } else {
            std::f64::consts::PI
        };
        let drift = moved + slope * turned + DRIFT_MARGIN;
        drift.is_finite().then_some(drift)
    }

    /// Smallest bearing radius over bearing-frame angles `[start, end]` (from the sectors).
    pub(super) fn bearing_min_between(&self, start: f64, end: f64) -> f64 {
        let first = floor(start / BLOCK) as i64;
        let last = (floor(end / BLOCK) as i64).min(first + BLOCKS as i64 - 1);
        (first..=last)
            .map(|b| self.bearing_block_min[b.rem_euclid(BLOCKS as i64) as usize])
            .fold(f64::INFINITY, f64::min)
    }
}

/// The angle of node `k` of `cells` in the pin's frame: its cell's centre.
#[inline]
pub(super) fn node_angle(k: usize, cells: usize) -> f64 {
    (k as f64 + 0.5) * TAU / cells as f64
}
