//! The thin-gap model's tables ([`ThinGapTables`]): its nodes fixed in the bearing's frame
//! (their directions and the bearing's radius there), the pin's outline as an interpolating
//! periodic cubic spline on the same grid (read at any turn of the pin by one set of weights,
//! [`Shift`]), and the radius and slope bounds that bound the loaded window.

use std::f64::consts::TAU;

use crate::surface::SurfaceProfile;

/// The thin-gap model's state for one pair of profiles, built once per joint and again when
/// its profiles change; evaluations only read it. Arrays are per node, struct of arrays.
#[derive(Clone, Debug, PartialEq)]
pub struct ThinGapTables {
    /// Nodes over 360°.
    pub(super) cells: usize,
    /// `cos θ_k`, `sin θ_k` of node `k`'s direction `θ_k = (k + ½) 2π/N` in the bearing's
    /// frame, at index `k` and again at `k + N` ([`padded_nodes`] entries): a window that
    /// wraps past node `N − 1` reads on without an index modulo.
    pub(super) cos: Vec<f64>,
    pub(super) sin: Vec<f64>,
    /// The bearing's radius at its nodes less [`Self::reference`] (m), padded as `cos`.
    pub(super) bearing: Vec<f64>,
    /// The pin's radius less [`Self::reference`] as a periodic cubic B-spline whose value at
    /// its knots (the pin-frame angles `(j + ½) 2π/N`) is the pin's radius there: control
    /// point `j` at every index `i ≡ j + 1 (mod N)`, over `3N + 7` entries, so that the four
    /// points of any padded node index and shift ([`Shift::offset`]) are consecutive.
    pub(super) pin: Vec<f64>,
    /// The pin's curvature (m/rad²) as a periodic cubic B-spline of its own, padded as `pin`:
    /// it takes the curvature of the radius's spline at the knots and is read by the same
    /// shift. Its slope, the curvature term's partial in the turn, is C¹ where the radius
    /// spline's third derivative is piecewise constant.
    pub(super) bend: Vec<f64>,
    /// The pin's largest radius `R` (m): the radius the second-order terms divide by and the
    /// radius the arcs are measured on.
    pub(super) reference: f64,
    /// Outline length per node, `R 2π/N` (m).
    pub(super) node_arc: f64,
    /// The bearing's smallest radius at its nodes less `R` (m), and the pin's largest
    /// interpolated radius less `R` (m, ≥ 0 up to rounding): bounds for the window.
    pub(super) bearing_min: f64,
    pub(super) pin_max: f64,
    /// The pin's smallest interpolated radius less `R` (m, ≤ 0): bounds `1/r` for the window.
    pub(super) pin_min: f64,
    /// Largest `|R_j'|` of the interpolated pin (m/rad): bounds the reading shift's term.
    pub(super) pin_slope_max: f64,
    /// Largest curvature of [`Self::bend`], at least 0 (m/rad²): bounds the curvature term.
    pub(super) bend_max: f64,
}

impl ThinGapTables {
    /// The tables of `cells` nodes for these profiles.
    pub(super) fn new<B: SurfaceProfile, P: SurfaceProfile>(
        bearing: &B,
        pin: &P,
        cells: usize,
    ) -> Self {
        let step = TAU / cells as f64;
        let angle = |k: usize| (k as f64 + 0.5) * step;
        let pin_samples: Vec<f64> = (0..cells).map(|k| pin.sample(angle(k)).radius).collect();
        let reference = pin_samples
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        let deviations: Vec<f64> = pin_samples.iter().map(|r| r - reference).collect();
        let control = interpolating_control_points(&deviations);
        // The radius spline's curvature at knot `j`: `(c_{j−1} − 2c_j + c_{j+1})/h²`.
        let knot_curvature: Vec<f64> = (0..cells)
            .map(|j| {
                (control[(j + cells - 1) % cells] - 2.0 * control[j] + control[(j + 1) % cells])
                    / (step * step)
            })
            .collect();
        let bend = interpolating_control_points(&knot_curvature);
        let padded_spline = |control: &[f64]| -> Vec<f64> {
            (0..padded_nodes(cells) + cells + 3)
                .map(|i| control[(i + cells - 1) % cells])
                .collect()
        };
        let padded = |per_node: &dyn Fn(usize) -> f64| -> Vec<f64> {
            (0..padded_nodes(cells))
                .map(|i| per_node(i % cells))
                .collect()
        };
        // The B-spline stays within its control points' range, and its derivative within
        // their largest difference per knot spacing.
        let pin_max = control.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let pin_min = control.iter().copied().fold(f64::INFINITY, f64::min);
        let steepest = (0..cells)
            .map(|j| (control[(j + 1) % cells] - control[j]).abs())
            .fold(0.0, f64::max);
        let bearing: Vec<f64> = (0..cells)
            .map(|k| bearing.sample(angle(k)).radius - reference)
            .collect();
        Self {
            cells,
            cos: padded(&|k| angle(k).cos()),
            sin: padded(&|k| angle(k).sin()),
            bearing_min: bearing.iter().copied().fold(f64::INFINITY, f64::min),
            bearing: padded(&|k| bearing[k]),
            pin: padded_spline(&control),
            bend: padded_spline(&bend),
            bend_max: bend.iter().copied().fold(0.0, f64::max),
            reference,
            node_arc: reference * step,
            pin_max,
            pin_min,
            pin_slope_max: steepest / step,
        }
    }

