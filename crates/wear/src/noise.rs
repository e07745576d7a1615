//! The sampling noise of staged wear: a delete-a-group jackknife over the stage's own
//! independent samples (docs/model.md §10.4).
//!
//! Every run of the K cycles yields two independent samples of the wear rate, its two halves
//! ([`crate::WearSample::halves`]: two trajectories, or two halves of one trajectory's cycles),
//! each entering the surfaces with half the run's amplification. The samples are dealt into
//! `2 × groups` batches: the half, and the run's place among the weighted runs modulo `groups`
//! (interleaved, so every batch samples the whole life evenly and a trend of the wear rate
//! over the stages does not pass for noise). A replica of the surfaces leaves one batch out and
//! scales the rest up to the same amplification; the spread of any measure over the replicas
//! is its jackknife standard error. The replicas are linear in the wear, so they cost a few
//! extra depth grids.
//!
//! A replica follows the path the surfaces actually took (the samples share the geometry they
//! were simulated on), so the feedback of the noise on later wear rates is not in it: the worn
//! geometry levels out what one sample deepened (a deeper dent carries less load). What of a
//! sub-step's noise survives to the end is read from the life curve itself ([`levelling`]):
//! a fluctuation that survives a fraction `s` of itself per sub-step leaves the increments of
//! the curve correlated by `−(1 − s)/2`. The other way, a trajectory that continues across
//! sub-steps can keep a more wearing motion for a few of them, which the interleaved batches
//! count as independent: [`persistence`] reads that from the curve's positive correlations.
//! [`JointNoise::levelled`] scales the jackknife by both ([`Levelling::share`]). The peak of a
//! noisy profile is biased upwards by about its noise.

use crate::accumulate::StageWear;
use crate::joint::WornJoint;
use crate::profile::layer_volume;

/// Groups the runs are dealt into per half: `2 × NOISE_GROUPS` batches, enough for a standard
/// error good to about 16 % (`1/√(2·19)`), few enough that each batch of a 40-sub-step stage
/// still holds four runs' halves.
pub const NOISE_GROUPS: usize = 10;

/// The batches of a run's samples so far, per joint, and their weights.
#[derive(Clone, Debug, PartialEq)]
pub struct NoiseBatches {
    groups: usize,
    /// Per batch (`half × groups + group`): the amplification its samples received.
    weights: Vec<f64>,
    /// Per batch, per joint: its samples' wear, each times its amplification (bearing, pin).
    sums: Vec<Vec<[Vec<f64>; 2]>>,
    /// Weighted runs added so far (the next run's group is this modulo `groups`).
    runs: usize,
}

impl NoiseBatches {
    /// Empty batches for `joints` (the wearing joints in the stages' order), `groups` per
    /// half (at least 1).
    pub fn new(joints: &[WornJoint], groups: usize) -> Self {
        let groups = groups.max(1);
        let empty: Vec<[Vec<f64>; 2]> = joints
            .iter()
            .map(|j| [vec![0.0; j.bearing().cells()], vec![0.0; j.pin().cells()]])
            .collect();
        Self {
            groups,
            weights: vec![0.0; 2 * groups],
            sums: vec![empty; 2 * groups],
            runs: 0,
        }
    }

    /// Adds one run: per joint its two halves, the run's wear having entered the surfaces with
    /// amplification `weight` (each half with the same factor: it is half the run). A run
    /// with no weight (a rejected prediction, an unused run) adds nothing; halves of another
    /// joint count or grid size are ignored.
    pub fn add(&mut self, halves: &[[StageWear; 2]], weight: f64) {
        if weight <= 0.0 || !weight.is_finite() || halves.len() != self.sums[0].len() {
            return;
        }
        let group = self.runs % self.groups;
        self.runs += 1;
        for (half, batch) in [group, self.groups + group].into_iter().enumerate() {
            self.weights[batch] += 0.5 * weight;
            for (sum, joint) in self.sums[batch].iter_mut().zip(halves) {
                let sample = &joint[half];
                for (s, h) in sum[0].iter_mut().zip(sample.bearing()) {
                    *s += weight * h;
                }
                for (s, h) in sum[1].iter_mut().zip(sample.pin()) {
                    *s += weight * h;
                }
            }
        }
    }

