//! The elastic-foundation contact: a Winkler layer over the true outlines of pin and bearing.
//!
//! A worn bearing is a groove with dents and flanks, and a worn pin touches it over an arc, at
//! times over two; a line-of-centres contact sees one point. Here every point of the pin's
//! outline presses into a thin elastic layer on the bearing (Mukras et al., J. Tribol. 2010,
//! used it for revolute-joint wear).
//!
//! # Overlap
//! The pin's outline is sampled at `N` nodes fixed in the pin's frame, at the centres of its
//! cells `α_k = (k + ½) 2π/N` (the wear grid's), at its own (worn) radius `r_k`. Node `k` sits at
//! `P_k = r_j + A(θ_j)(s_j + r_k u(α_k))`. Its overlap with the bearing's outline is measured
//! radially from the bearing centre `C_i`: with `D_k = P_k − C_i`, `ρ_k = |D_k|` and
//! `ψ_k = atan2(D_k)`, `g_k = ρ_k − R_i(ψ_k − θ_i)`, the bearing's (worn) radius in that
//! direction. This is exact geometry for any eccentricity: nothing is linearised about the
//! line of centres.
//!
//! # Energy and force
//! The layer stores `V = (k w/2) ∫ d² ds` over the pin's outline (`d = max(0, g)`, `k` the layer
//! modulus in Pa/m, `w` the hinge width, `ds = R_j0 dα`). Between nodes `g` is taken linear and
//! the positive part is integrated exactly:
//! `∫₀¹ max(0, a + (b − a)s)² ds` is `(a² + ab + b²)/3` for `a, b ≥ 0` and `a³/(3(a − b))` when
//! only `a > 0`. This is C² in `(a, b)` as a node crosses the edge of a contact zone, so the
//! force is C¹: the integrator sees no kink when a zone grows or shrinks by a cell. The
//! segments' sum is the trapezoid rule, with an error `O(h²)`; by default ([`Quadrature`]) the
//! energy is Richardson's `(4 V_h − V_2h)/3`, `V_2h` the same sum over the segments joining every
//! other node: Simpson's rule on the same nodes, `O(h⁴)` inside a zone, as exact a gradient
//! and as smooth.
//!
//! The elastic force is exactly `−∇V`: with `G_k = ∂V/∂g_k ≥ 0` and
//! `∇g_k = m_k·∂D_k/∂q + R_i' ∂θ_i/∂q`, `m_k = n_k − (R_i'/ρ_k) t_k`, node `k` pushes the pin
//! with `−G_k m_k` at `P_k` and the bearing with `+G_k m_k` at the same point (its moment about
//! the bearing centre carries the `R_i'` term). So an elastic worn joint conserves energy on
//! any shape, and the pair of forces has no net moment.
//!
//! # Damping and friction, per node
//! Each node's load is `L_k = G_k φ(ġ_k)`, where `φ` is the joint's normal law's hysteresis
//! factor (for Lankarani–Nikravesh `1 + 3(1 − c_e²)/4 · ġ/δ̇⁻`, clamped at zero so the layer
//! never pulls) and `ġ_k = ∇g_k·q̇`, held within `±δ̇⁻` (the law's floored onset velocity, or
//! the layer's reference speed if larger). Within that range, the rates one impact spans, the
//! law is unchanged: on round surfaces `ġ_k ≈ δ̇` across the small contact arc, so the total is
//! the law's force and an impact rebounds with its `c_e` at any speed. Beyond it the factor is
//! held at `1 ± χ`: a pin that settled gently into a worn groove (`δ̇⁻` at the floor) and then
//! slides along its flanks would otherwise carry `χ ġ_k/δ̇⁻`, tens to hundreds of times its
//! elastic load; held, the damping adds at most what an impact's onset adds. Damping
//! dissipates `Σ (L_k − G_k) ġ_k ≥ 0` either way. Friction
//! acts at each node along the local tangent `t̂_k ⟂ m_k`, with the law evaluated on the node's
//! load `L_k |m_k|` and its material sliding velocity (the pin's material point at `P_k`
//! relative to the bearing's), or the paper's `d_k φ̇` where the joint chooses it.
//!
//! # Calibration
//! For a round pin of radius `R − c` in a round bearing of radius `R`, penetration `δ`, the
//! integral gives to leading order `F = (4√2/3) k w √(R R_j) δ^{3/2}/√(c + δ)`. With
//! `k w = E*/√2`, `E* = 1/(σ_i + σ_j)`, this is the model's conformal Hertz force
//! `K δ^{3/2}`, `K = (4/3) E* √(R_i R_j/c)`, times `√(c/(c + δ))` ([`Foundation::calibrated`]);
//! the tests check it against an independent quadrature. [`Foundation::hertz_matched`] makes
//! it exact at a chosen overlap instead (the scenes' default: 4 % of the clearance).
//!
//! # Cost
//! Only nodes that can touch are visited. The pin's nodes are grouped in 64 sectors; a sector
//! is skipped when its farthest reach from the bearing centre (its largest radius, at the angle
//! nearest the eccentricity `e`) stays inside the bearing's smallest radius over the sector of
//! the bearing it can land on ([`SurfaceProfile::radius_bounds_between`], exact for worn
//! profiles). In free flight (`|e| + R_j⁺ ≤ R_i⁻`) no node is visited, and the deepest overlap
//! (the event function) is then the skipped sectors' bound. The Jacobian runs the same code on
//! dual numbers, only on the nodes next to an overlap. A node's ray angle `ψ_k` is not an
//! `atan2` but its own direction `θ_j + α_k` plus the small angle between the two (within
//! `asin(|e|/r_k)`), summed from its series to rounding.
//!
//! Between evaluations the joint moves little (a step's Newton iterations, the next step), so
//! plain evaluations also remember the overlaps they found and the pose they found them at
//! (`OverlapMemory`): a node whose remembered gap stays negative by more than the distance it
//! can have moved since (plus the bearing's slope bound times the angle that subtends), and out
//! of contact below the remembered deepest node's, is not computed; the event function starts
//! from the remembered deepest node, so that its bound passes over the rest. This changes no
//! result, bit for bit; on the worn LGRES cycle it saves 40 % of the instructions
//! (docs/performance.md).

use nalgebra::Vector3;

