//! The wear process's Jacobian, gathered per contact zone, and the linearly implicit sub-step.
//!
//! Within a contact zone the pressure follows the overlap: a cell that wore `Δh` more presses
//! less, and the pin moves to keep carrying its load. At one instant, with the zone's nodes `k`
//! meeting pin cell `j_k` and bearing cell `i_k` along directions `u_k` (the bearing's frame),
//! a change `v` of the depths changes the overlaps by `δd = −(I − Π)(D v)/2`: `D v` the two
//! surfaces' depths facing each node (`v_b[i_k] + v_p[j_k]`, each surface taking half in
//! radius) and `Π` the projection onto the two translations `u_k·δe` over the zone's nodes
//! (the pin's move). Each node deposits on both surfaces `λ_k δd_k` more, `λ_k` its
//! relaxation ([`StageWear::bearing_relaxation`](crate::StageWear::bearing_relaxation)). So
//! the rate's Jacobian in the depths is `J = −Σ_zones (λ/2) Dᵀ(I − Π)D`, summed over every
//! zone of every accepted step (its nodes' mean `λ`): symmetric and negative semi-definite,
//! and it leaves alone any pattern that is a translation over each zone that saw it (a
//! turning pin's even wear, a groove that fits the pin), damping only the wear pattern's shape
//! within the zones.
//!
//! Zones that meet the same cells along the same directions are merged (their `λ` added),
//! which keeps a stage's record to a few thousand zones.

use std::collections::HashMap;
use std::f64::consts::TAU;

use contact::NodeLoad;

/// One contact zone at one instant: `nodes` nodes of the pin's outline, consecutive, each
/// relaxing at `relaxation` per unit amplification.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactZone {
    /// The mean relaxation of the zone's nodes, per unit amplification, in cell units (a
    /// node's share of its cells: the same spread as its depth).
    pub relaxation: f64,
    /// Pin-frame angle of the first node, and the step to the next (rad).
    pub pin_start: f64,
    /// Pin-frame angle step between nodes (rad).
    pub pin_step: f64,
    /// Bearing-frame angle where the first node meets the bearing (rad), also the node's
    /// normal direction.
    pub bearing_start: f64,
    /// Bearing-frame angle step between nodes (rad).
    pub bearing_step: f64,
    /// Number of nodes (≥ 1).
    pub nodes: u32,
}

/// A stage's zones, merged where they meet the same cells along the same directions.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct ZoneBook {
    zones: Vec<ContactZone>,
    index: HashMap<(i64, i64, u32, i64), usize>,
}

impl ZoneBook {
    pub(crate) fn clear(&mut self) {
        self.zones.clear();
        self.index.clear();
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.zones.is_empty()
    }

    pub(crate) fn zones(&self) -> &[ContactZone] {
        &self.zones
    }

    /// Adds `zone`, merged with a recorded one on the same cells (`pin_cells`,
    /// `bearing_cells`: the grids) and directions (to 1/64 of a bearing cell per node).
    pub(crate) fn add(&mut self, zone: ContactZone, pin_cells: usize, bearing_cells: usize) {
        if zone.relaxation.is_nan() || zone.relaxation <= 0.0 || zone.nodes == 0 {
            return;
        }
        let cell = |angle: f64, n: usize| cell_at(angle.rem_euclid(TAU) * n as f64 / TAU, n) as i64;
        let per_bearing_cell = TAU / bearing_cells as f64;
        let key = (
            cell(zone.pin_start, pin_cells),
            cell(zone.bearing_start, bearing_cells),
            zone.nodes,
            (64.0 * zone.bearing_step / per_bearing_cell).round() as i64,
        );
        match self.index.get(&key) {
            Some(&i) => self.zones[i].relaxation += zone.relaxation,
            None => {
                self.index.insert(key, self.zones.len());
                self.zones.push(zone);
            }
        }
    }

    pub(crate) fn merge(&mut self, other: &ZoneBook, pin_cells: usize, bearing_cells: usize) {
        for zone in &other.zones {
            self.add(*zone, pin_cells, bearing_cells);
        }
    }

    pub(crate) fn scale(&mut self, factor: f64) {
        for zone in &mut self.zones {
            zone.relaxation *= factor;
        }
    }
}

