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
//! What it does not see: a replica follows the path the surfaces actually took (the samples
//! share the geometry they were simulated on), so the feedback of the noise on later wear
//! rates is not in it; and the peak of a noisy profile is biased upwards by about its noise.

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

    /// The noise of `joint`'s results on its surfaces as they stand: peak depths, worn volume
    /// and largest local clearance. `None` with fewer than two replicas.
    pub fn joint_noise(&self, joint: &WornJoint) -> Option<JointNoise> {
        if self.count() < 2 {
            return None;
        }
        let (bearing, pin) = (joint.bearing().depth(), joint.pin().depth());
        let peak = |h: &[f64]| h.iter().copied().fold(0.0, f64::max);
        let c0 = joint.nominal_clearance();
        let width = joint.hinge_width();
        let (r_b, r_p) = (
            joint.bearing().nominal_radius(),
            joint.pin().nominal_radius(),
        );
        Some(JointNoise {
            bearing_peak_depth: self.noise(bearing, pin, |b, _| peak(b))?,
            pin_peak_depth: self.noise(bearing, pin, |_, p| peak(p))?,
            worn_volume: self.noise(bearing, pin, |b, p| {
                layer_volume(b, r_b, width) + layer_volume(p, r_p, width)
            })?,
            max_local_clearance: self.noise(bearing, pin, |b, p| c0 + 0.5 * (peak(b) + peak(p)))?,
        })
    }
}

/// The sampling noise (jackknife standard error) of a joint's results at one point of a run.
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

/// Sub-steps a stage with a noise target runs at the plan's own bound first, to measure the
/// noise from (16 of the 20 batches then hold samples).
pub const NOISE_WARM_UP: usize = 8;

/// The relative clearance change the next adaptive sub-step may make so that the stage ends
/// with every joint's peak depths within `target` relative noise: between `floor` (the plan's
/// bound, also the answer before [`NOISE_WARM_UP`] sub-steps or when the noise is not
/// measured) and [`NOISE_MAX_FRACTION`](crate::staging::NOISE_MAX_FRACTION).
///
/// Per surface, with `D` its peak depth (`D₀` at the stage's start, `Δᵢ` its growth in the
/// sub-steps so far) and `σ` the noise of `D` now: each sub-step's growth carries a relative
/// noise `ρ = σ/√(ΣΔᵢ²)`; the rest of the stage, `D_rem` at the stage's rate so far, in
/// sub-steps of growth `Δ` adds `ρ²·D_rem·Δ` to `σ²`, so the end's noise stays within
/// `target·D_end` for `Δ ≤ (target²·D_end² − σ²)/(ρ²·D_rem)`; the fraction scales with `Δ`
/// from the last sub-step's. The smallest over the surfaces.
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
            let mut before = d0;
            let mut squares = 0.0;
            for s in substeps {
                let d = depth_at(s);
                squares += (d - before).powi(2);
                before = d;
            }
            let now = before;
            let last_growth = now - substeps.iter().rev().nth(1).map_or(d0, depth_at);
            let Some(sigma) =
                replicas.noise(bearing, pin, |b, p| peak(if side == 0 { b } else { p }))
            else {
                return floor;
            };
            let rest = (now - d0) / used * remaining;
            if squares <= 0.0 || rest <= 0.0 || last_growth <= 0.0 || sigma <= 0.0 {
                continue;
            }
            let rho2 = sigma * sigma / squares;
            let end = now + rest;
            let allowed = (target * target * end * end - sigma * sigma) / (rho2 * rest);
            if allowed <= 0.0 {
                return floor;
            }
            fraction = fraction.min(last.max_change_fraction * allowed / last_growth);
        }
    }
    fraction.clamp(floor, ceiling)
}
