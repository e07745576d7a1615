//! The thin-gap evaluation: the loaded window of nodes, each node's overlap, its share of the
//! energy's gradient, damping and friction, and the forces on both bodies (plain numbers for
//! the forces, dual numbers for their exact Jacobian).

use nalgebra::Vector3;

use super::layer::{ThinGap, ThinGapWorkspace, with_overlaps};
use super::tables::{Shift, ThinGapTables};
use crate::diagnostics::ContactDiagnostics;
use crate::friction::FrictionLaw;
use crate::joint::dual::{Real, body_variables, jacobian};
use crate::joint::foundation::books::{Books, LayerPose};
use crate::joint::foundation::geometry::{Body, cross, dot, offset};
use crate::joint::foundation::stream::segment;
use crate::joint::foundation::{Quadrature, Sink};
use crate::joint::model::{NodeLoad, Visit};
use crate::joint::pair::ContactPair;
use crate::joint::types::{ContactForces, ContactJacobian, JointState, SlidingVelocity};
use crate::normal::NormalLaw;
use crate::surface::{SurfaceProfile, wrap_angle};

/// One evaluation's model, pair and tables.
pub(super) struct Kernel<'k, B, P, N, F> {
    model: &'k ThinGap,
    pair: &'k ContactPair<B, P, N, F>,
    tables: &'k ThinGapTables,
}

/// The pose in the bearing's frame, in the evaluation's arithmetic.
struct Pose<T> {
    /// `ε`, the pin centre from the bearing centre (m), and its rate (m/s).
    eps: [T; 2],
    eps_rate: [T; 2],
    /// `Δ = θ_j − θ_i` (rad) and its rate.
    turn: T,
    turn_rate: T,
}

/// The nodes one evaluation visits, signed and in order (`first..=last`, wrapping), or none.
#[derive(Clone, Copy)]
struct Window {
    first: i64,
    last: i64,
    /// Bound on every overlap outside it (m).
    outside: f64,
}

impl Window {
    /// The padded table indexes of its nodes and `beyond` more at each end (`beyond` ≤ 2):
    /// one contiguous range, the modulo taken once ([`super::tables::padded_nodes`]).
    fn nodes(&self, cells: usize, beyond: i64) -> std::ops::Range<usize> {
        let start = (self.first - beyond).rem_euclid(cells as i64) as usize;
        start..start + (self.last - self.first + 1 + 2 * beyond) as usize
    }
}

/// The sums of the forces over the nodes, in the bearing's frame.
struct Sums<T> {
    /// `Σ L_k m_k` (the normal loads; elastic pulls of Simpson's negative weights included).
    normal: [T; 2],
    /// `Σ f_k t̂_k`, the friction forces.
    friction: [T; 2],
    /// `Σ L_k ∂g_k/∂Δ`: the moment the pin's turn carries.
    turn: T,
    /// `Σ q_k × f_k t̂_k`: the friction's moment about the bearing centre.
    friction_moment: T,
    /// The neglected terms' estimate summed over the overlapping nodes (m).
    neglected: f64,
}

/// Per-evaluation constants of the node loop.
struct Pass<T> {
    /// `k w · arc/2` (N/m).
    weight: f64,
    simpson: bool,
    onset: f64,
    /// The paper's sliding rate `φ̇ = e × ė/|e|²` (rad/s).
    phi_rate: T,
    shift: Shift,
    /// `1/R` (1/m).
    inverse_radius: f64,
}

/// One node's quantities beyond its overlap, for its force.
struct NodeForce<T> {
    m: [T; 2],
    /// `∂g_k/∂Δ` (m/rad).
    d_turn: T,
    rate: T,
    /// `g_k` (m).
    g: T,
    /// The estimate of what `g_k` neglects (m), where it is positive.
    neglected: f64,
}