/// The zones of one state's loaded nodes (in the order the contact reported them): runs of
/// consecutive nodes, the run across node 0 joined. `spread` is a node's share of its cells
/// (the depth's spread factor), `relaxation(node)` its relaxation before that share.
pub(crate) fn zones_of(
    nodes: &[NodeLoad],
    node_count: usize,
    spread: f64,
    relaxation: impl Fn(&NodeLoad) -> f64,
    mut emit: impl FnMut(ContactZone),
) {
    let n = nodes.len();
    if n == 0 || node_count == 0 {
        return;
    }
    let next = |a: &NodeLoad, b: &NodeLoad| (a.cell + 1) % node_count == b.cell;
    // Start at a break, so that a run across node 0 is one zone.
    let start = (0..n)
        .find(|&k| !next(&nodes[(k + n - 1) % n], &nodes[k]))
        .unwrap_or(0);
    let mut first = start;
    let (mut sum, mut pin_turn, mut bearing_turn) = (0.0, 0.0, 0.0);
    for step in 0..n {
        let k = (start + step) % n;
        sum += relaxation(&nodes[k]);
        let last = step + 1 == n || !next(&nodes[k], &nodes[(k + 1) % n]);
        if last {
            let count = step + 1 - (first + n - start) % n;
            let a = &nodes[first];
            // The mean step between consecutive nodes (a zone may span the whole circle).
            let steps = count.saturating_sub(1).max(1) as f64;
            emit(ContactZone {
                relaxation: spread * sum / count as f64,
                pin_start: a.pin_angle,
                pin_step: pin_turn / steps,
                bearing_start: a.bearing_angle,
                bearing_step: bearing_turn / steps,
                nodes: count as u32,
            });
            first = (k + 1) % n;
            (sum, pin_turn, bearing_turn) = (0.0, 0.0, 0.0);
        } else {
            let b = &nodes[(k + 1) % n];
            pin_turn += signed_difference(b.pin_angle, nodes[k].pin_angle);
            bearing_turn += signed_difference(b.bearing_angle, nodes[k].bearing_angle);
        }
    }
}

/// `b − a` wrapped into `(−π, π]`.
fn signed_difference(b: f64, a: f64) -> f64 {
    let d = (b - a).rem_euclid(TAU);
    if d > 0.5 * TAU { d - TAU } else { d }
}

/// A zone prepared for repeated products: where its first node's cells are, how far a node
/// steps (in cells), its directions' rotation per node, and the pseudo-inverse of `Σ u uᵀ`.
/// The nodes' cells and directions are regenerated in each product: a stage's zones hold
/// hundreds of thousands of nodes.
struct Prepared {
    half_relaxation: f64,
    nodes: usize,
    /// Pin and bearing positions of the first node, in cells (from 0 at angle 0).
    pin_start: f64,
    bearing_start: f64,
    /// Steps between nodes, in cells.
    pin_step: f64,
    bearing_step: f64,
    /// The first node's direction and the rotation between nodes (cos, sin).
    direction: [f64; 2],
    turn: [f64; 2],
    inverse: [[f64; 2]; 2],
}

impl Prepared {
    /// Calls `f(bearing cell, pin cell, direction)` for every node, in order.
    fn for_each(
        &self,
        pin_cells: usize,
        bearing_cells: usize,
        mut f: impl FnMut(usize, usize, [f64; 2]),
    ) {
        let mut u = self.direction;
        for k in 0..self.nodes {
            let p = cell_at(self.pin_start + k as f64 * self.pin_step, pin_cells);
            let b = cell_at(
                self.bearing_start + k as f64 * self.bearing_step,
                bearing_cells,
            );
            f(b, p, u);
            u = [
                u[0] * self.turn[0] - u[1] * self.turn[1],
                u[0] * self.turn[1] + u[1] * self.turn[0],
            ];
        }
    }
}

/// The cell holding position `x` (in cells) of a periodic grid of `n`.
fn cell_at(x: f64, n: usize) -> usize {
    let i = x.floor().rem_euclid(n as f64) as usize;
    i.min(n - 1)
}

fn prepare(zones: &[ContactZone], pin_cells: usize, bearing_cells: usize) -> Vec<Prepared> {
    let (per_pin, per_bearing) = (pin_cells as f64 / TAU, bearing_cells as f64 / TAU);
    zones
        .iter()
        .map(|z| {
            let (s, c) = z.bearing_start.sin_cos();
            let (ts, tc) = z.bearing_step.sin_cos();
            let mut p = Prepared {
                half_relaxation: 0.5 * z.relaxation,
                nodes: z.nodes as usize,
                pin_start: z.pin_start.rem_euclid(TAU) * per_pin,
                bearing_start: z.bearing_start.rem_euclid(TAU) * per_bearing,
                pin_step: z.pin_step * per_pin,
                bearing_step: z.bearing_step * per_bearing,
                direction: [c, s],
                turn: [tc, ts],
                inverse: [[0.0; 2]; 2],
            };
            let mut m = [[0.0; 2]; 2];
            p.for_each(pin_cells, bearing_cells, |_, _, u| {
                m[0][0] += u[0] * u[0];
                m[0][1] += u[0] * u[1];
                m[1][1] += u[1] * u[1];
            });
            m[1][0] = m[0][1];
            p.inverse = pseudo_inverse(m);
            p
        })
        .collect()
}

