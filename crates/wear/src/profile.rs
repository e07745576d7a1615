//! A worn surface: a body-fixed grid of wear depths and its smooth periodic interpolation.
//!
//! # Interpolation: periodic uniform cubic B-spline on the cell depths
//!
//! The depth of cell `k` is the control point of a uniform cubic B-spline placed at the cell
//! centre `(k + ½)Δθ`, `Δθ = 2π/N`, wrapped around the circle. Why this one:
//! - **C²** everywhere, including cell edges and 0/2π: a stiff integrator sees no jump in
//!   the radius, its slope or the slope's derivative.
//! - **Local**: a sample uses 4 neighbouring cells, so a dent moves the radius only within
//!   ±2 cells of itself (an interpolating C² spline would ring around the whole circle).
//! - **Never negative, never above the largest cell** (the basis weights are a partition of
//!   unity and ≥ 0), so interpolation cannot create negative wear or close the clearance.
//! - **Volume-preserving**: each basis function integrates to one cell width, so the
//!   interpolated depth carries exactly the volume of the cell depths.
//!
//! The price is that it smooths rather than interpolates: a single-cell spike shows 2/3 of its
//! height. Archard depth is spread over arcs of tens of cells, so this is immaterial.
//! Cost per sample: one angle wrap, one floor (both without library calls), 4 loads, about 25
//! flops; no allocation.

use std::f64::consts::TAU;

use contact::{RadiusSample, SurfaceProfile};
use serde::{Deserialize, Serialize};

use crate::error::{WearError, check_depths, positive};

/// Which side of a clearance joint a surface is: it fixes how wear changes the radius.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// The hole: wear grows its radius, `R_i* = R_i + h/2`.
    Bearing,
    /// The journal: wear shrinks its radius, `R_j* = R_j − h/2`.
    Pin,
}

impl Side {
    /// Radius change per unit of wear depth `h` (each surface takes half).
    fn radius_per_depth(self) -> f64 {
        match self {
            Side::Bearing => 0.5,
            Side::Pin => -0.5,
        }
    }
}

/// One worn surface: nominal radius plus a body-fixed grid of accumulated wear depths.
///
/// `depth()[k]` is the Archard depth `h_k` of cell `k` (angles `[kΔθ, (k+1)Δθ)` in the body
/// frame); the surface's radius changes by `h/2` there (see [`Side`]). Implements
/// [`SurfaceProfile`] with the B-spline described in the module docs. Deserialization
/// validates (non-empty grid, finite non-negative depths, positive radius).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "ProfileData")]
pub struct WornProfile {
    side: Side,
    nominal_radius: f64,
    depth: Vec<f64>,
    /// `N / 2π`, cached: cells per radian.
    #[serde(skip)]
    cells_per_rad: f64,
    /// No cell is worn: the surface is round, and a joint may take the round-surface kernel.
    #[serde(skip)]
    unworn: bool,
}

/// The serialized form, validated on the way in.
#[derive(Deserialize)]
struct ProfileData {
    side: Side,
    nominal_radius: f64,
    depth: Vec<f64>,
}

impl TryFrom<ProfileData> for WornProfile {
    type Error = WearError;
    fn try_from(data: ProfileData) -> Result<Self, WearError> {
        WornProfile::from_depths(data.side, data.nominal_radius, data.depth)
    }
}

/// The deepest cell of a surface ([`WornProfile::peak`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Peak {
    /// Its Archard depth `h` (m); the radius changed by `h/2`. 0 on an unworn surface.
    pub depth: f64,
    /// Its index, from 0 (the first cell when several are equally deep).
    pub cell: usize,
    /// Its centre, body-frame angle in `[0, 2π)` (rad).
    pub angle: f64,
}

/// A contiguous angular range of a surface (body frame, radians).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct AngularRange {
    /// Start angle, in `[0, 2π)`.
    pub start: f64,
    /// End angle, `> start`; above 2π when the range wraps through 0.
    pub end: f64,
    /// Largest cell depth inside the range (m).
    pub peak: f64,
}

impl AngularRange {
    /// `[start, end]` in degrees, both in `[0°, 360°)`, for reports: an end below the start
    /// means the range wraps through 0° (e.g. `[298°, 12°]`).
    pub fn degrees(&self) -> [f64; 2] {
        [
            self.start.to_degrees(),
            self.end.to_degrees().rem_euclid(360.0),
        ]
    }
}