    /// The pin's radius less `R`, its slope and its curvature at the pin-frame angle of node
    /// `k` (a padded index, below [`padded_nodes`]) turned back by the shift (m, m/rad,
    /// m/rad²): the four control points from the shift's base on, with its weights.
    #[inline(always)]
    pub(super) fn pin_at(&self, k: usize, shift: &Shift) -> (f64, f64, f64) {
        read(&self.pin, k, shift)
    }

    /// The pin's curvature from [`Self::bend`] at node `k` under the shift, and its first
    /// and second derivatives (m/rad², m/rad³, m/rad⁴).
    #[inline(always)]
    pub(super) fn bend_at(&self, k: usize, shift: &Shift) -> (f64, f64, f64) {
        read(&self.bend, k, shift)
    }

    /// The pin's third derivative at node `k` under the shift (m/rad³): the Jacobian's
    /// partial of the curvature (piecewise constant on a cubic).
    #[inline]
    pub(super) fn pin_third_at(&self, k: usize, shift: &Shift) -> f64 {
        let base = k + shift.offset;
        let c = &self.pin[base..base + 4];
        shift.third * (-c[0] + 3.0 * c[1] - 3.0 * c[2] + c[3])
    }
}

/// A padded spline `table` at node `k` under the shift: its value and first two derivatives.
#[inline(always)]
fn read(table: &[f64], k: usize, shift: &Shift) -> (f64, f64, f64) {
    let base = k + shift.offset;
    let c = &table[base..base + 4];
    shift.read([c[0], c[1], c[2], c[3]])
}

/// Entries of the padded per-node tables for `cells` nodes: a window of up to every node and
/// two beyond each end, starting anywhere in `0..N`, indexes below `2N + 4`.
pub(super) const fn padded_nodes(cells: usize) -> usize {
    2 * cells + 4
}

/// The pin read at its rotation `Δ = θ_j − θ_i` relative to the bearing: node `k` (direction
/// `θ_k` in the bearing's frame) meets the pin at its frame's angle `θ_k − Δ`, which is knot
/// `k − Δ/h` of the pin's spline (`h = 2π/N`). One turn gives every node the same fractional
/// position between its knots, so the same four weights (and their derivatives) serve every
/// node; only the base index moves with `k`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Shift {
    /// Node `k`'s first control point is at padded index `k + offset` (`offset < N`).
    pub(super) offset: usize,
    pub(super) value: [f64; 4],
    /// The weights' derivatives in the pin-frame angle (1/rad).
    pub(super) slope: [f64; 4],
    /// Their second derivatives (1/rad²).
    pub(super) curvature: [f64; 4],
    /// `1/h³` (1/rad³): the third derivative's scale.
    pub(super) third: f64,
}

impl Shift {
    /// A spline's value and first two derivatives from the four control points `c` of a node
    /// under this shift.
    #[inline(always)]
    pub(super) fn read(&self, c: [f64; 4]) -> (f64, f64, f64) {
        let weigh = |w: &[f64; 4]| w[0] * c[0] + w[1] * c[1] + w[2] * c[2] + w[3] * c[3];
        (
            weigh(&self.value),
            weigh(&self.slope),
            weigh(&self.curvature),
        )
    }