/// `out = Σ (λ/2) Dᵀ(I − Π)D v` (the negative Jacobian's product), `v` and `out` the bearing's
/// cells then the pin's.
fn product(zones: &[Prepared], bearing_cells: usize, v: &[f64], out: &mut [f64]) {
    out.fill(0.0);
    let pin_cells = v.len() - bearing_cells;
    let (vb, vp) = v.split_at(bearing_cells);
    for z in zones {
        let mut r = [0.0; 2];
        z.for_each(pin_cells, bearing_cells, |i, j, u| {
            let x = vb[i] + vp[j];
            r[0] += u[0] * x;
            r[1] += u[1] * x;
        });
        let shift = [
            z.inverse[0][0] * r[0] + z.inverse[0][1] * r[1],
            z.inverse[1][0] * r[0] + z.inverse[1][1] * r[1],
        ];
        let (ob, op) = out.split_at_mut(bearing_cells);
        z.for_each(pin_cells, bearing_cells, |i, j, u| {
            let y = z.half_relaxation * (vb[i] + vp[j] - u[0] * shift[0] - u[1] * shift[1]);
            ob[i] += y;
            op[j] += y;
        });
    }
}

/// Solves `(I − aJ) x = w` for the stacked depths (bearing then pin) by conjugate gradients
/// (the matrix is symmetric positive definite), preconditioned with `1 + a·Σ λ/2` over the
/// nodes that meet each cell (the matrix's diagonal without the zones' projections), to a
/// residual of 1e-10 of `w`'s norm. Returns `x` and the iterations taken.
pub(crate) fn solve(
    zones: &[ContactZone],
    bearing_cells: usize,
    pin_cells: usize,
    a: f64,
    w: &[f64],
) -> (Vec<f64>, usize) {
    let prepared = prepare(zones, pin_cells, bearing_cells);
    let n = w.len();
    let mut inverse_diagonal = vec![0.0; n];
    for z in &prepared {
        let (b, p) = inverse_diagonal.split_at_mut(bearing_cells);
        z.for_each(pin_cells, bearing_cells, |i, j, _| {
            b[i] += z.half_relaxation;
            p[j] += z.half_relaxation;
        });
    }
    for d in &mut inverse_diagonal {
        *d = 1.0 / (1.0 + a * *d);
    }
    let apply = |v: &[f64], out: &mut [f64]| {
        product(&prepared, bearing_cells, v, out);
        for (o, x) in out.iter_mut().zip(v) {
            *o = x + a * *o;
        }
    };
    let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>();
    let precondition = |r: &[f64], z: &mut [f64]| {
        for ((z, x), d) in z.iter_mut().zip(r).zip(&inverse_diagonal) {
            *z = x * d;
        }
    };
    let mut x = w.to_vec();
    let mut ax = vec![0.0; n];
    apply(&x, &mut ax);
    let mut r: Vec<f64> = w.iter().zip(&ax).map(|(p, q)| p - q).collect();
    let mut z = vec![0.0; n];
    precondition(&r, &mut z);
    let mut p = z.clone();
    let mut rz = dot(&r, &z);
    let goal = 1e-20 * dot(w, w);
    let mut ap = vec![0.0; n];
    let mut iterations = 0;
    while dot(&r, &r) > goal && iterations < 10 * n.max(1) {
        apply(&p, &mut ap);
        let pap = dot(&p, &ap);
        if pap.is_nan() || pap <= 0.0 {
            break;
        }
        let alpha = rz / pap;
        for k in 0..n {
            x[k] += alpha * p[k];
            r[k] -= alpha * ap[k];
        }
        precondition(&r, &mut z);
        let next = dot(&r, &z);
        let beta = next / rz;
        rz = next;
        for k in 0..n {
            p[k] = z[k] + beta * p[k];
        }
        iterations += 1;
    }
    (x, iterations)
}

/// The pseudo-inverse of a symmetric positive semi-definite 2×2 matrix: eigenvalues below
/// 1e-9 of the largest count as zero (a zone of one node, or along one direction, has fewer
/// translations).
fn pseudo_inverse(m: [[f64; 2]; 2]) -> [[f64; 2]; 2] {
    let (p, q, r) = (m[0][0], m[0][1], m[1][1]);
    let mean = 0.5 * (p + r);
    let spread = (0.25 * (p - r) * (p - r) + q * q).sqrt();
    let (large, small) = (mean + spread, mean - spread);
    if large.is_nan() || large <= 0.0 || large.is_infinite() {
        return [[0.0; 2]; 2];
    }
    let v = if spread > 0.0 {
        let (x, y) = if p >= r {
            (large - r, q)
        } else {
            (q, large - p)
        };
        let norm = x.hypot(y);
        [x / norm, y / norm]
    } else {
        [1.0, 0.0]
    };
    let w = [-v[1], v[0]];
    let mut inv = [[0.0; 2]; 2];
    for i in 0..2 {
        for j in 0..2 {
            inv[i][j] += v[i] * v[j] / large;
            if small > 1e-9 * large {
                inv[i][j] += w[i] * w[j] / small;
            }
        }
    }
    inv
}