impl<'k, B: SurfaceProfile, P: SurfaceProfile, N: NormalLaw, F: FrictionLaw>
    Kernel<'k, B, P, N, F>
{
    pub(super) fn new(
        model: &'k ThinGap,
        pair: &'k ContactPair<B, P, N, F>,
        tables: &'k ThinGapTables,
    ) -> Self {
        Self {
            model,
            pair,
            tables,
        }
    }

    pub(super) fn forces(
        &self,
        workspace: &mut ThinGapWorkspace,
        at: JointState,
        visit: Visit,
    ) -> ContactForces {
        let out = self.evaluate(
            workspace,
            at.bearing.coordinates(),
            at.pin.coordinates(),
            at.onset_velocity,
            visit,
        );
        ContactForces {
            bearing: Vector3::from(out.0),
            pin: Vector3::from(out.1),
            diagnostics: out.2,
        }
    }

    pub(super) fn forces_and_jacobian(
        &self,
        workspace: &mut ThinGapWorkspace,
        at: JointState,
    ) -> (ContactForces, ContactJacobian) {
        let (bearing, pin, diagnostics) = self.evaluate(
            workspace,
            body_variables(at.bearing, 0),
            body_variables(at.pin, 3),
            at.onset_velocity,
            None,
        );
        let jacobian = jacobian(&bearing, &pin);
        let forces = ContactForces {
            bearing: Vector3::from(bearing.map(|v| v.value)),
            pin: Vector3::from(pin.map(|v| v.value)),
            diagnostics,
        };
        (forces, jacobian)
    }

    /// The deepest overlap at the nodes (m; negative apart): the event function. Free, the
    /// window's bound.
    pub(super) fn deepest(&self, workspace: &mut ThinGapWorkspace, at: JointState) -> f64 {
        let bearing = Body::new(at.bearing.coordinates());
        let pin = Body::new(at.pin.coordinates());
        let pose = self.pose(&bearing, &pin, at.pin.theta - at.bearing.theta);
        // One node beyond the arc each side: the bound outside it is then negative.
        let Some(window) = self.window(pose.eps, 1) else {
            return self.outside_bound(pose.eps);
        };
        let shift = Shift::new(pose.turn, self.tables.cells);
        let nodes = window.nodes(self.tables.cells, 0);
        let inverse_radius = 1.0 / self.tables.reference;
        let ThinGapWorkspace {
            weighed, overlaps, ..
        } = workspace;
        with_overlaps(weighed, overlaps, nodes.len(), |weighed, overlaps| {
            self.sweep(nodes, pose.eps, &shift, inverse_radius, weighed, overlaps);
            overlaps.iter().copied().fold(window.outside, f64::max)
        })
    }

    /// The pose of the pin in the bearing's frame.
    fn pose<T: Real>(&self, bearing: &Body<T>, pin: &Body<T>, turn: T) -> Pose<T> {
        let arm_i = bearing.rotate(self.pair.bearing_centre());
        let arm_j = pin.rotate(self.pair.pin_centre());
        let e = offset(pin, &arm_j, bearing, &arm_i);
        let e_rate = {
            let p = pin.point_velocity(&arm_j);
            let b = bearing.point_velocity(&arm_i);
            [p[0] - b[0], p[1] - b[1]]
        };
        let (s, c) = bearing.theta_sin_cos;
        let eps = [c * e[0] + s * e[1], c * e[1] - s * e[0]];
        // ε = Aᵀe, so ε̇ = Aᵀė − ω_i ε⊥.
        let eps_rate = [
            c * e_rate[0] + s * e_rate[1] + bearing.omega * eps[1],
            c * e_rate[1] - s * e_rate[0] - bearing.omega * eps[0],
        ];
        Pose {
            eps,
            eps_rate,
            turn,
            turn_rate: pin.omega - bearing.omega,
        }
    }

    /// A bound on the overlap of every node at eccentricity `eps` (m).
    fn outside_bound<T: Real>(&self, eps: [T; 2]) -> f64 {
        let rho = eps[0].value().hypot(eps[1].value());
        rho + self.slack(rho)
    }

    /// `R_j⁺ − R_i⁻ + max|r'| ρ/r⁻ + max(r'', 0) ρ²/(2r⁻²)` (m, `r⁻` the pin's smallest
    /// radius): a node at angle `ψ` from `ε` overlaps by at most `ρ cos ψ` plus this.
    fn slack(&self, rho: f64) -> f64 {
        let t = self.tables;
        let shift = rho * inverse_radius_at(t.pin_min, 1.0 / t.reference);
        t.pin_max - t.bearing_min + t.pin_slope_max * shift + 0.5 * t.bend_max * shift * shift
    }

    /// The nodes that can overlap and `beyond` more at each end, or `None` when none can.
    fn window<T: Real>(&self, eps: [T; 2], beyond: i64) -> Option<Window> {
        let (x, y) = (eps[0].value(), eps[1].value());
        let rho = x.hypot(y);
        let slack = self.slack(rho);
        if rho + slack <= 0.0 {
            return None;
        }
        let cells = self.tables.cells as i64;
        let per_rad = self.tables.cells as f64 / std::f64::consts::TAU;
        let direction = y.atan2(x);
        let half = (-slack / rho).clamp(-1.0, 1.0).acos();
        let first = ((direction - half) * per_rad - 0.5).ceil() as i64 - beyond;
        let last = ((direction + half) * per_rad - 0.5).floor() as i64 + beyond;
        if last - first + 1 >= cells {
            // Every node (the bounds allow it): the whole circle from opposite `ε`, where the
            // outlines are furthest apart, so that no segment joins its two ends.
            let away = ((direction + std::f64::consts::PI) * per_rad - 0.5).round() as i64;
            return Some(Window {
                first: away,
                last: away + cells - 1,
                outside: f64::NEG_INFINITY,
            });
        }
        Some(Window {
            first,
            last,
            // The nodes outside lie more than `beyond` nodes past the arc `ρ cos ψ > −slack`.
            outside: (rho
                * (half + beyond as f64 / per_rad)
                    .min(std::f64::consts::PI)
                    .cos()
                + slack)
                .min(0.0),
        })
    }

    /// The overlap of the node at padded index `node`, weighed by the pin's outline,
    /// `g̃_k = g_k (1 + a_k/(2r_k))` (m), in the arithmetic of the pose, and its overlap `g_k` (m).
    #[inline(always)]
    fn gap<T: Real>(
        &self,
        node: usize,
        pose: &Pose<T>,
        shift: &Shift,
        inverse_radius: f64,
    ) -> (T, f64) {
        let t = self.tables;
        let (cos, sin) = (t.cos[node], t.sin[node]);
        let a = pose.eps[0] * cos + pose.eps[1] * sin;
        let b = pose.eps[1] * cos - pose.eps[0] * sin;
        let (value, slope, curvature) = t.pin_at(node, shift);
        let (bend, bend_slope, _) = t.bend_at(node, shift);
        // The pin's radius, slope and curvature at `θ_k − Δ`: their partials in Δ are minus
        // the next derivative.
        let radius = pose.turn.chain(value, -slope);
        let slope = pose.turn.chain(slope, -curvature);
        let bend = pose.turn.chain(bend, -bend_slope);
        weighed_overlap(
            [a, b],
            [radius, slope, bend],
            t.bearing[node],
            inverse_radius,
        )
    }

    /// [`Self::gap`] in plain numbers of the nodes at the padded indexes `nodes`, into
    /// `weighed` (`g̃_k`) and `overlaps` (`g_k`), as many as there are nodes: one straight
    /// sweep over the tables, no branch and no bounds check per node, that the compiler
    /// turns into packed arithmetic.
    fn sweep(
        &self,
        nodes: std::ops::Range<usize>,
        eps: [f64; 2],
        shift: &Shift,
        inverse_radius: f64,
        weighed: &mut [f64],
        overlaps: &mut [f64],
    ) {
        let t = self.tables;
        let n = nodes.len();
        let (cos, sin, bearing) = (
            &t.cos[nodes.clone()],
            &t.sin[nodes.clone()],
            &t.bearing[nodes.clone()],
        );
        // The four control points of node `i` are `pin[base + i + j]`, `j` in 0..4.
        let base = nodes.start + shift.offset;
        let taps = |table: &'k [f64]| [0, 1, 2, 3].map(|j| &table[base + j..base + j + n]);
        let (pin, bend) = (taps(&t.pin), taps(&t.bend));
        let (weighed, overlaps) = (&mut weighed[..n], &mut overlaps[..n]);
        for i in 0..n {
            let a = eps[0] * cos[i] + eps[1] * sin[i];
            let b = eps[1] * cos[i] - eps[0] * sin[i];
            let (radius, slope, _) = shift.read([pin[0][i], pin[1][i], pin[2][i], pin[3][i]]);
            let (bend, _, _) = shift.read([bend[0][i], bend[1][i], bend[2][i], bend[3][i]]);
            let (w, g) = weighed_overlap([a, b], [radius, slope, bend], bearing[i], inverse_radius);
            weighed[i] = w;
            overlaps[i] = g;
        }
    }

    /// The normal `m̃_k = ∂g̃_k/∂ε` of the node at padded index `node`, `∂g̃_k/∂Δ`, its rate,
    /// its overlap `g_k` and, where it overlaps, the estimate of what its overlap neglects,
    /// given its weighed overlap `g̃_k`.
    #[inline]
    fn node_force<T: Real>(
        &self,
        node: usize,
        pose: &Pose<T>,
        weighed: T,
        shift: &Shift,
        inverse_radius: f64,
    ) -> NodeForce<T> {
        let t = self.tables;
        let (cos, sin) = (t.cos[node], t.sin[node]);
        let a = pose.eps[0] * cos + pose.eps[1] * sin;
        let b = pose.eps[1] * cos - pose.eps[0] * sin;
        let (value, slope, curvature) = t.pin_at(node, shift);
        let (bend, bend_slope, bend_curvature) = t.bend_at(node, shift);
        let third = if T::PLAIN {
            0.0
        } else {
            t.pin_third_at(node, shift)
        };
        let neglected = if weighed.value() > 0.0 {
            t.reference
                * neglected(
                    b.value() * inverse_radius,
                    [value, slope, curvature, bend, bend_slope],
                    inverse_radius,
                )
        } else {
            0.0
        };
        let radius = pose.turn.chain(value, -slope);
        let slope = pose.turn.chain(slope, -curvature);
        let curvature = pose.turn.chain(curvature, -third);
        let bend = pose.turn.chain(bend, -bend_slope);
        let bend_slope = pose.turn.chain(bend_slope, -bend_curvature);
        // `ι = 1/r_k` and `∂ι/∂Δ = r'_k/R²` (the radius's partial in Δ is `−r'_k`).
        let inverse = inverse_radius_at(radius, inverse_radius);
        let d_inverse = slope * (inverse_radius * inverse_radius);
        let reading = b * inverse;
        let lean = (slope + b - bend * reading) * inverse;
        // g̃ = g J, J = 1 + a ι/2: ∂g̃ = J ∂g + g ∂J, ∂J/∂ε = ι n/2, ∂J/∂Δ = a (∂ι/∂Δ)/2.
        let weigh = a * (inverse * 0.5) + 1.0;
        let g = weighed / weigh;
        let half_g = g * (inverse * 0.5);
        let m = [
            (lean * sin + cos) * weigh + half_g * cos,
            (-(lean * cos) + sin) * weigh + half_g * sin,
        ];
        // With `q = b ι` and `κ` the curvature spline's:
        // ∂g/∂Δ = −r' + r'' q − (r' + b/2 − κ q) b ∂ι/∂Δ − κ' q²/2.
        let d_gap = curvature * reading
            - slope
            - (slope + b * 0.5 - bend * reading) * b * d_inverse
            - bend_slope * reading * reading * 0.5;
        let d_turn = d_gap * weigh + g * a * (d_inverse * 0.5);
        let rate = dot(&m, &pose.eps_rate) + d_turn * pose.turn_rate;
        NodeForce {
            m,
            d_turn,
            rate,
            g,
            neglected,
        }
    }

    /// The kernel: generalized forces on bearing and pin and the diagnostics; each loaded
    /// node to `visit`.
    fn evaluate<T: Real>(
        &self,
        workspace: &mut ThinGapWorkspace,
        bearing_state: [T; 6],
        pin_state: [T; 6],
        onset_velocity: Option<f64>,
        visit: Visit,
    ) -> ([T; 3], [T; 3], ContactDiagnostics) {
        let layer = self.model.layer();
        let cells = self.tables.cells;
        let bearing = Body::new(bearing_state);
        let pin = Body::new(pin_state);
        let pose = self.pose(&bearing, &pin, pin_state[2] - bearing_state[2]);
        let arm_i = bearing.rotate(self.pair.bearing_centre());
        let arm_j = pin.rotate(self.pair.pin_centre());
        let e = offset(&pin, &arm_j, &bearing, &arm_i);
        let e_value = [e[0].value(), e[1].value()];
        let rho = e_value[0].hypot(e_value[1]);
        let e_rate = {
            let p = pin.point_velocity(&arm_j);
            let b = bearing.point_velocity(&arm_i);
            [p[0] - b[0], p[1] - b[1]]
        };
        let (phi_rate, centre_rate) = if rho > 0.0 {
            (
                cross(&e, &e_rate) / dot(&e, &e),
                (e_value[0] * e_rate[0].value() + e_value[1] * e_rate[1].value()) / rho,
            )
        } else {
            (T::constant(0.0), 0.0)
        };
        let onset = self.pair.normal_law().effective_onset(
            onset_velocity
                .unwrap_or(centre_rate)
                .abs()
                .max(layer.reference_speed),
        );
        let simpson = layer.quadrature == Quadrature::Simpson;
        let pass = Pass {
            weight: 0.5 * layer.line_modulus * self.tables.node_arc,
            simpson,
            onset,
            phi_rate,
            shift: Shift::new(pose.turn.value(), cells),
            inverse_radius: 1.0 / self.tables.reference,
        };
        let zero = T::constant(0.0);
        let mut sums = Sums {
            normal: [zero; 2],
            friction: [zero; 2],
            turn: zero,
            friction_moment: zero,
            neglected: 0.0,
        };
        let mut books = Books {
            grid: cells,
            quadrature: layer.quadrature,
            ..Books::default()
        };
        let window = self.window(pose.eps, if simpson { 2 } else { 1 });
        // Padded indexes of nodes `first − 2 ..= last + 2` (`first`, `last` the window's);
        // their overlaps in the buffers in the same order, node `first` at 2.
        let nodes = window.map_or(0..0, |w| w.nodes(cells, 2));
        let ThinGapWorkspace {
            deposits,
            weighed,
            overlaps,
        } = workspace;
        deposits.clear();
        let mut sink = Sink { visit, deposits };
        let mut overlapping = 0.0;
        let n = nodes.len();
        if let Some(window) = window {
            with_overlaps(weighed, overlaps, n, |weighed, overlaps| {
                let eps = [pose.eps[0].value(), pose.eps[1].value()];
                let before = nodes.start;
                self.sweep(
                    nodes,
                    eps,
                    &pass.shift,
                    pass.inverse_radius,
                    weighed,
                    overlaps,
                );
                let (weighed, overlaps) = (&*weighed, &*overlaps);
                let first = window.first;
                // Node `first + i − 2`'s index in `0..N` (books and wear).
                let cell_of = |i: usize| (first + i as i64 - 2).rem_euclid(cells as i64) as usize;
                // Whether a positive overlap reaches the node at buffer index `i` through a
                // segment of its own (the fine segments, Simpson's coarse ones at even cells).
                let reaches_at = |i: usize, cell: usize| {
                    weighed[i - 1] > 0.0
                        || overlaps[i] > 0.0
                        || weighed[i + 1] > 0.0
                        || (simpson
                            && cell.is_multiple_of(2)
                            && (weighed[i - 2] > 0.0 || weighed[i + 2] > 0.0))
                };
                let reaches = |i: usize| reaches_at(i, cell_of(i));
                // A node reaches only within two of a positive overlap: the search for the first
                // and the last that reach starts there.
                let end = overlaps.len() - 3;
                let positive = |(w, g): (&f64, &f64)| *w > 0.0 || *g > 0.0;
                let pairs = || weighed.iter().zip(overlaps);
                let reached = pairs().position(positive).and_then(|p| {
                    let lo = (p.saturating_sub(2).max(2)..=end).find(|&i| reaches(i))?;
                    let q = pairs().rposition(positive).unwrap_or(p);
                    let hi = (lo..=(q + 2).min(end)).rev().find(|&i| reaches(i));
                    Some((lo, hi.unwrap_or(lo)))
                });
                // The nodes no overlap reaches carry nothing: only their overlaps are seen.
                let (lo, hi) = reached.unwrap_or((end + 1, end));
                for &g in &overlaps[2..lo] {
                    books.see_overlap(g);
                }
                let gap_at = |i: usize| {
                    if T::PLAIN {
                        T::constant(weighed[i])
                    } else {
                        self.gap(before + i, &pose, &pass.shift, pass.inverse_radius)
                            .0
                    }
                };
                // Weighed overlaps of the nodes at i − 2 ..= i + 2.
                let ring_at = |i: usize| std::array::from_fn::<_, 5, _>(|j| gap_at(i - 2 + j));
                let mut ring = if lo <= hi {
                    ring_at(lo)
                } else {
                    [T::constant(0.0); 5]
                };
                let mut cell = cell_of(lo);
                // Node `i` reaches (`lo` and `hi` do; between them the nodes that do not are
                // stepped over in one search).
                let mut i = lo;
                while i <= hi {
                    let k = first + i as i64 - 2;
                    let g = overlaps[i];
                    let deepest = books.see_overlap(g);
                    let coarse = simpson && cell.is_multiple_of(2);
                    // The segment to the left (its energy) and this node's share of both.
                    let (q_left, _, left) = segment(ring[1], ring[2]);
                    let (_, right, _) = segment(ring[2], ring[3]);
                    let fine = left + right;
                    let (gradient, fine_energy) = if simpson {
                        let mut gradient = fine * (4.0 / 3.0);
                        let mut energy = q_left.value() * (4.0 / 3.0);
                        if coarse {
                            let (q_coarse, _, coarse_left) = segment(ring[0], ring[2]);
                            let (_, coarse_right, _) = segment(ring[2], ring[4]);
                            gradient = gradient - (coarse_left + coarse_right) * (2.0 / 3.0);
                            if k - 2 >= first {
                                energy -= q_coarse.value() * (2.0 / 3.0);
                            }
                        }
                        (gradient, energy)
                    } else {
                        (fine, q_left.value())
                    };
                    // The first node's left segments join nodes outside the window (overlaps ≤ 0).
                    if k > first {
                        books.energy += pass.weight * fine_energy;
                    }
                    if g > 0.0 {
                        overlapping += g;
                    }
                    let load_gradient = gradient * pass.weight;
                    let normal = self.carry(
                        &pass,
                        (before + i, cell),
                        &pose,
                        ring[2],
                        load_gradient,
                        fine.value() * pass.weight,
                        &mut sums,
                        &mut books,
                        &mut sink,
                    );
                    if deepest {
                        books.deepest_rate = normal.1;
                    }
                    books.see_zone(cell, g, normal.0);
                    if i == hi {
                        break;
                    }
                    cell += 1;
                    if cell == cells {
                        cell = 0;
                    }
                    if reaches_at(i + 1, cell) {
                        i += 1;
                        ring.rotate_left(1);
                        ring[4] = gap_at(i + 2);
                        continue;
                    }
                    // The next node that reaches (`hi` does) is `i + 2`, reached from `i`, or lies
                    // within two of the next positive overlap; those between are apart and only
                    // seen, their zone closed.
                    let after = weighed[i + 1..]
                        .iter()
                        .zip(&overlaps[i + 1..])
                        .position(positive)
                        .map_or(hi, |p| i + 1 + p);
                    let next = std::iter::once(i + 2)
                        .chain(after.saturating_sub(2).max(i + 3)..=hi)
                        .find(|&j| j <= hi && reaches(j))
                        .unwrap_or(hi);
                    for &g in &overlaps[i + 1..next] {
                        books.see_overlap(g);
                    }
                    books.close_zone();
                    i = next;
                    cell = cell_of(i);
                    ring = ring_at(i);
                }
                for &g in &overlaps[(hi + 1).max(lo)..=end] {
                    books.see_overlap(g);
                }
                books.close_zone();
            });
        }
        sink.deposit(&books);
        let (s, c) = bearing.theta_sin_cos;
        let turned = |v: [T; 2]| [c * v[0] - s * v[1], s * v[0] + c * v[1]];
        let pushed = [
            sums.normal[0] + sums.friction[0],
            sums.normal[1] + sums.friction[1],
        ];
        let on_bearing = turned(pushed);
        let pin_force = [-on_bearing[0], -on_bearing[1]];
        let pin_out = [
            pin_force[0],
            pin_force[1],
            cross(&arm_j, &pin_force) - sums.turn - sums.friction_moment
                + cross(&pose.eps, &sums.friction),
        ];
        let bearing_out = [
            on_bearing[0],
            on_bearing[1],
            cross(&arm_i, &on_bearing)
                + cross(&pose.eps, &sums.normal)
                + sums.turn
                + sums.friction_moment,
        ];
        let outside = window.map_or_else(|| self.outside_bound(pose.eps), |w| w.outside);
        if books.deepest.is_none_or(|d| d < outside) {
            books.deepest = Some(outside);
        }
        let theta_i = bearing_state[2].value();
        let resultant = |v: [f64; 2]| {
            let (s, c) = (s.value(), c.value());
            [c * v[0] - s * v[1], s * v[0] + c * v[1]]
        };
        books.normal_resultant = resultant(books.normal_resultant);
        books.elastic_resultant = resultant(books.elastic_resultant);
        let centre = {
            let (x, y) = (bearing_state[0].value(), bearing_state[1].value());
            [x + arm_i[0].value(), y + arm_i[1].value()]
        };
        let mut diagnostics = books.diagnostics(
            self.pair.bearing_profile(),
            self.pair.pin_profile(),
            LayerPose {
                rho,
                e: e_value,
                centre,
                angles: (theta_i, pin_state[2].value()),
                phi_rate: phi_rate.value(),
                centre_rate,
                free_gap: rho + self.slack(rho),
            },
        );
        diagnostics.neglected_terms = if overlapping > 0.0 {
            sums.neglected / overlapping
        } else {
            0.0
        };
        (bearing_out, pin_out, diagnostics)
    }

    /// A node's share (`at`: its padded table index and its index in `0..N`): its elastic load
    /// `G_k`, damping and friction on it, their sums, the books and its wear load. Returns the
    /// node's normal load (N) and its rate `ġ_k` (m/s).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn carry<T: Real>(
        &self,
        pass: &Pass<T>,
        (node, cell): (usize, usize),
        pose: &Pose<T>,
        weighed: T,
        load_gradient: T,
        deposit_gradient: f64,
        sums: &mut Sums<T>,
        books: &mut Books,
        sink: &mut Sink<'_, '_>,
    ) -> (f64, f64) {
        let elastic = load_gradient.value();
        if elastic == 0.0 {
            return (0.0, 0.0);
        }
        let force = self.node_force(node, pose, weighed, &pass.shift, pass.inverse_radius);
        sums.neglected += force.neglected;
        let g = force.g;
        let rate = force.rate.value();
        books.elastic_resultant[0] += elastic * force.m[0].value();
        books.elastic_resultant[1] += elastic * force.m[1].value();
        if elastic < 0.0 {
            // A negative Simpson weight next to a zone edge: the energy's own gradient,
            // elastic only (no damping, no friction, no wear).
            sums.normal[0] = sums.normal[0] + load_gradient * force.m[0];
            sums.normal[1] = sums.normal[1] + load_gradient * force.m[1];
            sums.turn = sums.turn + load_gradient * force.d_turn;
            books.pull += elastic * norm(&force.m).value();
            return (0.0, rate);
        }
        let (factor, d_factor) = self
            .pair
            .normal_law()
            .hysteresis(rate.clamp(-pass.onset, pass.onset), pass.onset);
        // Beyond the impact's range the factor is held: no partial in the rate.
        let d_factor = if rate.abs() > pass.onset {
            0.0
        } else {
            d_factor
        };
        if factor <= 0.0 {
            // Clamped: the layer does not pull; its elastic load is released as damping.
            books.damping_power -= elastic * rate;
            return (0.0, rate);
        }
        let load = load_gradient * force.rate.chain(factor, d_factor);
        let m_norm = norm(&force.m);
        let t_hat = [-force.m[1] / m_norm, force.m[0] / m_norm];
        let normal = load * m_norm;
        // The pin's point on the ray, from the bearing centre, and the relative velocity of the
        // pin's material point there on the bearing's (bearing frame): ε̇ + Δ̇ (q − ε)⊥.
        let t = self.tables;
        let (cos, sin) = (t.cos[node], t.sin[node]);
        let reach = g + (t.reference + t.bearing[node]);
        let q = [reach * cos, reach * sin];
        let arm = [q[0] - pose.eps[0], q[1] - pose.eps[1]];
        let relative = [
            pose.eps_rate[0] - pose.turn_rate * arm[1],
            pose.eps_rate[1] + pose.turn_rate * arm[0],
        ];
        let material = dot(&relative, &t_hat);
        let paper = g.value().max(0.0) * pass.phi_rate.value();
        let sliding = match self.pair.friction_sliding {
            SlidingVelocity::Material => material,
            SlidingVelocity::Paper if g.value() > 0.0 => g * pass.phi_rate,
            SlidingVelocity::Paper => T::constant(0.0),
        };
        let friction = self
            .pair
            .friction_law()
            .evaluate(sliding.value(), normal.value());
        let friction_force = sliding.chain2(
            normal,
            friction.force,
            friction.d_velocity,
            friction.d_normal_force,
        );
        let along = [friction_force * t_hat[0], friction_force * t_hat[1]];
        sums.normal[0] = sums.normal[0] + load * force.m[0];
        sums.normal[1] = sums.normal[1] + load * force.m[1];
        sums.friction[0] = sums.friction[0] + along[0];
        sums.friction[1] = sums.friction[1] + along[1];
        sums.turn = sums.turn + load * force.d_turn;
        sums.friction_moment = sums.friction_moment + cross(&q, &along);

        let (load_v, normal_v, material_v) = (load.value(), normal.value(), material.value());
        books.damping_power += (load_v - elastic) * rate;
        books.friction_power += friction.force * material_v;
        books.friction_force += friction.force;
        books.normal_resultant[0] += load_v * force.m[0].value();
        books.normal_resultant[1] += load_v * force.m[1].value();
        books.load += normal_v;
        books.load_sliding += normal_v * material_v;
        let Some(visit) = sink.visit.as_mut() else {
            return (normal_v, rate);
        };
        let node_load = |normal_force| NodeLoad {
            cell,
            pin_angle: wrap_angle(
                (cell as f64 + 0.5) * std::f64::consts::TAU / t.cells as f64 - pose.turn.value(),
            ),
            bearing_angle: (cell as f64 + 0.5) * std::f64::consts::TAU / t.cells as f64,
            normal_force,
            arc: t.node_arc,
            material_sliding: material_v,
            paper_sliding: paper,
            stiffness: self.model.layer().line_modulus * t.node_arc * factor * m_norm.value(),
        };
        if pass.simpson {
            // Held until the evaluation's totals are known (the foundation's quadrature docs).
            let trapezoid = deposit_gradient * factor * m_norm.value();
            if trapezoid > 0.0 {
                books.trapezoid_load += trapezoid;
                sink.deposits.push(node_load(trapezoid));
            }
        } else {
            visit(&node_load(normal_v));
        }
        (normal_v, rate)
    }
}

