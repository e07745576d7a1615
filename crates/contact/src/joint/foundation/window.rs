//! The foundation's node window ([`NodeWindow`]): each outline's radius bounds by sector and the
//! pin's node table, what the node search works within. The model builds it once per pair of
//! profiles; its evaluations only read it.

use std::f64::consts::TAU;

use super::memory::{DRIFT_MARGIN, Pose};
use crate::surface::{RadiusSample, SurfaceProfile, floor};

/// The foundation's state for one pair of profiles: bounds on the two outlines, by sector, that
/// the visited-node window needs, and the pin's node table. Built by
/// [`crate::ContactModel::tables`] from [`SurfaceProfile::radius_bounds`] and the pin's samples
/// at the nodes, once per joint and again when its profiles change.
#[derive(Clone, Debug, PartialEq)]
pub struct NodeWindow {
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
    /// [`SurfaceProfile::slope_bound`] of the bearing (m/rad; `None`: no overlap memory).
    pub(super) bearing_slope: Option<f64>,
}

/// Sectors of 5.6° in which the outlines' radius bounds are kept, to skip the parts of the pin
/// that cannot reach the bearing.
pub(super) const BLOCKS: usize = 64;
/// Angle of a sector (rad).
pub(super) const BLOCK: f64 = TAU / BLOCKS as f64;

impl NodeWindow {
    /// The window of `cells` nodes for these profiles.
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