    /// Per joint, the jackknife replicas of its surfaces as they stand now: for each batch
    /// that holds samples, the change of the depths had it been left out,
    /// `δ_b = (W_b·D − W·D_b)/(W − W_b)` (`D`, `W`: all samples' wear and weight; `D_b`,
    /// `W_b`: the batch's), the rest scaled up to the whole weight.
    pub fn replicas(&self) -> Vec<Replicas> {
        let total_weight: f64 = self.weights.iter().sum();
        let filled: Vec<usize> = (0..self.weights.len())
            .filter(|&b| self.weights[b] > 0.0 && self.weights[b] < total_weight)
            .collect();
        let joints = self.sums[0].len();
        (0..joints)
            .map(|j| {
                let total = |side: usize| {
                    let mut d = vec![0.0; self.sums[0][j][side].len()];
                    for batch in &self.sums {
                        for (x, y) in d.iter_mut().zip(&batch[j][side]) {
                            *x += y;
                        }
                    }
                    d
                };
                let totals = [total(0), total(1)];
                let perturbations = filled
                    .iter()
                    .map(|&b| {
                        let w_b = self.weights[b];
                        let scale = 1.0 / (total_weight - w_b);
                        let side = |s: usize| -> Vec<f64> {
                            totals[s]
                                .iter()
                                .zip(&self.sums[b][j][s])
                                .map(|(d, d_b)| (w_b * d - total_weight * d_b) * scale)
                                .collect()
                        };
                        [side(0), side(1)]
                    })
                    .collect();
                Replicas { perturbations }
            })
            .collect()
    }
}

/// A joint's jackknife replicas at one point of a run: how its depth grids would differ had
/// one batch of the samples been left out ([`NoiseBatches::replicas`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Replicas {
    /// Per replica: the change of the bearing's and the pin's depths.
    perturbations: Vec<[Vec<f64>; 2]>,
}

impl Replicas {
    /// How many replicas (batches holding samples): the jackknife's sample size.
    pub fn count(&self) -> usize {
        self.perturbations.len()
    }

    /// The replicas of the depth grids `bearing`, `pin`: per replica, bearing and pin.
    pub fn surfaces(&self, bearing: &[f64], pin: &[f64]) -> Vec<[Vec<f64>; 2]> {
        let shifted = |base: &[f64], delta: &[f64]| -> Vec<f64> {
            base.iter().zip(delta).map(|(h, d)| h + d).collect()
        };
        self.perturbations
            .iter()
            .map(|[b, p]| [shifted(bearing, b), shifted(pin, p)])
            .collect()
    }

    /// `measure(bearing, pin)` of each replica of the depth grids `bearing`, `pin`.
    pub fn values<F>(&self, bearing: &[f64], pin: &[f64], mut measure: F) -> Vec<f64>
    where
        F: FnMut(&[f64], &[f64]) -> f64,
    {
        self.surfaces(bearing, pin)
            .iter()
            .map(|[b, p]| measure(b, p))
            .collect()
    }

    /// The jackknife standard error of `measure(bearing, pin)`; `None` with fewer than two
    /// replicas.
    pub fn noise<F>(&self, bearing: &[f64], pin: &[f64], measure: F) -> Option<f64>
    where
        F: FnMut(&[f64], &[f64]) -> f64,
    {
        jackknife_error(&self.values(bearing, pin, measure))
    }