use super::dual::{Dual, Real};
use super::model::{Foundation, NodeLoad, Quadrature};
use super::outline::{BLOCK, BLOCKS, Noted, Pose, Remembered, Skip};
use super::{BodyState, ClearanceJoint, ContactForces, ContactJacobian, SlidingVelocity};
use crate::diagnostics::ContactDiagnostics;
use crate::friction::FrictionLaw;
use crate::normal::NormalLaw;
use crate::surface::{SurfaceProfile, wrap_angle};

use std::f64::consts::TAU;

/// At most this many separate runs of candidate sectors are visited one by one; beyond it the
/// whole circle is visited.
const MAX_RUNS: usize = 16;

/// The node ranges that can touch (signed indices, each `first..=last`, wrapping), and a bound
/// on the deepest overlap of the nodes outside them (≤ 0).
struct Candidates {
    runs: [(i64, i64); MAX_RUNS],
    count: usize,
    outside_bound: f64,
}

/// The angle of `d`, given a vector `w` at a known angle `w_angle` close to it: `w_angle` plus
/// the small angle from `w` to `d` by its Taylor series where that is within 1/16 rad (its
/// truncation, the `z¹⁷/17` term, is below 1e-20 of the angle; the sum rounds like `atan2`'s
/// result), else `atan2`. The result may differ from `atan2`'s by a multiple of 2π.
#[inline]
fn angle_near(d: [f64; 2], w: [f64; 2], w_angle: f64) -> f64 {
    let along = w[0] * d[0] + w[1] * d[1];
    let across = w[0] * d[1] - w[1] * d[0];
    if !(along > 0.0 && across.abs() <= along * 0.0625) {
        return d[1].atan2(d[0]);
    }
    let z = across / along;
    let z2 = z * z;
    let series = 1.0
        + z2 * (-1.0 / 3.0
            + z2 * (1.0 / 5.0
                + z2 * (-1.0 / 7.0
                    + z2 * (1.0 / 9.0
                        + z2 * (-1.0 / 11.0 + z2 * (1.0 / 13.0 + z2 * (-1.0 / 15.0)))))));
    w_angle + z * series
}

/// The positional and kinematic values of one node.
#[derive(Clone, Copy)]
struct Node<T> {
    cell: usize,
    alpha: f64,
    /// Overlap `g_k` (m; negative: apart).
    g: T,
    /// `m_k = n_k − (R_i'/ρ_k) t_k`.
    m: [T; 2],
    /// `ġ_k`.
    g_rate: T,
    /// Relative velocity of the pin's material point at `P_k` on the bearing's.
    relative_velocity: [T; 2],
    /// `P_k` from the pin body's centroid.
    pin_arm: [T; 2],
    /// `P_k` from the bearing body's centroid.
    bearing_arm: [T; 2],
    /// `D_k`, whose angle less `θ_i` is where the node meets the bearing.
    ray: [f64; 2],
    /// `ψ_k − θ_i` (rad, unwrapped) when it was needed for the node (else found from `ray`).
    bearing_angle: Option<f64>,
    /// The overlap as [`ClearanceJoint::overlap_at`] gives it (m): `g_k`, or the distance
    /// below the bearing's smallest radius where the node cannot touch.
    overlap: f64,
    /// Whether the node lies beyond the bearing's smallest radius (`overlap` is `g_k`).
    beyond: bool,
}

/// One body's position and velocity in the kernel's arithmetic.
#[derive(Clone, Copy)]
struct Body<T> {
    position: [T; 2],
    /// The rotation's plain value (rad).
    theta: f64,
    theta_sin_cos: (T, T),
    velocity: [T; 2],
    omega: T,
}

impl<T: Real> Body<T> {
    fn new(state: [T; 6]) -> Self {
        Self {
            position: [state[0], state[1]],
            theta: state[2].value(),
            theta_sin_cos: state[2].sin_cos(),
            velocity: [state[3], state[4]],
            omega: state[5],
        }
    }

    /// A body-fixed vector turned into the global frame.
    #[inline]
    fn rotate(&self, local: [f64; 2]) -> [T; 2] {
        let (s, c) = self.theta_sin_cos;
        [c * local[0] - s * local[1], s * local[0] + c * local[1]]
    }

    /// Velocity of the material point at `arm` from the centroid.
    #[inline]
    fn point_velocity(&self, arm: &[T; 2]) -> [T; 2] {
        [
            self.velocity[0] - self.omega * arm[1],
            self.velocity[1] + self.omega * arm[0],
        ]
    }
}

/// The point at `pin_arm` from the pin body's centroid, seen from the point at `bearing_arm`
/// from the bearing body's.
#[inline]
fn offset<T: Real>(
    pin: &Body<T>,
    pin_arm: &[T; 2],
    bearing: &Body<T>,
    bearing_arm: &[T; 2],
) -> [T; 2] {
    [
        pin.position[0] + pin_arm[0] - bearing.position[0] - bearing_arm[0],
        pin.position[1] + pin_arm[1] - bearing.position[1] - bearing_arm[1],
    ]
}

#[inline]
fn dot<T: Real>(a: &[T; 2], b: &[T; 2]) -> T {
    a[0] * b[0] + a[1] * b[1]
}

#[inline]
fn cross<T: Real>(a: &[T; 2], b: &[T; 2]) -> T {
    a[0] * b[1] - a[1] * b[0]
}

/// `∫₀¹ max(0, a + (b − a)s)² ds` and its partials in `a` and `b` (the exact energy of one
/// segment between two nodes, see the module docs).
#[inline]
fn segment<T: Real>(a: T, b: T) -> (T, T, T) {
    let (av, bv) = (a.value(), b.value());
    let zero = T::constant(0.0);
    if av >= 0.0 && bv >= 0.0 {
        let q = (a * a + a * b + b * b) / 3.0;
        (q, (a * 2.0 + b) / 3.0, (a + b * 2.0) / 3.0)
    } else if av > 0.0 {
        let span = a - b;
        let a2 = a * a;
        let q = a2 * a / (span * 3.0);
        let dq_db = q / span;
        (q, a2 * (a * 2.0 - b * 3.0) / (span * span * 3.0), dq_db)
    } else if bv > 0.0 {
        let span = b - a;
        let b2 = b * b;
        let q = b2 * b / (span * 3.0);
        let dq_da = q / span;
        (q, dq_da, b2 * (b * 2.0 - a * 3.0) / (span * span * 3.0))
    } else {
        (zero, zero, zero)
    }
}

/// What one evaluation gives: generalized forces `(F_x, F_y, M)` on bearing and pin bodies.
struct Output<T> {
    bearing: [T; 3],
    pin: [T; 3],
    diagnostics: ContactDiagnostics,
}

