//! Which nodes an evaluation visits and what each one is: the sectors that can touch, a node's
//! cheap overlap for the look-ahead, and a node in full (its gap, normal, rate and arms).

use super::Kernel;
use super::geometry::{Body, Node, angle_near, dot, offset};
use super::memory::{Noted, Remembered, Skip};
use super::window::{BLOCK, BLOCKS};
use crate::friction::FrictionLaw;
use crate::joint::dual::Real;
use crate::normal::NormalLaw;
use crate::surface::{SurfaceProfile, wrap_angle};

use std::f64::consts::TAU;

/// At most this many separate runs of candidate sectors are visited one by one; beyond it the
/// whole circle is visited.
pub(super) const MAX_RUNS: usize = 16;

/// The node ranges that can touch (signed indices, each `first..=last`, wrapping), and a bound
/// on the deepest overlap of the nodes outside them (≤ 0).
pub(super) struct Candidates {
    pub(super) runs: [(i64, i64); MAX_RUNS],
    pub(super) count: usize,
    pub(super) outside_bound: f64,
}

impl<B: SurfaceProfile, P: SurfaceProfile, N: NormalLaw, F: FrictionLaw> Kernel<'_, B, P, N, F> {
    /// The nodes that can touch, sector by sector: a pin sector whose farthest reach from the
    /// bearing centre (its largest radius, at the angle nearest the eccentricity) stays inside
    /// the smallest bearing radius where it can land is skipped. In free flight (`|e| + R_j⁺ ≤
    /// R_i⁻`) nothing is visited. Each run reaches `beyond` nodes past its ends (the segments
    /// that may be loaded: 1 for the trapezoid, 2 for Simpson's every-other-node segments).
    pub(super) fn candidates(
        &self,
        cells: usize,
        e: [f64; 2],
        (theta_pin, theta_bearing): (f64, f64),
        beyond: i64,
    ) -> Candidates {
        let b = self.window;
        let rho = e[0].hypot(e[1]);
        let mut found = Candidates {
            runs: [(0, 0); MAX_RUNS],
            count: 0,
            outside_bound: rho + b.pin_max.min(1e300) - b.bearing_min,
        };
        if found.outside_bound <= 0.0 {
            return found;
        }
        let direction = e[1].atan2(e[0]);
        // A pin point turns by at most this between its direction from the pin centre and its
        // direction from the bearing centre.
        let slack = if b.pin_min > rho {
            (rho / (b.pin_min - rho)).min(1.0).asin()
        } else {
            std::f64::consts::PI
        };
        let mut candidate = [false; BLOCKS];
        let mut bound = f64::NEG_INFINITY;
        // Sectors from the one facing the eccentricity outwards, alternating sides: the margins
        // fall with the angle from it, so the nearest non-candidates set the bound early and
        // the rest are settled by a cheap upper bound on their margin (below).
        let facing = ((wrap_angle(direction - theta_pin) / BLOCK) as usize).min(BLOCKS - 1);
        for step in 0..BLOCKS {
            let turn = if step % 2 == 1 {
                step.div_ceil(2)
            } else {
                BLOCKS - step / 2
            };
            let block = (facing + turn) % BLOCKS;
            let is_candidate = &mut candidate[block];
            let reach = b.pin_block_max[block];
            if reach == f64::NEG_INFINITY {
                continue;
            }
            let start = block as f64 * BLOCK + theta_pin;
            let mid = start + 0.5 * BLOCK;
            let off =
                (wrap_angle(direction - mid + std::f64::consts::PI) - std::f64::consts::PI).abs();
            let gap = (off - 0.5 * BLOCK).max(0.0);
            // A sector turned away from the eccentricity is nearer the bearing centre than the
            // pin's own radius can reach out, √(ρ² + r²) < R_i⁻ in practice: check that first.
            if gap >= std::f64::consts::FRAC_PI_2
                && rho * rho + reach * reach <= b.bearing_min * b.bearing_min
            {
                bound = bound.max((rho * rho + reach * reach).sqrt() - b.bearing_min);
                continue;
            }
            // `1 − g²/2 + g⁴/24 ≥ cos g` for every g (and 1e-14 over its rounding): a reach at
            // least the exact one, computed the same way. A sector it keeps within the bearing's
            // smallest sector radius by no more than the bound so far is not a candidate and
            // cannot raise the bound: the exact margin would leave both as they are.
            let gap2 = gap * gap;
            let cos_above = 1.0 - gap2 * (0.5 - gap2 / 24.0) + 1e-14;
            let farthest_above = (rho * rho + reach * reach + 2.0 * reach * rho * cos_above)
                .max(0.0)
                .sqrt();
            let margin_above = farthest_above - b.bearing_floor;
            if margin_above <= 0.0 && margin_above <= bound {
                continue;
            }
            let farthest = (rho * rho + reach * reach + 2.0 * reach * rho * gap.cos())
                .max(0.0)
                .sqrt();
            let nearest_bearing = b.bearing_min_between(
                start - slack - theta_bearing,
                start + BLOCK + slack - theta_bearing,
            );
            let margin = farthest - nearest_bearing;
            *is_candidate = margin > 0.0;
            if !*is_candidate {
                bound = bound.max(margin);
            }
        }
        found.outside_bound = bound;
        let Some(quiet) = candidate.iter().position(|c| !c) else {
            // Every sector may touch (unknown bounds): the whole circle, from opposite the
            // eccentricity, which never overlaps.
            let away = direction + std::f64::consts::PI - theta_pin;
            let first = (away * cells as f64 / TAU - 0.5).round() as i64;
            found.runs[0] = (first, first + cells as i64 - 1);
            found.count = 1;
            return found;
        };
        let node_at_block = |block: i64| -> i64 {
            (block as f64 * cells as f64 / BLOCKS as f64 - 0.5).ceil() as i64
        };
        let mut open: Option<i64> = None;
        for step in 1..=BLOCKS as i64 {
            let block = quiet as i64 + step;
            let here = candidate[block.rem_euclid(BLOCKS as i64) as usize];
            match (here, open) {
                (true, None) => open = Some(block),
                (false, Some(first_block)) => {
                    open = None;
                    // Nodes beyond each end: they cannot overlap but may share a loaded
                    // segment with a node inside.
                    let run = (
                        node_at_block(first_block) - beyond,
                        node_at_block(block) + beyond - 1,
                    );
                    if found.count == MAX_RUNS {
                        // Too fragmented to list: the whole circle, from opposite the
                        // eccentricity (never overlapping).
                        let away = direction + std::f64::consts::PI - theta_pin;
                        let first = (away * cells as f64 / TAU - 0.5).round() as i64;
                        found.runs[0] = (first, first + cells as i64 - 1);
                        found.count = 1;
                        return found;
                    }
                    found.runs[found.count] = run;
                    found.count += 1;
                }
                _ => {}
            }
        }
        found
    }

    /// The overlap of node `cell` alone (m), cheaply: a node nearer the bearing centre than the
    /// bearing's smallest radius returns that (negative) distance without sampling the bearing.
    /// `None` when the overlap cannot exceed `deepest`: it is at most `ρ_k − R_i⁻`, and beyond
    /// the smallest radius at most `gap_bound` (a bound on `ρ_k − R_i(ψ_k)` from the overlap
    /// memory, +∞ without), so a node whose bound does not beat the deepest one so far is not
    /// sampled (`−∞`: always sampled).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub(super) fn overlap_at(
        &self,
        cell: usize,
        bearing: &Body<f64>,
        pin: &Body<f64>,
        bearing_centre_arm: &[f64; 2],
        theta_bearing: f64,
        deepest: f64,
        gap_bound: f64,
    ) -> Option<f64> {
        let (_, _, d) = self.node_point(cell, bearing, pin, bearing_centre_arm);
        let rho = d[0].hypot(d[1]);
        let below = rho - self.window.bearing_min;
        if below <= deepest {
            return None;
        }
        if rho <= self.window.bearing_min {
            return Some(below);
        }
        if gap_bound <= deepest {
            return None;
        }
        Some(
            rho - self
                .pair
                .bearing_profile
                .sample(self.ray_angle(cell, pin, &d) - theta_bearing)
                .radius,
        )
    }

    /// What the streaming loop of [`Self::foundation_eval`] looks ahead with for node `cell`, and
    /// what a renewal of the overlap memory may note for it if it is not computed in full. In
    /// plain arithmetic: `ρ_k − R_i⁻` within the bearing's smallest radius (the node's overlap,
    /// bit for bit); beyond it the node's gap if the memory remembers it apart, else +∞ (it may
    /// overlap: computed in full); −∞ for a node the memory rules out ([`Skip`]; without
    /// placing it only while the memory's deepest node surely overlaps). With dual numbers, the
    /// node's overlap.
    #[inline(always)]
    pub(super) fn look_ahead(
        &self,
        cell: usize,
        plain: bool,
        bodies: &(Body<f64>, Body<f64>),
        bearing_centre_arm: &[f64; 2],
        theta_bearing: f64,
        memory: Option<(Skip, &Remembered)>,
    ) -> (f64, Noted) {
        if !plain {
            let overlap = self
                .overlap_at(
                    cell,
                    &bodies.0,
                    &bodies.1,
                    bearing_centre_arm,
                    theta_bearing,
                    f64::NEG_INFINITY,
                    f64::INFINITY,
                )
                .unwrap_or(f64::NEG_INFINITY);
            return (overlap, Noted::Nothing);
        }
        let gap_bound = memory.map(|(skip, m)| (skip, skip.gap_bound(m, cell)));
        let ruled_out = gap_bound.filter(|(skip, bound)| *bound < skip.level);
        if let Some((skip, _)) = ruled_out
            && skip.overlapping
        {
            // The memory first, so a node it rules out is not even placed. (Within the
            // smallest radius that gives −∞ for an overlap ≤ 0: neither overlaps, and neither
            // is the deepest once the memory's deepest node, which surely overlaps, is counted.)
            return (f64::NEG_INFINITY, Noted::Carried);
        }
        let (_, _, d) = self.node_point(cell, &bodies.0, &bodies.1, bearing_centre_arm);
        let rho = dot(&d, &d).sqrt();
        if rho <= self.window.bearing_min {
            return (rho - self.window.bearing_min, Noted::Below);
        }
        if ruled_out.is_some() {
            return (f64::NEG_INFINITY, Noted::Carried);
        }
        // A node the memory remembers apart (but within the drift of touching) is probably
        // still apart: its gap alone (as `node` computes it, bit for bit) spares the full node
        // if it does not overlap, nor do its neighbours. (On the worn bench cycle 4 % fewer
        // instructions than computing it in full; other thresholds, from half a drift apart to
        // seven into contact, saved 1–3 %.)
        if gap_bound.is_some_and(|(skip, bound)| bound < skip.drift) {
            let radius = self
                .pair
                .bearing_profile
                .sample(self.ray_angle(cell, &bodies.1, &d) - theta_bearing)
                .radius;
            return (rho - radius, Noted::Gap);
        }
        (f64::INFINITY, Noted::Nothing)
    }

    /// Node `cell`'s angle on the pin, its arm from the pin body's centroid, and its offset
    /// `D_k` from the bearing centre.
    #[inline]
    pub(super) fn node_point<T: Real>(
        &self,
        cell: usize,
        bearing: &Body<T>,
        pin: &Body<T>,
        bearing_centre_arm: &[T; 2],
    ) -> (f64, [T; 2], [T; 2]) {
        let ([x, y], alpha) = self.window.pin_nodes[cell];
        let pin_arm = pin.rotate([self.pair.pin_centre.x + x, self.pair.pin_centre.y + y]);
        let d = offset(pin, &pin_arm, bearing, bearing_centre_arm);
        (alpha, pin_arm, d)
    }

    /// The angle `ψ_k` of node `cell`'s offset `d` from the bearing centre. The node's own
    /// direction from the pin centre, `θ_j + α_k`, is within `asin(|e|/r_k)` of it (a few
    /// hundredths of a radian in a clearance joint), so its value adds the small angle
    /// between the two ([`angle_near`]) instead of calling `atan2`. Dual numbers (the
    /// Jacobian) take `atan2`'s partials with the same value, so that both evaluations agree.
    #[inline]
    pub(super) fn ray_angle<T: Real>(&self, cell: usize, pin: &Body<T>, d: &[T; 2]) -> T {
        let ([x, y], alpha) = self.window.pin_nodes[cell];
        let w = pin.rotate([x, y]);
        let value = angle_near(
            [d[0].value(), d[1].value()],
            [w[0].value(), w[1].value()],
            pin.theta + alpha,
        );
        if T::PLAIN {
            T::constant(value)
        } else {
            d[1].atan2(d[0]).chain(value, 1.0)
        }
    }

    /// Node `cell` at the given bodies.
    #[inline]
    pub(super) fn node<T: Real>(
        &self,
        cell: usize,
        bearing: &Body<T>,
        pin: &Body<T>,
        bearing_centre_arm: &[T; 2],
        theta_bearing: T,
    ) -> Node<T> {
        let (alpha, pin_arm, d) = self.node_point(cell, bearing, pin, bearing_centre_arm);
        let rho = dot(&d, &d).sqrt();
        // The ray's angle matters for a worn bearing's sample and for the partials; a plain
        // node on a round bearing needs neither (its bearing angle for wear is found only when
        // the node is visited).
        let (angle, sample, bearing_angle) = match self.window.round_bearing {
            Some(sample) if T::PLAIN => (theta_bearing, sample, None),
            _ => {
                let angle = self.ray_angle(cell, pin, &d) - theta_bearing;
                let sample = self.pair.bearing_profile.sample(angle.value());
                (angle, sample, Some(angle.value()))
            }
        };
        let bearing_radius = angle.chain(sample.radius, sample.slope);
        let bearing_slope = angle.chain(sample.slope, sample.curvature);
        let n = [d[0] / rho, d[1] / rho];
        let t = [-n[1], n[0]];
        let slope_over_rho = bearing_slope / rho;
        let m = [n[0] - t[0] * slope_over_rho, n[1] - t[1] * slope_over_rho];
        let bearing_arm = [bearing_centre_arm[0] + d[0], bearing_centre_arm[1] + d[1]];
        let pin_velocity = pin.point_velocity(&pin_arm);
        let d_rate = {
            let centre = bearing.point_velocity(bearing_centre_arm);
            [pin_velocity[0] - centre[0], pin_velocity[1] - centre[1]]
        };
        let bearing_velocity = bearing.point_velocity(&bearing_arm);
        let g = rho - bearing_radius;
        let beyond = rho.value() > self.window.bearing_min;
        let overlap = if beyond {
            g.value()
        } else {
            rho.value() - self.window.bearing_min
        };
        Node {
            cell,
            alpha,
            overlap,
            g,
            m,
            g_rate: dot(&m, &d_rate) + bearing_slope * bearing.omega,
            relative_velocity: [
                pin_velocity[0] - bearing_velocity[0],
                pin_velocity[1] - bearing_velocity[1],
            ],
            pin_arm,
            bearing_arm,
            ray: [d[0].value(), d[1].value()],
            bearing_angle,
            beyond,
        }
    }
}