    /// Surfaces that each differ from `bearing`, `pin` by about one sampling noise (times
    /// `scale`, e.g. a [`Levelling::share`]): the replicas' deviations from their mean times
    /// `√(n − 1)`. A replica moves the depths by only `1/√(n − 1)` of their noise, too little to
    /// change a measure that moves in jumps (a count); over these surfaces such a measure takes
    /// the values its noise makes plausible ([`discrete_noise`]). For a measure linear in the
    /// depths, their root-mean-square deviation is exactly the jackknife's standard error.
    pub fn plausible_surfaces(
        &self,
        bearing: &[f64],
        pin: &[f64],
        scale: f64,
    ) -> Vec<[Vec<f64>; 2]> {
        let n = self.count();
        if n < 2 {
            return Vec::new();
        }
        let mean = |side: usize, len: usize| -> Vec<f64> {
            let mut m = vec![0.0; len];
            for p in &self.perturbations {
                for (m, d) in m.iter_mut().zip(&p[side]) {
                    *m += d / n as f64;
                }
            }
            m
        };
        let means = [mean(0, bearing.len()), mean(1, pin.len())];
        let factor = scale * ((n - 1) as f64).sqrt();
        let plausible = |base: &[f64], delta: &[f64], mean: &[f64]| -> Vec<f64> {
            base.iter()
                .zip(delta)
                .zip(mean)
                .map(|((h, d), m)| h + factor * (d - m))
                .collect()
        };
        self.perturbations
            .iter()
            .map(|[b, p]| {
                [
                    plausible(bearing, b, &means[0]),
                    plausible(pin, p, &means[1]),
                ]
            })
            .collect()
    }

    /// The jackknife noise of `joint`'s results on its surfaces as they stand: peak depths,
    /// worn volume and largest local clearance ([`JointResults`]), before levelling
    /// ([`JointNoise::levelled`]). `None` with fewer than two replicas.
    pub fn joint_noise(&self, joint: &WornJoint) -> Option<JointNoise> {
        if self.count() < 2 {
            return None;
        }
        let (bearing, pin) = (joint.bearing().depth(), joint.pin().depth());
        let replicas: Vec<JointResults> = self
            .surfaces(bearing, pin)
            .iter()
            .map(|[b, p]| JointResults::measure(joint, b, p))
            .collect();
        let field = |pick: fn(&JointResults) -> f64| {
            jackknife_error(&replicas.iter().map(pick).collect::<Vec<_>>())
        };
        Some(JointNoise {
            bearing_peak_depth: field(|r| r.bearing_peak_depth)?,
            pin_peak_depth: field(|r| r.pin_peak_depth)?,
            worn_volume: field(|r| r.worn_volume)?,
            max_local_clearance: field(|r| r.max_local_clearance)?,
        })
    }
}

/// A joint's results at one point of a run, the quantities whose noise [`JointNoise`] holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointResults {
    /// The bearing's peak depth, m.
    pub bearing_peak_depth: f64,
    /// The pin's peak depth, m.
    pub pin_peak_depth: f64,
    /// The worn volume of bearing and pin, m³.
    pub worn_volume: f64,
    /// The largest local clearance, `c₀ + (peak_bearing + peak_pin)/2`, m.
    pub max_local_clearance: f64,
}

impl JointResults {
    /// `joint`'s results on its own surfaces.
    pub fn of(joint: &WornJoint) -> Self {
        Self::measure(joint, joint.bearing().depth(), joint.pin().depth())
    }

    /// `joint`'s results had its surfaces the depths `bearing`, `pin`.
    fn measure(joint: &WornJoint, bearing: &[f64], pin: &[f64]) -> Self {
        let peak = |h: &[f64]| h.iter().copied().fold(0.0, f64::max);
        let width = joint.hinge_width();
        let (bearing_peak_depth, pin_peak_depth) = (peak(bearing), peak(pin));
        Self {
            bearing_peak_depth,
            pin_peak_depth,
            worn_volume: layer_volume(bearing, joint.bearing().nominal_radius(), width)
                + layer_volume(pin, joint.pin().nominal_radius(), width),
            max_local_clearance: joint.nominal_clearance()
                + 0.5 * (bearing_peak_depth + pin_peak_depth),
        }
    }
}