impl WornProfile {
    /// An unworn surface of `cells` cells.
    pub fn new(side: Side, nominal_radius: f64, cells: usize) -> Result<Self, WearError> {
        if cells == 0 {
            return Err(WearError::ZeroCells);
        }
        Self::from_depths(side, nominal_radius, vec![0.0; cells])
    }

    /// A surface with given cell depths `h_k` (m), e.g. a resumed stage. Each must be finite
    /// and non-negative, and half the deepest (the radius it removes) below the nominal radius
    /// on either side: a pin worn through, or a bearing dug deeper than its own radius, is
    /// not a joint.
    pub fn from_depths(
        side: Side,
        nominal_radius: f64,
        depth: Vec<f64>,
    ) -> Result<Self, WearError> {
        positive("nominal_radius", nominal_radius)?;
        if depth.is_empty() {
            return Err(WearError::ZeroCells);
        }
        check_depths("depth", &depth)?;
        let max = depth.iter().copied().fold(0.0, f64::max);
        if 0.5 * max >= nominal_radius {
            let (radius, depth) = (nominal_radius, 0.5 * max);
            return Err(match side {
                Side::Pin => WearError::PinWornThrough { radius, depth },
                Side::Bearing => WearError::BearingTooDeep { radius, depth },
            });
        }
        let cells_per_rad = depth.len() as f64 / TAU;
        let unworn = depth.iter().all(|h| *h == 0.0);
        Ok(Self {
            side,
            nominal_radius,
            depth,
            cells_per_rad,
            unworn,
        })
    }

    /// Bearing or pin.
    pub fn side(&self) -> Side {
        self.side
    }

    /// Unworn radius (m).
    pub fn nominal_radius(&self) -> f64 {
        self.nominal_radius
    }

    /// Number of cells `N`.
    pub fn cells(&self) -> usize {
        self.depth.len()
    }

    /// Cell width `Δθ = 2π/N` (rad).
    pub fn cell_width(&self) -> f64 {
        TAU / self.depth.len() as f64
    }

    /// Body-frame angle of the centre of cell `k` (rad).
    pub fn cell_center(&self, k: usize) -> f64 {
        (k as f64 + 0.5) * self.cell_width()
    }

    /// Accumulated Archard depth `h_k` of every cell (m); the radius changes by `h_k/2`.
    pub fn depth(&self) -> &[f64] {
        &self.depth
    }

    /// The deepest cell: its depth, index and centre angle.
    pub fn peak(&self) -> Peak {
        let (k, h) = self
            .depth
            .iter()
            .copied()
            .enumerate()
            .fold(
                (0, 0.0),
                |best, (k, h)| if h > best.1 { (k, h) } else { best },
            );
        Peak {
            depth: h,
            cell: k,
            angle: self.cell_center(k),
        }
    }

    /// Interpolated wear depth `h(θ)` and its derivative `dh/dθ` at body-frame angle `angle`.
    #[inline]
    pub fn wear_depth(&self, angle: f64) -> (f64, f64) {
        let (value, slope, _) = self.spline(angle);
        (value, slope)
    }

    /// Second derivative `d²h/dθ²` of the interpolated depth at body-frame angle `angle`
    /// (piecewise linear in the angle: the spline is C²).
    #[inline]
    pub fn wear_curvature(&self, angle: f64) -> f64 {
        self.spline(angle).2
    }

    /// `h`, `dh/dθ` and `d²h/dθ²` of the B-spline at `angle`.
    #[inline(always)]
    fn spline(&self, angle: f64) -> (f64, f64, f64) {
        let n = self.depth.len();
        // Control point k sits at u = k (the cell centre).
        let u = contact::wrap_angle(angle) * self.cells_per_rad - 0.5;
        let base = contact::floor(u);
        let t = u - base;
        // u ∈ [−0.5, N − 0.5], so base ∈ [−1, N − 1]: the four cells are base − 1 … base + 2,
        // one slice away from the ends of the grid, wrapped only near them.
        let i = base as i64;
        let (c0, c1, c2, c3) = match self.depth.get((i - 1).max(0) as usize..(i + 3) as usize) {
            Some(&[c0, c1, c2, c3]) if i >= 1 => (c0, c1, c2, c3),
            _ => {
                let c = |offset: i64| self.depth[(i + offset).rem_euclid(n as i64) as usize];
                (c(-1), c(0), c(1), c(2))
            }
        };
        let s = 1.0 - t;
        let t2 = t * t;
        let value = (s * s * s * c0
            + (3.0 * t2 * t - 6.0 * t2 + 4.0) * c1
            + (-3.0 * t2 * t + 3.0 * t2 + 3.0 * t + 1.0) * c2
            + t2 * t * c3)
            / 6.0;
        let du =
            (-s * s * c0 + (3.0 * t2 - 4.0 * t) * c1 + (-3.0 * t2 + 2.0 * t + 1.0) * c2 + t2 * c3)
                / 2.0;
        let duu = s * c0 + (3.0 * t - 2.0) * c1 + (1.0 - 3.0 * t) * c2 + t * c3;
        (
            value,
            du * self.cells_per_rad,
            duu * self.cells_per_rad * self.cells_per_rad,
        )
    }