/// Adds a node's force on the pin (at its point) to both bodies' generalized forces.
#[inline]
fn apply<T: Real>(out: &mut Output<T>, node: &Node<T>, force_on_pin: [T; 2]) {
    out.pin[0] = out.pin[0] + force_on_pin[0];
    out.pin[1] = out.pin[1] + force_on_pin[1];
    out.pin[2] = out.pin[2] + cross(&node.pin_arm, &force_on_pin);
    out.bearing[0] = out.bearing[0] - force_on_pin[0];
    out.bearing[1] = out.bearing[1] - force_on_pin[1];
    out.bearing[2] = out.bearing[2] - cross(&node.bearing_arm, &force_on_pin);
}

/// A computed node waiting for the segments to its right, with the partials of the energy in
/// its overlap gathered so far: from the segments to its neighbours (`fine`) and, for
/// Simpson's even nodes, to the even nodes two apart (`coarse`, in units of the node weight).
#[derive(Clone, Copy)]
struct Pending<T> {
    index: i64,
    node: Node<T>,
    fine: T,
    coarse: T,
}

/// The nodes waiting to be closed, oldest first: at most three (`k − 2`, `k − 1`, `k`), in a
/// ring so that closing the oldest moves no node.
struct NodeQueue<T> {
    items: [Option<Pending<T>>; 3],
    /// The oldest node's slot.
    head: usize,
    len: usize,
}

impl<T: Copy> Default for NodeQueue<T> {
    fn default() -> Self {
        Self {
            items: [None; 3],
            head: 0,
            len: 0,
        }
    }
}

impl<T: Copy> NodeQueue<T> {
    fn slot(&self, position: usize) -> usize {
        (self.head + position) % self.items.len()
    }

    fn at(&mut self, index: i64) -> Option<&mut Pending<T>> {
        let slots = (0..self.len).map(|position| self.slot(position));
        let slot = slots
            .into_iter()
            .find(|&slot| self.items[slot].as_ref().is_some_and(|p| p.index == index))?;
        self.items[slot].as_mut()
    }

    fn push(&mut self, pending: Pending<T>) {
        let slot = self.slot(self.len);
        self.items[slot] = Some(pending);
        self.len += 1;
    }

    fn front(&self) -> Option<&Pending<T>> {
        if self.len == 0 {
            return None;
        }
        self.items[self.head].as_ref()
    }

    /// The oldest node.
    fn pop(&mut self) -> Option<Pending<T>> {
        if self.len == 0 {
            return None;
        }
        let first = self.items[self.head].take()?;
        self.head = self.slot(1);
        self.len -= 1;
        Some(first)
    }
}

/// Running sums for the diagnostics (plain values).
#[derive(Default)]
struct Books {
    energy: f64,
    damping_power: f64,
    friction_power: f64,
    friction_force: f64,
    normal_resultant: [f64; 2],
    /// `Σ G_k m_k` over the overlapping nodes, clamped ones included.
    elastic_resultant: [f64; 2],
    load: f64,
    load_sliding: f64,
    /// The deepest overlap seen (m), and the rate `ġ` of its node once computed.
    deepest: Option<f64>,
    deepest_rate: f64,
    cells: u32,
    zones: u32,
    /// Nodes around the pin (for zones through cell 0).
    grid: usize,
    /// The open zone: its last cell, its cells and its load.
    open: Option<(usize, u32, f64)>,
    /// The first [`MAX_ZONES`] closed zones' cells and loads.
    closed: [(u32, f64); MAX_ZONES],
    /// The quadrature, whose error the zones' resolution implies.
    quadrature: Quadrature,
    /// The loaded nodes' normal loads as the trapezoid weighs them (N; Simpson's deposits).
    trapezoid_load: f64,
    /// The normal loads of the nodes Simpson weighs negatively (N, ≤ 0; elastic only).
    pull: f64,
}

/// Zones whose width and load are kept for the narrowest-zone measure.
const MAX_ZONES: usize = 16;
/// Relative load a zone of one node misses by the linear interpolation between nodes; `n`
/// nodes miss this over `n²` (see [`Books::resolution_error`]).
const RESOLUTION_ERROR: f64 = 0.96;
/// The same bound for [`Quadrature::Simpson`], also over `n²`: a quarter of the trapezoid's.
/// Simpson's error falls faster (test `simpsons_quadrature_is_within_its_resolution_estimate`:
/// worst 3.3 % at zones of 2.5 nodes, 0.48 % at 5, 0.012 % at 10), so this overstates it
/// beyond a few nodes, where it is far below the validity limit anyway; it is tight where
/// the limit decides.
const SIMPSON_RESOLUTION_ERROR: f64 = 0.24;

impl Books {
    /// Counts one node's overlap for the deepest; `true` when it is the deepest so far.
    fn see_overlap(&mut self, g: f64) -> bool {
        let deepest = self.deepest.is_none_or(|d| g > d);
        if deepest {
            self.deepest = Some(g);
        }
        deepest
    }

    /// Adds node `cell` (overlap `g`, normal load `load`) to the zone bookkeeping; nodes come
    /// in order, and a zone is a run of consecutive overlapping cells.
    fn see_zone(&mut self, cell: usize, g: f64, load: f64) {
        let grid = self.grid.max(1);
        let continues = self
            .open
            .is_some_and(|(last, _, _)| (last + 1) % grid == cell);
        if g <= 0.0 || !continues {
            self.close_zone();
        }
        if g > 0.0 {
            self.cells += 1;
            let (_, width, carried) = self.open.unwrap_or((cell, 0, 0.0));
            self.open = Some((cell, width + 1, carried + load));
        }
    }

    fn close_zone(&mut self) {
        if let Some((_, width, load)) = self.open.take() {
            if (self.zones as usize) < MAX_ZONES {
                self.closed[self.zones as usize] = (width, load);
            }
            self.zones += 1;
        }
    }

    /// The relative error of the total normal load that the grid's resolution of each zone
    /// implies: linear interpolation across a smooth cap of `n` nodes misses `≈ 0.96/n²` of its
    /// load (measured on round surfaces: −0.24 % at 20 nodes, −0.025 % at 63, −0.009 % at 108,
    /// docs/model.md §10.2), weighted by each zone's share of the load.
    fn resolution_error(&mut self) -> f64 {
        self.close_zone();
        let kept = &self.closed[..(self.zones as usize).min(MAX_ZONES)];
        let total: f64 = kept.iter().map(|(_, load)| load).sum();
        if total <= 0.0 {
            return 0.0;
        }
        let miss = |width: u32| match self.quadrature {
            Quadrature::Trapezoid => RESOLUTION_ERROR / f64::from(width).powi(2),
            Quadrature::Simpson => SIMPSON_RESOLUTION_ERROR / f64::from(width).powi(2),
        };
        kept.iter()
            .map(|(width, load)| load / total * miss(*width))
            .sum()
    }