/// The sampling noise of a joint's results at one point of a run: the jackknife's standard
/// error ([`Replicas::joint_noise`]), or that levelled ([`JointNoise::levelled`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointNoise {
    /// Of the bearing's peak depth, m.
    pub bearing_peak_depth: f64,
    /// Of the pin's peak depth, m.
    pub pin_peak_depth: f64,
    /// Of the worn volume, m³.
    pub worn_volume: f64,
    /// Of the largest local clearance, m.
    pub max_local_clearance: f64,
}

impl JointNoise {
    /// The noise at the end, the worn geometry's levelling and the fluctuations' persistence
    /// counted: each field's jackknife noise times the [`levelling`] share read from that
    /// result's life curve so far, `history` (its
    /// values at the stage's start and after every sub-step, this point last) and the
    /// sub-steps' lengths (amplifications) `lengths`.
    pub fn levelled(self, history: &[JointResults], lengths: &[f64]) -> Self {
        let share = |pick: fn(&JointResults) -> f64| {
            levelling(&history.iter().map(pick).collect::<Vec<_>>(), lengths).share
        };
        Self {
            bearing_peak_depth: self.bearing_peak_depth * share(|r| r.bearing_peak_depth),
            pin_peak_depth: self.pin_peak_depth * share(|r| r.pin_peak_depth),
            worn_volume: self.worn_volume * share(|r| r.worn_volume),
            max_local_clearance: self.max_local_clearance * share(|r| r.max_local_clearance),
        }
    }
}

/// How much of the sampling noise of a result survives the levelling of the worn geometry
/// ([`levelling`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Levelling {
    /// The fraction of a sub-step's fluctuation still there one sub-step later, in `[0, 1]`
    /// (1: none levelled, the fluctuations add up).
    pub survival: f64,
    /// How much the curve's fluctuations persist beyond the jackknife's independent
    /// sub-steps, at least 1 ([`persistence`]).
    pub persistence: f64,
    /// The share of the jackknife's noise there at the end, `√(Σ_{k<N} s^{2k} / N)` times the
    /// persistence: below 1 where the geometry levels the fluctuations out, above where
    /// consecutive sub-steps' fluctuations go the same way.
    pub share: f64,
}

/// Increments a life curve needs before its levelling is read: with fewer, the share is 1.
pub const LEVELLING_MIN_STEPS: usize = NOISE_WARM_UP;

/// The levelling of a result whose values after consecutive sub-steps are `curve` (the first
/// its value before them), the sub-steps' lengths (amplifications) `lengths`.
///
/// The jackknife counts every sub-step's sampling fluctuation `ε` as staying in the surfaces,
/// `σ² = N σ_ε²` after `N` sub-steps. If the geometry instead keeps a fraction `s` of a
/// fluctuation per sub-step (a first-order autoregression about the trend), the end carries
/// `σ_ε² Σ_{k<N} s^{2k}`, and the curve's increments are correlated at lag one by
/// `r₁ = −(1 − s)/2`. So `s = 1 + 2 r₁`, from the increments per unit length (so that a change
/// of sub-step length is not a trend) less their mean, with `r₁` taken
/// one standard error `1/√N` above its estimate and clamped to `[0, 1]`: without that margin a
/// curve whose fluctuations all stay (`s = 1`, the jackknife's case) reads `s < 1` half the time
/// and its noise would be understated (by 2.7× in the median over 143 sub-steps); with it,
/// synthetic curves give the ends' scatter at `s = 0` and `s = 1` and overstate it in between
/// (`wear/tests/noise.rs`). A trending curve (positively correlated increments) keeps the
/// jackknife's noise. Fewer than [`LEVELLING_MIN_STEPS`] increments, or a curve that does not
/// move, or lengths that are not one positive number per sub-step: share 1. The share is then
/// multiplied by the increments' [`persistence`] (1 unless they stay correlated positively).
pub fn levelling(curve: &[f64], lengths: &[f64]) -> Levelling {
    let none = Levelling {
        survival: 1.0,
        persistence: 1.0,
        share: 1.0,
    };
    let steps = curve.len().saturating_sub(1);
    if steps < LEVELLING_MIN_STEPS
        || lengths.len() != steps
        || curve.iter().any(|v| !v.is_finite())
        || lengths.iter().any(|l| !(l.is_finite() && *l > 0.0))
    {
        return none;
    }
    let increments: Vec<f64> = curve
        .windows(2)
        .zip(lengths)
        .map(|(w, l)| (w[1] - w[0]) / l)
        .collect();
    let mean = increments.iter().sum::<f64>() / steps as f64;
    let centred: Vec<f64> = increments.iter().map(|d| d - mean).collect();
    let variance: f64 = centred.iter().map(|d| d * d).sum();
    if variance <= 0.0 {
        return none;
    }
    let lag_one: f64 = centred.windows(2).map(|w| w[0] * w[1]).sum::<f64>() / variance;
    let upper = lag_one + 1.0 / (steps as f64).sqrt();
    let survival = (1.0 + 2.0 * upper).clamp(0.0, 1.0);
    let (mut sum, mut term) = (0.0, 1.0);
    for _ in 0..steps {
        sum += term;
        term *= survival * survival;
    }
    let persistence = persistence(&increments);
    Levelling {
        survival,
        persistence,
        share: (sum / steps as f64).sqrt() * persistence,
    }
}