    /// Volume removed from this surface over hinge width `width` (m³):
    /// `Σ h_k/2 · R Δθ · w` (thin layer, arc length at the nominal radius).
    pub fn worn_volume(&self, width: f64) -> f64 {
        layer_volume(&self.depth, self.nominal_radius, width)
    }

    /// Contiguous ranges of cells whose depth is at least `fraction` of the peak depth,
    /// deepest first. Empty for an unworn surface. A range through 0 is reported once.
    pub fn concentrated_ranges(&self, fraction: f64) -> Vec<AngularRange> {
        let peak = self.peak().depth;
        if peak <= 0.0 {
            return Vec::new();
        }
        let n = self.depth.len();
        let hot = |k: usize| self.depth[k % n] >= fraction * peak;
        if (0..n).all(hot) {
            return vec![AngularRange {
                start: 0.0,
                end: TAU,
                peak,
            }];
        }
        // Start scanning just after a cold cell so a range through 0 is not split.
        let first_cold = (0..n).find(|&k| !hot(k)).unwrap_or(0);
        let dtheta = self.cell_width();
        let mut ranges = Vec::new();
        let mut k = first_cold + 1;
        while k <= first_cold + n {
            if hot(k) {
                let start = k;
                let mut top: f64 = 0.0;
                while hot(k) {
                    top = top.max(self.depth[k % n]);
                    k += 1;
                }
                let start_angle = (start % n) as f64 * dtheta;
                ranges.push(AngularRange {
                    start: start_angle,
                    end: start_angle + (k - start) as f64 * dtheta,
                    peak: top,
                });
            }
            k += 1;
        }
        ranges.sort_by(|a, b| b.peak.total_cmp(&a.peak));
        ranges
    }

    /// Adds `amplification · increment[k]` to every cell. Callers have validated the
    /// increment (finite, ≥ 0, same grid) and the amplification (> 0).
    pub(crate) fn add_scaled(&mut self, increment: &[f64], amplification: f64) {
        for (h, dh) in self.depth.iter_mut().zip(increment) {
            *h += amplification * dh;
        }
        self.unworn = self.depth.iter().all(|h| *h == 0.0);
    }

    /// Largest pin wear `h/2` after adding `amplification · increment`, for the worn-through guard.
    pub(crate) fn max_half_depth_after(&self, increment: &[f64], amplification: f64) -> f64 {
        self.depth
            .iter()
            .zip(increment)
            .map(|(h, dh)| 0.5 * (h + amplification * dh))
            .fold(0.0, f64::max)
    }

    /// Largest slope `|Δh'|/2` and curvature `|Δh''|/2` (m/rad, m/rad²) that adding
    /// `increment` (amplification 1) gives this surface's radius, at the cell centres, where
    /// the B-spline's derivatives are the central differences of the cell depths.
    pub(crate) fn shape_change(&self, increment: &[f64]) -> (f64, f64) {
        shape_of(increment, self.cells_per_rad)
    }

    /// Largest slope `|h'|/2` and curvature `|h''|/2` of this surface's radius change so far
    /// (m/rad, m/rad²), at the cell centres.
    pub(crate) fn shape(&self) -> (f64, f64) {
        shape_of(&self.depth, self.cells_per_rad)
    }
    /// Largest `(Δh_k/2) / (c0 + h_k/2)` over cells: this surface's share of the relative
    /// change of the local clearance per unit amplification (`c0` nominal clearance).
    pub(crate) fn relative_opening(&self, increment: &[f64], nominal_clearance: f64) -> f64 {
        self.depth
            .iter()
            .zip(increment)
            .map(|(h, dh)| 0.5 * dh / (nominal_clearance + 0.5 * h))
            .fold(0.0, f64::max)
    }
}