/// The estimate of what a node's overlap neglects, over `R` (each term by its magnitude;
/// docs/model.md §10.8 derives them), from `b/R` and the pin's `[v, r', r'', κ, κ']` where
/// the node reads it (`r''` the radius spline's curvature, `κ` the curvature spline's): of
/// second order in `b/R` the curvature splines' difference, `|r'' − κ| b²/(2R²)`, and the
/// reading shift's own second order, `r'² b²/R³`; of third the shift's `2 r' b³/(3R³)` and
/// the third derivative's `κ' b³/(6R³)`; the chord's next, `b⁴/(8R³)`; and `1/r_k` read to
/// first order in `v/R`, `(|r' b|/R + b²/(2R) + |κ| b²/R²) (v/R)²`.
#[inline]
fn neglected(b: f64, pin: [f64; 5], inverse_radius: f64) -> f64 {
    let [value, slope, curvature, bend, bend_slope] = pin;
    let (slope, b) = (slope.abs() * inverse_radius, b.abs());
    let b2 = b * b;
    let deviation = value * inverse_radius;
    b2 * (0.5 * (curvature - bend).abs() * inverse_radius + slope * slope)
        + b2 * b * (2.0 / 3.0 * slope + bend_slope.abs() * inverse_radius / 6.0)
        + b2 * b2 / 8.0
        + (slope * b + b2 * (0.5 + bend.abs() * inverse_radius)) * deviation * deviation
}