    /// Cells across the narrowest zone among those carrying at least a tenth of the load (all
    /// zones when none carries load); 0 without contact.
    fn narrowest(&mut self) -> u32 {
        self.close_zone();
        let kept = &self.closed[..(self.zones as usize).min(MAX_ZONES)];
        let total: f64 = kept.iter().map(|(_, load)| load).sum();
        kept.iter()
            .filter(|(_, load)| total <= 0.0 || *load >= 0.1 * total)
            .map(|(width, _)| *width)
            .min()
            .unwrap_or(0)
    }
}

impl<B: SurfaceProfile, P: SurfaceProfile, N: NormalLaw, F: FrictionLaw>
    ClearanceJoint<B, P, N, F>
{
    /// The nodes that can touch, sector by sector: a pin sector whose farthest reach from the
    /// bearing centre (its largest radius, at the angle nearest the eccentricity) stays inside
    /// the smallest bearing radius where it can land is skipped. In free flight (`|e| + R_j⁺ ≤
    /// R_i⁻`) nothing is visited. Each run reaches `beyond` nodes past its ends (the segments
    /// that may be loaded: 1 for the trapezoid, 2 for Simpson's every-other-node segments).
    fn candidates(
        &self,
        cells: usize,
        e: [f64; 2],
        (theta_pin, theta_bearing): (f64, f64),
        beyond: i64,
    ) -> Candidates {
        let b = &self.bounds;
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
    fn overlap_at(
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
        let below = rho - self.bounds.bearing_min;
        if below <= deepest {
            return None;
        }
        if rho <= self.bounds.bearing_min {
            return Some(below);
        }
        if gap_bound <= deepest {
            return None;
        }
        Some(
            rho - self
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
    fn look_ahead(
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
        if rho <= self.bounds.bearing_min {
            return (rho - self.bounds.bearing_min, Noted::Below);
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
    fn node_point<T: Real>(
        &self,
        cell: usize,
        bearing: &Body<T>,
        pin: &Body<T>,
        bearing_centre_arm: &[T; 2],
    ) -> (f64, [T; 2], [T; 2]) {
        let ([x, y], alpha) = self.bounds.pin_nodes[cell];
        let pin_arm = pin.rotate([self.pin_centre.x + x, self.pin_centre.y + y]);
        let d = offset(pin, &pin_arm, bearing, bearing_centre_arm);
        (alpha, pin_arm, d)
    }

    /// The angle `ψ_k` of node `cell`'s offset `d` from the bearing centre. The node's own
    /// direction from the pin centre, `θ_j + α_k`, is within `asin(|e|/r_k)` of it (a few
    /// hundredths of a radian in a clearance joint), so its value adds the small angle
    /// between the two ([`angle_near`]) instead of calling `atan2`. Dual numbers (the
    /// Jacobian) take `atan2`'s partials with the same value, so that both evaluations agree.
    #[inline]
    fn ray_angle<T: Real>(&self, cell: usize, pin: &Body<T>, d: &[T; 2]) -> T {
        let ([x, y], alpha) = self.bounds.pin_nodes[cell];
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
    fn node<T: Real>(
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
        let (angle, sample, bearing_angle) = match self.bounds.round_bearing {
            Some(sample) if T::PLAIN => (theta_bearing, sample, None),
            _ => {
                let angle = self.ray_angle(cell, pin, &d) - theta_bearing;
                let sample = self.bearing_profile.sample(angle.value());
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
        let beyond = rho.value() > self.bounds.bearing_min;
        let overlap = if beyond {
            g.value()
        } else {
            rho.value() - self.bounds.bearing_min
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

    /// The kernel: forces on both bodies, diagnostics, and each loaded node to `visit` if any.
    fn foundation_eval<T: Real>(
        &self,
        foundation: &Foundation,
        bearing_state: [T; 6],
        pin_state: [T; 6],
        onset_velocity: Option<f64>,
        mut visit: Option<&mut dyn FnMut(&NodeLoad)>,
    ) -> Output<T> {
        // Simpson's node loads for wear, held until the evaluation's totals are known: only
        // on evaluations that visit nodes (accepted steps).
        let mut deposits: Vec<NodeLoad> = Vec::new();
        let cells = foundation.cells;
        let bearing = Body::new(bearing_state);
        let pin = Body::new(pin_state);
        let bearing_centre_arm = bearing.rotate([self.bearing_centre.x, self.bearing_centre.y]);
        let pin_centre_arm = pin.rotate([self.pin_centre.x, self.pin_centre.y]);
        let e = offset(&pin, &pin_centre_arm, &bearing, &bearing_centre_arm);
        let e_value = [e[0].value(), e[1].value()];
        let rho = e_value[0].hypot(e_value[1]);
        // The line of centres: the direction of the free joint's diagnostics, and the paper's
        // sliding rate φ̇ = t·ė/|e|.
        let e_rate = {
            let p = pin.point_velocity(&pin_centre_arm);
            let b = bearing.point_velocity(&bearing_centre_arm);
            [p[0] - b[0], p[1] - b[1]]
        };
        let e_norm = dot(&e, &e).sqrt();
        let phi_rate = if rho > 0.0 {
            cross(&e, &e_rate) / (e_norm * e_norm)
        } else {
            T::constant(0.0)
        };
        let centre_rate = if rho > 0.0 {
            (e_value[0] * e_rate[0].value() + e_value[1] * e_rate[1].value()) / rho
        } else {
            0.0
        };
        // The impact's onset velocity as the law reads it (floored), and at least the layer's
        // reference speed when one is set (`Foundation::with_reference_speed`). A node's rate
        // counts only within ± this: the range one impact spans (`Foundation`'s docs).
        let onset = self.normal_law.effective_onset(
            onset_velocity
                .unwrap_or(centre_rate)
                .abs()
                .max(foundation.reference_speed),
        );
        let theta_bearing = bearing_state[2];
        let theta_pin = pin_state[2].value();

        let zero = T::constant(0.0);
        let mut out = Output {
            bearing: [zero; 3],
            pin: [zero; 3],
            diagnostics: ContactDiagnostics::default(),
        };
        let mut books = Books {
            grid: cells,
            quadrature: foundation.quadrature,
            ..Books::default()
        };
        let weight = 0.5 * foundation.line_modulus * self.bounds.node_arc;
        let simpson = foundation.quadrature == Quadrature::Simpson;
        let candidates = self.candidates(
            cells,
            e_value,
            (theta_pin, theta_bearing.value()),
            if simpson { 2 } else { 1 },
        );

        // Plain evaluations pass over the nodes the overlap memory rules out (`Skip`), and
        // renew it with the overlaps they find when it has nothing to say or has gone stale.
        // (No memory, no pose: nothing of it runs for round bearings or dual numbers.)
        let mut memory = (T::PLAIN && self.bounds.bearing_slope.is_some()).then(|| {
            let (s, c) = bearing.theta_sin_cos;
            let pose = Pose::new(
                e_value,
                (s.value(), c.value()),
                theta_bearing.value(),
                theta_pin,
            );
            let remembered = self
                .bounds
                .memory
                .take()
                .filter(|m| m.overlap.len() == cells)
                .unwrap_or_else(|| Remembered::empty(cells));
            (remembered, pose)
        });
        let mut skip = memory
            .as_ref()
            .filter(|(m, _)| m.deepest > f64::NEG_INFINITY)
            .and_then(|(m, pose)| Some(Skip::new(m, self.bounds.drift(m.pose, *pose)?)));
        // A memory whose deepest node surely still overlaps is only read; otherwise (and when
        // stale) this evaluation renews it, passing over what the old notes rule out and
        // carrying their bounds (plus the drift) into the new ones.
        let recording = memory.is_some()
            && !(skip.is_some_and(|s| s.overlapping)
                && memory.as_ref().is_some_and(|(m, _)| !m.stale));
        let mut mem: Option<&mut Remembered> = memory.as_mut().map(|(m, pose)| {
            if recording && m.renew(*pose).is_none() {
                skip = None;
            }
            &mut **m
        });
        let mut computed = 0_usize;

        let mut carry = |node: &Node<T>,
                         load_gradient: T,
                         deposit_gradient: f64,
                         books: &mut Books,
                         out: &mut Output<T>|
         -> f64 {
            let g_k = load_gradient * weight;
            if g_k.value() < 0.0 {
                // A negative Simpson weight next to a zone edge: the energy's own gradient,
                // elastic only (no damping, no friction, no wear).
                let force_on_pin = [-(g_k * node.m[0]), -(g_k * node.m[1])];
                books.elastic_resultant[0] += g_k.value() * node.m[0].value();
                books.elastic_resultant[1] += g_k.value() * node.m[1].value();
                books.pull += g_k.value() * dot(&node.m, &node.m).sqrt().value();
                apply(out, node, force_on_pin);
                return 0.0;
            }
            if g_k.value() == 0.0 {
                return 0.0;
            }
            books.elastic_resultant[0] += g_k.value() * node.m[0].value();
            books.elastic_resultant[1] += g_k.value() * node.m[1].value();
            let rate = node.g_rate.value();
            let (factor, d_factor) = self.normal_law.hysteresis(rate.clamp(-onset, onset), onset);
            // Beyond the impact's range the factor is held: no partial in the rate.
            let d_factor = if rate.abs() > onset { 0.0 } else { d_factor };
            if factor <= 0.0 {
                // Clamped: the layer does not pull; its elastic load is released as damping.
                books.damping_power -= g_k.value() * node.g_rate.value();
                return 0.0;
            }
            let load = g_k * node.g_rate.chain(factor, d_factor);
            let m_norm = dot(&node.m, &node.m).sqrt();
            let t_hat = [-node.m[1] / m_norm, node.m[0] / m_norm];
            let normal = load * m_norm;
            let material = dot(&node.relative_velocity, &t_hat);
            let paper = if node.g.value() > 0.0 {
                node.g * phi_rate
            } else {
                zero
            };
            let sliding = match self.friction_sliding {
                SlidingVelocity::Material => material,
                SlidingVelocity::Paper => paper,
            };
            let friction = self.friction_law.evaluate(sliding.value(), normal.value());
            let friction_force = sliding.chain2(
                normal,
                friction.force,
                friction.d_velocity,
                friction.d_normal_force,
            );
            let force_on_pin = [
                -(load * node.m[0]) - friction_force * t_hat[0],
                -(load * node.m[1]) - friction_force * t_hat[1],
            ];
            apply(out, node, force_on_pin);

            let (load_v, normal_v, material_v) = (load.value(), normal.value(), material.value());
            books.damping_power += (load_v - g_k.value()) * node.g_rate.value();
            books.friction_power += friction.force * material_v;
            books.friction_force += friction.force;
            books.normal_resultant[0] += load_v * node.m[0].value();
            books.normal_resultant[1] += load_v * node.m[1].value();
            books.load += normal_v;
            books.load_sliding += normal_v * material_v;
            let Some(visit) = visit.as_mut() else {
                return normal_v;
            };
            let node_load = |normal_force| NodeLoad {
                cell: node.cell,
                pin_angle: node.alpha,
                bearing_angle: wrap_angle(node.bearing_angle.unwrap_or_else(|| {
                    let w = [
                        node.pin_arm[0].value() - pin_centre_arm[0].value(),
                        node.pin_arm[1].value() - pin_centre_arm[1].value(),
                    ];
                    angle_near(node.ray, w, theta_pin + node.alpha) - theta_bearing.value()
                })),
                normal_force,
                arc: self.bounds.node_arc,
                material_sliding: material_v,
                paper_sliding: paper.value(),
                stiffness: foundation.line_modulus * self.bounds.node_arc * factor * m_norm.value(),
            };
            if simpson {
                // Held until the evaluation's totals are known (the quadrature's docs).
                let trapezoid = deposit_gradient * weight * factor * m_norm.value();
                if trapezoid > 0.0 {
                    books.trapezoid_load += trapezoid;
                    deposits.push(node_load(trapezoid));
                }
            } else {
                visit(&node_load(normal_v));
            }
            normal_v
        };
        // Every computed node passes here in order: its load, and the zone it belongs to.
        let mut emit = |pending: &Pending<T>, books: &mut Books, out: &mut Output<T>| {
            let (gradient, deposit) = if simpson {
                (
                    pending.fine * (4.0 / 3.0) - pending.coarse / 3.0,
                    pending.fine.value(),
                )
            } else {
                (pending.fine, pending.fine.value())
            };
            let normal = carry(&pending.node, gradient, deposit, books, out);
            books.see_zone(pending.node.cell, pending.node.overlap, normal);
        };

        for &(first, last) in &candidates.runs[..candidates.count] {
            let n = cells as i64;
            let node_at = |k: i64| {
                self.node(
                    k.rem_euclid(n) as usize,
                    &bearing,
                    &pin,
                    &bearing_centre_arm,
                    theta_bearing,
                )
            };
            let plain = (
                Body::new(bearing_state.map(Real::value)),
                Body::new(pin_state.map(Real::value)),
            );
            let plain_arm = [bearing_centre_arm[0].value(), bearing_centre_arm[1].value()];
            // Stream the nodes, closing each node's load once all its segments are seen: its
            // neighbours' and, for Simpson, the even nodes' two neighbours two apart. A node none
            // of whose segments can be loaded (its overlap and those of the nodes it joins ≤ 0)
            // carries nothing: only its plain overlap is computed, not the node in `T`. (A
            // whole-circle window starts opposite the contact, so no segment closes the circle.)
            let mut queue = NodeQueue::<T>::default();
            // Overlaps behind (`k − 1`, `k − 2`) and ahead (`k + 1`, `k + 2`; the second only for
            // Simpson) of node `k`.
            let mut behind = [f64::NEG_INFINITY; 2];
            // Plain arithmetic would compute a node's overlap twice (here and in `node_at`), so
            // it looks ahead with the node's distance from the bearing centre: below the
            // bearing's smallest radius that is the overlap `node_at` gives, bit for bit, and
            // above it the node may overlap (+∞) and is computed in full, unless the memory
            // remembers it apart: then its gap alone, again bit for bit `node_at`'s.
            // A node the memory rules out looks ahead as −∞: not computed unless a node it
            // joins may overlap, exactly as a node below the bearing's smallest radius.
            // (A method, not a closure: called from several places, a closure is not inlined.)
            let theta = theta_bearing.value();
            macro_rules! look {
                ($k:expr) => {{
                    let k: i64 = $k;
                    if k > last {
                        (f64::NEG_INFINITY, Noted::Nothing)
                    } else {
                        self.look_ahead(
                            k.rem_euclid(n) as usize,
                            T::PLAIN,
                            &plain,
                            &plain_arm,
                            theta,
                            skip.zip(mem.as_deref()),
                        )
                    }
                }};
            }
            let nothing = (f64::NEG_INFINITY, Noted::Nothing);
            let mut here = look!(first);
            let mut ahead = [
                look!(first + 1),
                if simpson { look!(first + 2) } else { nothing },
            ];
            for k in first..=last {
                let (overlap_here, noted_here) = here;
                let coarse_node = simpson && k.rem_euclid(2) == 0;
                let joins_overlap = overlap_here > 0.0
                    || behind[0] > 0.0
                    || ahead[0].0 > 0.0
                    || (coarse_node && (behind[1] > 0.0 || ahead[1].0 > 0.0));
                let early =
                    (!T::PLAIN || overlap_here <= 0.0).then(|| books.see_overlap(overlap_here));
                if joins_overlap {
                    let node = node_at(k);
                    computed += 1;
                    if let Some(m) = mem.as_deref_mut().filter(|_| recording) {
                        m.note(node.cell, node.overlap, node.beyond);
                    }
                    if early.unwrap_or_else(|| books.see_overlap(node.overlap)) {
                        books.deepest_rate = node.g_rate.value();
                    }
                    let mut entry = Pending {
                        index: k,
                        node,
                        fine: zero,
                        coarse: zero,
                    };
                    if let Some(left) = queue.at(k - 1) {
                        let (q, dq_a, dq_b) = segment(left.node.g, entry.node.g);
                        books.energy += weight * q.value() * if simpson { 4.0 / 3.0 } else { 1.0 };
                        left.fine = left.fine + dq_a;
                        entry.fine = dq_b;
                    }
                    if coarse_node && let Some(left) = queue.at(k - 2) {
                        // The every-other-node segment spans two arcs: twice the weight.
                        let (q, dq_a, dq_b) = segment(left.node.g, entry.node.g);
                        books.energy -= weight * q.value() * (2.0 / 3.0);
                        left.coarse = left.coarse + dq_a * 2.0;
                        entry.coarse = dq_b * 2.0;
                    }
                    queue.push(entry);
                    // Close what has seen all its segments, in order.
                    while queue.front().is_some_and(|front| {
                        front.index < k
                            && (!simpson || front.index.rem_euclid(2) == 1 || front.index + 2 <= k)
                    }) && let Some(done) = queue.pop()
                    {
                        emit(&done, &mut books, &mut out);
                    }
                } else {
                    if let Some(m) = mem.as_deref_mut().filter(|_| recording) {
                        let cell = k.rem_euclid(n) as usize;
                        match (noted_here, skip) {
                            (Noted::Below, _) => m.note(cell, overlap_here, false),
                            (Noted::Gap, _) => m.note(cell, overlap_here, true),
                            (Noted::Carried, Some(skip)) => {
                                m.note(cell, skip.gap_bound(m, cell), false);
                            }
                            _ => {}
                        }
                    }
                    // Nothing left to join for the nodes waiting: their remaining segments meet
                    // overlaps ≤ 0 (else this node would have been computed).
                    while let Some(done) = queue.pop() {
                        emit(&done, &mut books, &mut out);
                    }
                }
                behind = [overlap_here, behind[0]];
                here = ahead[0];
                // The trapezoid looks one node ahead only.
                ahead = if simpson {
                    [ahead[1], look!(k + 3)]
                } else {
                    [look!(k + 2), nothing]
                };
            }
            while let Some(done) = queue.pop() {
                emit(&done, &mut books, &mut out);
            }
        }
        if let Some(visit) = visit.as_mut() {
            // Simpson's weights alternate along a zone (4/3, 2/3 of a node's arc): the wear gets
            // the trapezoid's even loads, scaled to the force's total so that the Archard
            // volume follows the load the joint carries.
            let scale = if books.trapezoid_load > 0.0 {
                ((books.load + books.pull) / books.trapezoid_load).max(0.0)
            } else {
                0.0
            };
            for load in &mut deposits {
                load.normal_force *= scale;
                visit(load);
            }
        }
        if let Some((mut m, _)) = memory {
            if recording {
                m.computed = computed;
            } else {
                m.stale = 2 * computed > m.computed;
            }
            self.bounds.memory.put(m);
        }
        if books.deepest.is_none_or(|d| d < candidates.outside_bound) {
            books.deepest = Some(candidates.outside_bound);
        }
        out.diagnostics = self.foundation_diagnostics(
            &mut books,
            rho,
            e_value,
            [
                bearing_state[0].value(),
                bearing_state[1].value(),
                theta_bearing.value(),
            ],
            [bearing_centre_arm[0].value(), bearing_centre_arm[1].value()],
            theta_pin,
            phi_rate.value(),
            centre_rate,
        );
        out
    }

    #[allow(clippy::too_many_arguments)]
    fn foundation_diagnostics(
        &self,
        books: &mut Books,
        rho: f64,
        e: [f64; 2],
        bearing_pose: [f64; 3],
        bearing_centre_arm: [f64; 2],
        theta_pin: f64,
        phi_rate: f64,
        centre_rate: f64,
    ) -> ContactDiagnostics {
        let loaded = books.load > 0.0;
        // The direction of the resultant normal force on the bearing when loaded, else the
        // line of centres.
        let direction = if loaded { books.normal_resultant } else { e };
        let contact_angle = if direction == [0.0, 0.0] {
            0.0
        } else {
            direction[1].atan2(direction[0])
        };
        let bearing_angle = wrap_angle(contact_angle - bearing_pose[2]);
        let pin_angle = wrap_angle(contact_angle - theta_pin);
        let bearing_sample = self.bearing_profile.sample(bearing_angle);
        let pin_sample = self.pin_profile.sample(pin_angle);
        let (sin, cos) = contact_angle.sin_cos();
        let centre = [
            bearing_pose[0] + bearing_centre_arm[0],
            bearing_pose[1] + bearing_centre_arm[1],
        ];
        // The deepest overlap and its rate; free, a negative distance between the outlines (or
        // their bounds) and the rate of the centres' distance.
        let (penetration, normal_velocity) = match books.deepest {
            Some(g) if g > 0.0 => (g, books.deepest_rate),
            Some(g) => (g, centre_rate),
            None => (
                rho + self.bounds.pin_max.min(1e300) - self.bounds.bearing_min,
                centre_rate,
            ),
        };
        ContactDiagnostics {
            in_contact: penetration > 0.0,
            penetration,
            eccentricity: rho,
            contact_angle,
            bearing_angle,
            pin_angle,
            bearing_radius: bearing_sample.radius,
            pin_radius: pin_sample.radius,
            normal_velocity,
            tangential_velocity: if loaded {
                books.load_sliding / books.load
            } else {
                0.0
            },
            geometric_sliding_velocity: penetration.max(0.0) * phi_rate,
            normal_force: books.normal_resultant[0].hypot(books.normal_resultant[1]),
            elastic_force: books.elastic_resultant[0].hypot(books.elastic_resultant[1]),
            friction_force: books.friction_force,
            contact_point: [
                centre[0] + bearing_sample.radius * cos,
                centre[1] + bearing_sample.radius * sin,
            ],
            elastic_energy: books.energy,
            damping_power: books.damping_power,
            friction_power: books.friction_power,
            bearing_slope: bearing_sample.slope,
            pin_slope: pin_sample.slope,
            bearing_curvature: bearing_sample.curvature,
            pin_curvature: pin_sample.curvature,
            contact_cells: books.cells,
            contact_zones: books.zones,
            narrowest_zone_cells: books.narrowest(),
            resolution_error: books.resolution_error(),
        }
    }

    /// Forces of the foundation model at the given states.
    pub(super) fn foundation_forces(
        &self,
        foundation: &Foundation,
        bearing: &BodyState,
        pin: &BodyState,
        onset_velocity: Option<f64>,
        visit: Option<&mut dyn FnMut(&NodeLoad)>,
    ) -> ContactForces {
        let out = self.foundation_eval(
            foundation,
            state_array(bearing),
            state_array(pin),
            onset_velocity,
            visit,
        );
        ContactForces {
            bearing: Vector3::from(out.bearing),
            pin: Vector3::from(out.pin),
            diagnostics: out.diagnostics,
        }
    }

    /// Forces of the foundation model and their exact Jacobian (dual numbers).
    pub(super) fn foundation_forces_and_jacobian(
        &self,
        foundation: &Foundation,
        bearing: &BodyState,
        pin: &BodyState,
        onset_velocity: Option<f64>,
    ) -> (ContactForces, ContactJacobian) {
        let seed = |state: &BodyState, offset: usize| -> [Dual; 6] {
            let values = state_array(state);
            // Positions are columns 0–2 (bearing) and 3–5 (pin), velocities 6–8 and 9–11.
            std::array::from_fn(|k| {
                let column = if k < 3 {
                    offset + k
                } else {
                    6 + offset + k - 3
                };
                Dual::variable(values[k], column)
            })
        };
        let out = self.foundation_eval(
            foundation,
            seed(bearing, 0),
            seed(pin, 3),
            onset_velocity,
            None,
        );
        let mut jacobian = ContactJacobian::zeros();
        for (row, value) in out.bearing.iter().chain(&out.pin).enumerate() {
            for (column, partial) in value.partials.iter().enumerate() {
                jacobian[(row, column)] = *partial;
            }
        }
        let forces = ContactForces {
            bearing: Vector3::new(
                out.bearing[0].value,
                out.bearing[1].value,
                out.bearing[2].value,
            ),
            pin: Vector3::new(out.pin[0].value, out.pin[1].value, out.pin[2].value),
            diagnostics: out.diagnostics,
        };
        (forces, jacobian)
    }

    /// The deepest overlap of the outlines (m; negative when apart): the foundation's event
    /// function. In free flight, the gap between the outlines' radius bounds.
    pub(super) fn foundation_overlap(
        &self,
        foundation: &Foundation,
        bearing_body: &BodyState,
        pin_body: &BodyState,
    ) -> f64 {
        let bearing = Body::new(state_array(bearing_body));
        let pin = Body::new(state_array(pin_body));
        let bearing_centre_arm = bearing.rotate([self.bearing_centre.x, self.bearing_centre.y]);
        let pin_centre_arm = pin.rotate([self.pin_centre.x, self.pin_centre.y]);
        let e = offset(&pin, &pin_centre_arm, &bearing, &bearing_centre_arm);
        let cells = foundation.cells;
        // The nodes that may overlap (the runs' outer nodes, which cannot, are sampled too).
        let candidates = self.candidates(cells, e, (pin_body.theta, bearing_body.theta), 1);
        let mut deepest = candidates.outside_bound;
        // The overlap memory skips the nodes that cannot beat the deepest so far (read only).
        let memory = self
            .bounds
            .bearing_slope
            .and_then(|_| self.bounds.memory.take())
            .filter(|m| m.overlap.len() == cells);
        let skip = memory.as_deref().and_then(|m| {
            let now = Pose::new(e, bearing.theta_sin_cos, bearing_body.theta, pin_body.theta);
            Some((Skip::new(m, self.bounds.drift(m.pose, now)?), m))
        });
        let floor = skip.map_or(f64::NEG_INFINITY, |(skip, _)| skip.floor);
        let runs = &candidates.runs[..candidates.count];
        let n = cells as i64;
        let overlap_of = |cell: usize, deepest: f64, gap_bound: f64| {
            self.overlap_at(
                cell,
                &bearing,
                &pin,
                &bearing_centre_arm,
                bearing_body.theta,
                deepest,
                gap_bound,
            )
        };
        // The memory's deepest node first: when it still overlaps, every node whose bound does
        // not beat it is passed over below without being placed. (The maximum over the
        // candidate runs does not depend on the order in which their nodes come.)
        if let Some(cell) = skip.and_then(|(_, m)| m.deepest_cell)
            && runs
                .iter()
                .any(|&(first, last)| (cell as i64 - first).rem_euclid(n) <= last - first)
            && let Some(g) = overlap_of(cell, deepest, f64::INFINITY)
        {
            deepest = deepest.max(g);
        }
        for k in runs.iter().flat_map(|&(first, last)| first..=last) {
            let cell = k.rem_euclid(n) as usize;
            let gap_bound = skip.map_or(f64::INFINITY, |(skip, m)| skip.gap_bound(m, cell));
            let gap_bound = if gap_bound < floor {
                f64::NEG_INFINITY
            } else {
                gap_bound
            };
            // Once something overlaps, a node beyond the smallest radius cannot beat it past its
            // bound, and one within it not at all (`overlap_at` would say `None` either way).
            if deepest > 0.0 && gap_bound <= deepest {
                continue;
            }
            if let Some(g) = overlap_of(cell, deepest, gap_bound) {
                deepest = deepest.max(g);
            }
        }
        if let Some(m) = memory {
            self.bounds.memory.put(m);
        }
        deepest
    }
}

fn state_array(state: &BodyState) -> [f64; 6] {
    [
        state.x,
        state.y,
        state.theta,
        state.vx,
        state.vy,
        state.omega,
    ]
}

#[cfg(test)]
mod tests {
    use super::{angle_near, segment};
    use rand::{Rng, SeedableRng};
    use std::f64::consts::{PI, TAU};

    /// A node's ray angle from the small-angle series agrees with `atan2` to rounding (modulo
    /// 2π) over random pins and eccentricities up to a tenth of the radius (past 1/16 rad it
    /// is `atan2` itself), and falls back to `atan2` where the node's own direction is far off.
    #[test]
    fn a_rays_angle_near_its_nodes_direction_matches_atan2() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let mut worst: f64 = 0.0;
        let mut series = 0;
        for _ in 0..100_000 {
            let radius = rng.random_range(0.01..0.2);
            let turn = rng.random_range(-50.0..50.0);
            let w_angle: f64 = turn + rng.random_range(0.0..TAU);
            let w = [radius * w_angle.cos(), radius * w_angle.sin()];
            let (size, direction) = (
                rng.random_range(0.0..0.1 * radius),
                rng.random_range(0.0..TAU),
            );
            let d = [w[0] + size * direction.cos(), w[1] + size * direction.sin()];
            let near = angle_near(d, w, w_angle);
            let exact = d[1].atan2(d[0]);
            let apart = (near - exact + PI).rem_euclid(TAU) - PI;
            // The rounding of an angle of up to 56 rad (8 ulp there is 6e-14), not of the
            // small one.
            worst = worst.max(apart.abs());
            let z = (w[0] * d[1] - w[1] * d[0]) / (w[0] * d[0] + w[1] * d[1]);
            series += usize::from(z.abs() <= 0.0625);
        }
        assert!(worst < 6e-14, "worst {worst:e}");
        assert!(series > 50_000, "the series ran {series} times");
        // Opposite directions: atan2.
        assert_eq!(
            angle_near([-1.0, 1e-3], [1.0, 0.0], 0.0),
            1e-3_f64.atan2(-1.0)
        );
    }

    /// The segment energy and its partials are continuous, with continuous partials, as a node
    /// crosses zero: the force is C¹ across a zone edge.
    #[test]
    fn segment_is_smooth_across_a_zone_edge() {
        let a = 3e-6;
        for b in [1e-14, -1e-14] {
            let (q, qa, qb) = segment(a, b);
            // Both sides of b = 0 give the edge values to within b/a = 3e-9.
            assert!((q / (a * a / 3.0) - 1.0).abs() < 1e-8, "{q}");
            assert!((qa / (2.0 * a / 3.0) - 1.0).abs() < 1e-8, "{qa}");
            assert!((qb / (a / 3.0) - 1.0).abs() < 1e-8, "{qb}");
        }
        // Second derivatives: ∂²Q/∂b² tends to 2/3 from both sides (2/3 · (a/(a − b))³ below).
        let h = 1e-11;
        let second = |b: f64| (segment(a, b + h).2 - segment(a, b - h).2) / (2.0 * h);
        for b in [1e-10, -1e-10] {
            assert!((second(b) - 2.0 / 3.0).abs() < 1e-3, "{}", second(b));
        }
        // Against a fine quadrature of the definition.
        for (a, b) in [(2e-6, -5e-6), (-1e-6, 4e-6), (1e-6, 2e-6), (-1.0, -2.0)] {
            let n = 200_000;
            let quad: f64 = (0..n)
                .map(|k| {
                    let s = (k as f64 + 0.5) / n as f64;
                    let v = f64::max(0.0, a + (b - a) * s);
                    v * v
                })
                .sum::<f64>()
                / n as f64;
            let (q, _, _) = segment(a, b);
            assert!(
                (q - quad).abs() <= 1e-8 * quad.max(1e-30),
                "{a} {b}: {q} vs {quad}"
            );
        }
    }
}