/// Degree of the trend [`persistence`] takes out of a life curve's increments: the wear rate
/// changes smoothly over a stage as the surfaces conform, and that change is not noise.
pub const PERSISTENCE_TREND_DEGREE: i32 = 3;

/// How much more than independent the sampling fluctuations of consecutive sub-steps add up:
/// `√max(1, 1 + 2 Σ_{k=1}^{b} (1 − k/(b+1)) r_k)`, `r_k` the autocorrelation at lag `k` of the
/// increments (per unit length) less a least-squares cubic in the sub-step's index, with
/// Bartlett weights over `b = ⌊4 (N/100)^{2/9}⌋` lags (Newey and West's bandwidth; 4 at 141
/// sub-steps).
///
/// Why: the jackknife deals consecutive runs into different batches (so that a trend does not
/// pass for noise) and so counts every sub-step's sample as independent. A trajectory that
/// continues across sub-steps can stay in a more (or less) wearing motion for a few of them;
/// those fluctuations add up to `1 + 2 Σ r_k` times the independent variance. Negative
/// correlations are the levelling's (counted by the survival); they do not lower this factor
/// below 1. On the default LGRES stage A's peaks and volume read 1.2 (the curve's increments
/// correlate by about +0.12 at lags 1 to 3 after the cubic), B's 1.0, which brought A's printed
/// noise from 0.72–0.80 of the scatter of eight repeats to 0.88–0.96 (docs/convergence.md).
/// A curve whose increments the cubic takes out (to rounding), or with fewer increments than
/// the cubic and two lags need: 1.
pub fn persistence(increments: &[f64]) -> f64 {
    let n = increments.len();
    let bandwidth = (4.0 * (n as f64 / 100.0).powf(2.0 / 9.0)).floor() as usize;
    if n < PERSISTENCE_TREND_DEGREE as usize + 3 || bandwidth == 0 {
        return 1.0;
    }
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    // Least squares by modified Gram–Schmidt on the powers of the index mapped to [−1, 1].
    let index: Vec<f64> = (0..n)
        .map(|i| 2.0 * i as f64 / (n - 1) as f64 - 1.0)
        .collect();
    let mut residual = increments.to_vec();
    let mut basis: Vec<Vec<f64>> = Vec::with_capacity(PERSISTENCE_TREND_DEGREE as usize + 1);
    for degree in 0..=PERSISTENCE_TREND_DEGREE {
        let mut v: Vec<f64> = index.iter().map(|t| t.powi(degree)).collect();
        for b in &basis {
            let c = dot(&v, b);
            v.iter_mut().zip(b).for_each(|(x, y)| *x -= c * y);
        }
        let norm = dot(&v, &v).sqrt();
        v.iter_mut().for_each(|x| *x /= norm);
        let c = dot(&residual, &v);
        residual.iter_mut().zip(&v).for_each(|(x, y)| *x -= c * y);
        basis.push(v);
    }
    let variance = dot(&residual, &residual);
    let scale = dot(increments, increments);
    if !variance.is_finite() || variance <= 1e-20 * scale {
        return 1.0;
    }
    let lags = bandwidth.min(n - 1);
    let sum: f64 = (1..=lags)
        .map(|k| {
            let weight = 1.0 - k as f64 / (lags + 1) as f64;
            weight * dot(&residual[..n - k], &residual[k..]) / variance
        })
        .sum();
    (1.0 + 2.0 * sum).max(1.0).sqrt()
}