/// Largest `|h'|/2` and `|h''|/2` of cell depths `depths` at the cell centres (central
/// differences: the uniform cubic B-spline's exact derivatives there).
fn shape_of(depths: &[f64], per_rad: f64) -> (f64, f64) {
    let n = depths.len();
    let mut slope: f64 = 0.0;
    let mut curvature: f64 = 0.0;
    for k in 0..n {
        let before = depths[(k + n - 1) % n];
        let after = depths[(k + 1) % n];
        slope = slope.max(0.25 * (after - before).abs() * per_rad);
        curvature =
            curvature.max(0.5 * (after - 2.0 * depths[k] + before).abs() * per_rad * per_rad);
    }
    (slope, curvature)
}

impl SurfaceProfile for WornProfile {
    #[inline(always)]
    fn sample(&self, angle: f64) -> RadiusSample {
        let (h, dh, ddh) = self.spline(angle);
        let k = self.side.radius_per_depth();
        RadiusSample {
            radius: self.nominal_radius + k * h,
            slope: k * dh,
            curvature: k * ddh,
        }
    }

    fn is_round(&self) -> bool {
        self.unworn
    }

    /// Exact: the B-spline never leaves `[0, max h]`, so the radius stays between the nominal
    /// one and the nominal one moved by half the deepest cell.
    fn radius_bounds(&self) -> Option<(f64, f64)> {
        let moved = self.nominal_radius + self.side.radius_per_depth() * self.peak().depth;
        Some((
            self.nominal_radius.min(moved),
            self.nominal_radius.max(moved),
        ))
    }

    /// Exact bounds from the cells whose B-spline support meets the range: a sample at `u`
    /// mixes the four control points around it, so the depth over `[start, end]` lies between
    /// the smallest and largest of those cells.
    fn radius_bounds_between(&self, start: f64, end: f64) -> Option<(f64, f64)> {
        let n = self.depth.len() as i64;
        let first = contact::floor(start * self.cells_per_rad - 0.5) as i64 - 1;
        let last = (contact::floor(end * self.cells_per_rad - 0.5) as i64 + 2).min(first + n - 1);
        let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
        for k in first..=last {
            let h = self.depth[k.rem_euclid(n) as usize];
            low = low.min(h);
            high = high.max(h);
        }
        let a = self.nominal_radius + self.side.radius_per_depth() * low;
        let b = self.nominal_radius + self.side.radius_per_depth() * high;
        Some((a.min(b), a.max(b)))
    }

    /// Exact bound: the B-spline's derivative mixes the differences of neighbouring cells with
    /// non-negative weights that sum to one, so it never exceeds the largest of them.
    fn slope_bound(&self) -> Option<f64> {
        let n = self.depth.len();
        let steepest = (0..n)
            .map(|k| (self.depth[(k + 1) % n] - self.depth[k]).abs())
            .fold(0.0, f64::max);
        Some(self.side.radius_per_depth().abs() * steepest * self.cells_per_rad)
    }
}

/// `Σ h_k/2 · R Δθ · w` for cell depths `depths` on a surface of radius `radius`.
pub(crate) fn layer_volume(depths: &[f64], radius: f64, width: f64) -> f64 {
    let dtheta = TAU / depths.len() as f64;
    0.5 * depths.iter().sum::<f64>() * radius * dtheta * width
}

/// Deposits depth over the arc `[center − half, center + half]` (rad) with the elliptic
/// (Hertzian) pressure distribution `p(u) = (4/π) p̄ √(1 − u²)`, `u` the position across the arc:
/// a cell gets `amount ×` the integral of the weight over the part of it under the arc, so
/// the deposited volume is exactly `amount · 2·half / Δθ` cells' worth (as a flat box would
/// give) but the deposit has no sharp edges, which keeps amplified profiles smooth.
///
/// The cell weights (an `asin` per cell edge) depend only on the arc, and the trapezoid
/// deposits every step end twice (as the end of one step and the start of the next), so the
/// weights of the last arc are kept: depositing on the same arc again only scales them, with
/// the same products as a fresh computation (bit for bit).
#[derive(Clone, Debug, Default)]
pub(crate) struct ArcDeposit {
    /// `(cells, center, half)` the weights belong to.
    arc: Option<(usize, f64, f64)>,
    /// Index (shifted by the cell count) of the first cell the weights cover.
    first: usize,
    /// Integral of the weight over each covered cell; `None` when the arc covers the whole
    /// surface and every cell gets `amount`.
    weights: Option<Vec<f64>>,
}