/// The overlap `g_k` of a node (m) and its weighed form `g̃_k = g_k (1 + a_k/(2r_k))` (m), in
/// the arithmetic of the pose, from `[a_k, b_k]`, the pin's `[v_k, r'_k, κ_k]` where the node
/// reads it (`v_k = r_k − R`) and the bearing's radius there less `R`.
#[inline(always)]
fn weighed_overlap<T: Real>(
    [a, b]: [T; 2],
    [radius, slope, bend]: [T; 3],
    bearing: f64,
    inverse_radius: f64,
) -> (T, f64) {
    let inverse = inverse_radius_at(radius, inverse_radius);
    // The reading shift `b/r`.
    let reading = b * inverse;
    let g = a + radius - (slope + b * 0.5 - bend * reading * 0.5) * reading - bearing;
    (g * (a * (inverse * 0.5) + 1.0), g.value())
}

/// `1/r_k` of the pin's radius `r_k = R + v_k` where a node reads it (`deviation` = `v_k` ≤ 0),
/// to first order in `v_k/R`: `(1 − v_k/R)/R`, no division per node. Its relative error is
/// `(v_k/R)²`, 2e-5 on the LGRES's worn pins (0.24 mm of wear on a 50 mm radius), on terms that
/// are themselves of second order in `b/R`.
#[inline(always)]
fn inverse_radius_at<T: Real>(deviation: T, inverse_radius: f64) -> T {
    deviation * (-inverse_radius * inverse_radius) + inverse_radius
}

/// `|m|` of a normal `m = n − λ t` that leans by `λ = (r' + b)/r` off the unit:
/// `√(1 + λ²)` by its series in `x = λ²` to `x³`. The lean is the pin's slope and the
/// eccentricity over the radius, a few hundredths, so the next term, `5x⁴/128`, is below
/// 1e-12 of `|m|`.
#[inline]
fn norm<T: Real>(m: &[T; 2]) -> T {
    let excess = dot(m, m) - 1.0;
    excess * (-(excess * (-(excess * 0.0625) + 0.125)) + 0.5) + 1.0
}