/// A surface's noise at the stage's end as a function of the rest's sub-step growth
/// ([`noise_fraction`]).
struct EndNoise {
    /// The squared noise per unit of growth of one sub-step, `κ²`.
    kappa2: f64,
    /// The squared levelled noise now.
    now2: f64,
    /// The squared survival per sub-step, `s²`.
    survival2: f64,
    /// The growth the rest of the stage adds, m.
    rest: f64,
}

impl EndNoise {
    /// The squared noise at the end after the rest in sub-steps of growth `growth`.
    fn variance(&self, growth: f64) -> f64 {
        let steps = self.rest / growth;
        let kept = self.survival2.powf(steps);
        // Σ_{k<m} s^{2k} for real m: (1 − s^{2m})/(1 − s²), m as s → 1.
        let added = if self.survival2 < 1.0 - 1e-12 {
            (1.0 - kept) / (1.0 - self.survival2)
        } else {
            steps
        };
        kept * self.now2 + self.kappa2 * growth * growth * added
    }
}

/// The delete-one jackknife's standard error of the estimate whose leave-one-out values are
/// `values`: `√((n − 1)/n · Σ (θ_b − θ̄)²)`; `None` for fewer than two values or any that is
/// not finite.
pub fn jackknife_error(values: &[f64]) -> Option<f64> {
    let n = values.len();
    if n < 2 || values.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let mean = values.iter().sum::<f64>() / n as f64;
    let squares: f64 = values.iter().map(|v| (v - mean).powi(2)).sum();
    Some(((n - 1) as f64 / n as f64 * squares).sqrt())
}

/// The noise of a measure that moves in jumps of `unit` (a count: 1; a width counted in
/// cells: the cell's width) whose value is `central` and whose values on the
/// [`Replicas::plausible_surfaces`] are `values`: the root-mean-square change, with Laplace's
/// rule of succession, `√((Σ (v − central)² + unit²)/(n + 2))`, so that `n` surfaces none of
/// which changed it give a jump rate of `1/(n + 2)`, not a noise of zero that `n` tries cannot
/// establish. `None` for fewer than two values or any that is not finite.
pub fn discrete_noise(central: f64, values: &[f64], unit: f64) -> Option<f64> {
    let n = values.len();
    if n < 2 || !central.is_finite() || !unit.is_finite() || values.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let squares: f64 = values.iter().map(|v| (v - central).powi(2)).sum();
    Some(((squares + unit * unit) / (n + 2) as f64).sqrt())
}

/// Sub-steps a stage with a noise target runs at the plan's own bound first, to measure the
/// noise from (16 of the 20 batches then hold samples).
pub const NOISE_WARM_UP: usize = 8;