    /// The weights for relative rotation `turn = θ_j − θ_i` (rad) on `cells` nodes.
    pub(super) fn new(turn: f64, cells: usize) -> Self {
        let per_rad = cells as f64 / TAU;
        // Knot position `k − s`, `s = Δ/h`: base knot `k − m − 1` at fraction `t = 1 − f`
        // (`m = ⌊s⌋`, `f = s − m`), so `t ∈ (0, 1]`.
        let s = turn * per_rad;
        let m = crate::surface::floor(s);
        let t = 1.0 - (s - m);
        let n = cells as i64;
        // Padded index of control point `k − m − 2` is `k − m − 1`.
        let offset = (-(m as i64) - 1).rem_euclid(n) as usize;
        let u = 1.0 - t;
        let (t2, t3) = (t * t, t * t * t);
        let value = [
            u * u * u / 6.0,
            (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0,
            (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0,
            t3 / 6.0,
        ];
        let d = [
            -0.5 * u * u,
            0.5 * (3.0 * t2 - 4.0 * t),
            0.5 * (-3.0 * t2 + 2.0 * t + 1.0),
            0.5 * t2,
        ];
        let dd = [u, 3.0 * t - 2.0, 1.0 - 3.0 * t, t];
        Self {
            offset,
            value,
            slope: d.map(|w| w * per_rad),
            curvature: dd.map(|w| w * per_rad * per_rad),
            third: per_rad * per_rad * per_rad,
        }
    }
}

/// The control points of the periodic uniform cubic B-spline that takes the values `samples`
/// at its knots: the solution of `(c_{j−1} + 4 c_j + c_{j+1})/6 = p_j` (periodic), by Jacobi
/// sweeps, each of which shrinks the error by half or more, to rounding. On a pin worn on a
/// B-spline of the same grid (the wear grid's cells at the nodes) these are its own control
/// points, and the interpolated outline is the pin's.
fn interpolating_control_points(samples: &[f64]) -> Vec<f64> {
    let n = samples.len();
    let mut c = samples.to_vec();
    let mut next = vec![0.0; n];
    let scale = samples.iter().fold(0.0_f64, |m, p| m.max(p.abs()));
    for _ in 0..200 {
        let mut change: f64 = 0.0;
        for j in 0..n {
            let neighbours = c[(j + n - 1) % n] + c[(j + 1) % n];
            next[j] = (6.0 * samples[j] - neighbours) / 4.0;
            change = change.max((next[j] - c[j]).abs());
        }
        std::mem::swap(&mut c, &mut next);
        if change <= 1e-17 * scale.max(f64::MIN_POSITIVE) {
            break;
        }
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::RadiusSample;

    /// A smooth non-round pin: `R + a cos(3α) + b sin(7α)`.
    struct Wavy;
    impl SurfaceProfile for Wavy {
        fn sample(&self, angle: f64) -> RadiusSample {
            let (a, b) = (2e-5, 1e-5);
            RadiusSample {
                radius: 0.05 + a * (3.0 * angle).cos() + b * (7.0 * angle).sin(),
                slope: -3.0 * a * (3.0 * angle).sin() + 7.0 * b * (7.0 * angle).cos(),
                curvature: -9.0 * a * (3.0 * angle).cos() - 49.0 * b * (7.0 * angle).sin(),
            }
        }
    }

    /// The shifted spline reads the pin's radius, slope and curvature at any turn, within the
    /// interpolating cubic's error on 400 nodes (`5h⁴/384`, `h³/24` and `h²/12` times the
    /// fourth derivative: 2e-11 m, 4e-9 m/rad, 5e-7 m/rad²), and hits the samples at the
    /// knots to rounding.
    #[test]
    fn the_shifted_spline_reads_the_pin_at_any_turn() {
        let tables = ThinGapTables::new(&crate::CircularProfile::new(0.051), &Wavy, 400);
        let h = TAU / 400.0;
        let mut worst_third: f64 = 0.0;
        for turn in [0.0, 0.3, -1.7, 2.0 * h, 12.345] {
            let shift = Shift::new(turn, 400);
            for k in [0, 1, 57, 399] {
                let (value, slope, curvature) = tables.pin_at(k, &shift);
                let exact = Wavy.sample((k as f64 + 0.5) * h - turn);
                let radius = value + tables.reference;
                assert!((radius - exact.radius).abs() < 5e-11, "{turn} {k}");
                assert!((slope - exact.slope).abs() < 2e-8, "{turn} {k}");
                assert!((curvature - exact.curvature).abs() < 2e-6, "{turn} {k}");
                let (bend, bend_slope, _) = tables.bend_at(k, &shift);
                assert!((bend - exact.curvature).abs() < 2e-6, "{turn} {k}");
                let angle = (k as f64 + 0.5) * h - turn;
                let third = 27.0 * 2e-5 * (3.0 * angle).sin() - 343.0 * 1e-5 * (7.0 * angle).cos();
                worst_third = worst_third.max((bend_slope - third).abs());
            }
        }
        eprintln!("the curvature spline's slope against the third derivative: {worst_third:.1e}");
        assert!(worst_third < 1e-4, "{worst_third:e}");
        let (value, _, _) = tables.pin_at(5, &Shift::new(0.0, 400));
        assert!((value + tables.reference - Wavy.sample(5.5 * h).radius).abs() < 1e-16);
    }
}