impl PartialEq for ArcDeposit {
    /// A cache, not part of the value of whatever holds it.
    fn eq(&self, _other: &Self) -> bool {
        true
    }
}

impl ArcDeposit {
    /// Adds `amount ×` the arc's cell weights to `buf`.
    pub(crate) fn deposit(&mut self, buf: &mut [f64], center: f64, half: f64, amount: f64) {
        let n = buf.len();
        if self.arc != Some((n, center, half)) {
            self.compute(n, center, half);
        }
        match &self.weights {
            None => buf.iter_mut().for_each(|h| *h += amount),
            Some(weights) => {
                for (k, &weight) in (self.first..).zip(weights) {
                    if weight > 0.0 {
                        buf[k % n] += amount * weight;
                    }
                }
            }
        }
    }

    fn compute(&mut self, n: usize, center: f64, half: f64) {
        self.arc = Some((n, center, half));
        let cells_per_rad = n as f64 / TAU;
        let half_cells = half * cells_per_rad;
        if 2.0 * half_cells >= n as f64 {
            self.weights = None;
            return;
        }
        let mid = center.rem_euclid(TAU) * cells_per_rad;
        let (lo, hi) = (mid - half_cells, mid + half_cells);
        // ∫ (4/π)√(1 − u²) du in cell units, as an antiderivative of the position x.
        let scale = 4.0 / std::f64::consts::PI * half_cells;
        let antiderivative = |x: f64| {
            let u = ((x - mid) / half_cells).clamp(-1.0, 1.0);
            0.5 * scale * (u * (1.0 - u * u).sqrt() + u.asin())
        };
        // lo > −N/2 − 1 and hi < 3N/2 + 1: shifting by N keeps indices unsigned.
        self.first = (lo.floor() + n as f64) as usize;
        let last = (hi.ceil() + n as f64) as usize;
        let weights = self.weights.get_or_insert_with(Vec::new);
        weights.clear();
        let mut below = antiderivative(lo);
        for k in self.first..last {
            let edge = k as f64 - n as f64 + 1.0;
            let above = antiderivative(edge.min(hi));
            weights.push(above - below);
            below = above;
        }
    }
}

/// Checks that a wear buffer belongs to `profile`'s grid and holds valid depths.
pub(crate) fn check_increment(
    name: &'static str,
    profile: &WornProfile,
    increment: &[f64],
) -> Result<(), WearError> {
    if increment.len() != profile.cells() {
        return Err(WearError::GridMismatch {
            name,
            expected: profile.cells(),
            found: increment.len(),
        });
    }
    check_depths(name, increment)
}

#[cfg(test)]
mod arc_deposit_tests {
    use super::*;

    /// A kept cache must give exactly what a fresh computation gives, whatever the order of
    /// arcs, and each deposit must carry `amount · 2·half/Δθ` cells' worth of depth.
    #[test]
    fn cached_weights_match_fresh_ones_and_conserve_depth() {
        let n = 1000;
        let arcs = [
            (0.3, 0.05),
            (0.3, 0.05),
            (6.25, 0.08),
            (0.3, 0.05),
            (1.0, 4.0),
        ];
        let mut cached = ArcDeposit::default();
        let mut kept = vec![0.0; n];
        let mut fresh_buf = vec![0.0; n];
        for (step, &(center, half)) in arcs.iter().enumerate() {
            let amount = 1e-9 * (step + 1) as f64;
            let before: f64 = kept.iter().sum();
            cached.deposit(&mut kept, center, half, amount);
            ArcDeposit::default().deposit(&mut fresh_buf, center, half, amount);
            assert_eq!(kept, fresh_buf, "arc {step}");
            let cells = (2.0 * half * n as f64 / TAU).min(n as f64);
            let added: f64 = kept.iter().sum::<f64>() - before;
            assert!(
                (added - amount * cells).abs() <= 1e-12 * amount * cells,
                "arc {step}: added {added}, expected {}",
                amount * cells
            );
        }
    }
}