/// The relative clearance change the next adaptive sub-step may make so that the stage ends
/// with every joint's peak depths within `target` relative noise: between `floor` (the plan's
/// bound, also the answer before [`NOISE_WARM_UP`] sub-steps or when the noise is not
/// measured) and [`NOISE_MAX_FRACTION`](crate::staging::NOISE_MAX_FRACTION).
///
/// Per surface, with `D` its peak depth (`D₀` at the stage's start, `Δᵢ` its growth in the
/// sub-steps so far), `σ` the jackknife noise of `D` now and `s` the curve's [`levelling`]:
/// each sub-step's growth carries a noise `κ Δ` with `κ = p σ/√(ΣΔᵢ²)` (`p` the curve's
/// persistence), of which a fraction `s`
/// survives each later sub-step. The rest of the stage, `D_rem` at the stage's rate so far, in
/// `m = D_rem/Δ` sub-steps of growth `Δ`, leaves at the end
/// `V = s^{2m} σ_ℓ² + κ² Δ² Σ_{k<m} s^{2k}` (`σ_ℓ` the levelled noise now; with `s = 1`,
/// `σ² + κ² D_rem Δ`), which grows with `Δ`; the largest `Δ` with `V ≤ (target·D_end)²` is
/// found by bisection, the fraction scaling with `Δ` from the last sub-step's. The smallest
/// over the surfaces.
pub(crate) fn noise_fraction(
    target: f64,
    batches: &NoiseBatches,
    joints: &[WornJoint],
    start: &[[f64; 2]],
    substeps: &[crate::SubstepReport],
    amplification: [f64; 2],
    floor: f64,
) -> f64 {
    let ceiling = crate::staging::NOISE_MAX_FRACTION.max(floor);
    let [used, remaining] = amplification;
    let Some(last) = substeps.last() else {
        return floor;
    };
    if substeps.len() < NOISE_WARM_UP || used <= 0.0 {
        return floor;
    }
    let peak = |h: &[f64]| h.iter().copied().fold(0.0, f64::max);
    let lengths: Vec<f64> = substeps.iter().map(|s| s.amplification).collect();
    let mut fraction = ceiling;
    for (j, (joint, replicas)) in joints.iter().zip(batches.replicas()).enumerate() {
        let (bearing, pin) = (joint.bearing().depth(), joint.pin().depth());
        for side in 0..2 {
            let depth_at = |s: &crate::SubstepReport| {
                s.joints.get(j).map_or(0.0, |d| {
                    if side == 0 {
                        d.max_bearing_depth
                    } else {
                        d.max_pin_depth
                    }
                })
            };
            let d0 = start.get(j).map_or(0.0, |s| s[side]);
            let curve: Vec<f64> = std::iter::once(d0)
                .chain(substeps.iter().map(depth_at))
                .collect();
            let squares: f64 = curve.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum();
            let now = curve[curve.len() - 1];
            let last_growth = now - curve[curve.len() - 2];
            let Some(sigma) =
                replicas.noise(bearing, pin, |b, p| peak(if side == 0 { b } else { p }))
            else {
                return floor;
            };
            let rest = (now - d0) / used * remaining;
            if squares <= 0.0 || rest <= 0.0 || last_growth <= 0.0 || sigma <= 0.0 {
                continue;
            }
            let levelling = levelling(&curve, &lengths);
            let ending = EndNoise {
                kappa2: (sigma * levelling.persistence).powi(2) / squares,
                now2: (sigma * levelling.share).powi(2),
                survival2: levelling.survival * levelling.survival,
                rest,
            };
            let limit = (target * (now + rest)).powi(2);
            let growth_at = |f: f64| last_growth * f / last.max_change_fraction;
            if ending.variance(growth_at(floor)) > limit {
                return floor;
            }
            let allowed = if ending.variance(growth_at(fraction)) <= limit {
                fraction
            } else {
                let (mut low, mut high) = (floor, fraction);
                for _ in 0..40 {
                    let mid = 0.5 * (low + high);
                    if ending.variance(growth_at(mid)) <= limit {
                        low = mid;
                    } else {
                        high = mid;
                    }
                }
                low
            };
            fraction = fraction.min(allowed);
        }
    }
    fraction.clamp(floor, ceiling)
}
