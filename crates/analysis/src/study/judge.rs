//! Verdicts on the paper's trends, judged on quantities that do not swing with chaos (docs/model.md §8).
//!
//! Chaos-robust quantities used by the judge: per-cycle **medians** of the peak normal force
//! after the start-up window (with their bootstrap noise), the largest deviation of rod 3 from
//! the ideal mechanism after the window (with the jackknife noise of a maximum over the
//! cycles), the energy dissipated per cycle (with the standard error of its cycles after the
//! window), the worn volume, the **worn
//! arc** (angular width where the depth is at least
//! [`ARC_FRACTION`] of the surface's peak) and, for irregularity, the coefficient of variation
//! of the depth over the worn arc and the number of separate concentrated ranges (depth at
//! least [`RANGE_FRACTION`] of the peak), each wear measure with its noise from the stage's
//! jackknife replicas (`wear::Replicas`), levelled as the run's life curves are; the arc and
//! the count, which move in jumps, from surfaces one noise away. A difference's noise combines
//! both cases'.

use std::fmt;

use wear::{WornJoint, WornProfile};

use super::results::{StudyKind, StudyResults};
use lgres::claim::{Cases, Claim, Direction, ResponseMeasure, WearMeasure};
use sim::{Response, ResponseSummary, RunOutcome};

/// Fraction of a surface's peak depth that counts as worn, for the worn arc and irregularity.
pub const ARC_FRACTION: f64 = 0.1;
/// Fraction of the peak depth that makes a concentrated range (as in the run summary).
pub const RANGE_FRACTION: f64 = 0.5;
/// Smallest relative change the judge counts as a change at all.
pub const RELATIVE_MARGIN: f64 = 0.05;

/// Whether a trend is seen in our results.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// The quantities change the way the paper says.
    Holds,
    /// More of the quantities that change go the paper's way than the other, but some go the
    /// other way: the trend holds for some of what the paper claims, not all.
    HoldsInPart,
    /// They change the other way (at least as many against the paper as with it).
    DoesNotHold,
    /// Most stay within their noise (and the relative margin): the runs cannot tell.
    Inconclusive,
}

impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Verdict::Holds => "HOLDS",
            Verdict::HoldsInPart => "HOLDS IN PART",
            Verdict::DoesNotHold => "DOES NOT HOLD",
            Verdict::Inconclusive => "INCONCLUSIVE",
        })
    }
}

/// One quantity the paper says grows from the `low` case to the `high` case.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    /// What it is, with its unit.
    pub quantity: String,
    /// Value in the case the paper says is smaller.
    pub low: f64,
    /// Value in the case the paper says is larger.
    pub high: f64,
    /// Spread of the values (e.g. interquartile range of per-cycle peaks); a change must
    /// exceed it to count.
    pub noise: f64,
}

impl Comparison {
    /// Whether this quantity grew: by more than its noise and [`RELATIVE_MARGIN`].
    pub fn verdict(&self) -> Verdict {
        judge_increase(self.low, self.high, self.noise)
    }
}

/// Whether `high` exceeds `low` by more than `noise` and by more than [`RELATIVE_MARGIN`] of
/// the larger magnitude ([`Verdict::DoesNotHold`] for a decrease as large, else inconclusive).
pub fn judge_increase(low: f64, high: f64, noise: f64) -> Verdict {
    if !(low.is_finite() && high.is_finite()) {
        return Verdict::Inconclusive;
    }
    let margin = (RELATIVE_MARGIN * low.abs().max(high.abs())).max(noise.abs());
    if high - low > margin {
        Verdict::Holds
    } else if low - high > margin {
        Verdict::DoesNotHold
    } else {
        Verdict::Inconclusive
    }
}

/// A trend over several quantities. Inconclusive when at most half of them move beyond their
/// noise (or there are none): only the noise decides that. Otherwise it holds when none moves
/// against the paper, holds in part when more move with it than against, and does not hold
/// when at least as many move against it.
pub fn judge_trend(comparisons: &[Comparison]) -> Verdict {
    let verdicts: Vec<Verdict> = comparisons.iter().map(Comparison::verdict).collect();
    let count = |v| verdicts.iter().filter(|x| **x == v).count();
    let (up, down) = (count(Verdict::Holds), count(Verdict::DoesNotHold));
    if 2 * (up + down) <= verdicts.len() {
        Verdict::Inconclusive
    } else if down == 0 {
        Verdict::Holds
    } else if up > down {
        Verdict::HoldsInPart
    } else {
        Verdict::DoesNotHold
    }
}

/// Wear measures of one surface.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceMetrics {
    /// Peak depth, m.
    pub peak_m: f64,
    /// Its body-frame angle, deg.
    pub peak_deg: f64,
    /// Angular width where depth ≥ [`ARC_FRACTION`] × peak, deg.
    pub arc_deg: f64,
    /// Coefficient of variation (std/mean) of depth over those cells.
    pub cv: f64,
    /// Concentrated ranges (depth ≥ [`RANGE_FRACTION`] × peak), deg, deepest first.
    pub ranges_deg: Vec<[f64; 2]>,
}

/// Wear measures of `p` (see [`SurfaceMetrics`]).
pub fn surface_metrics(p: &WornProfile) -> SurfaceMetrics {
    let wear::Peak {
        depth: peak, angle, ..
    } = p.peak();
    let worn: Vec<f64> = p
        .depth()
        .iter()
        .copied()
        .filter(|h| peak > 0.0 && *h >= ARC_FRACTION * peak)
        .collect();
    let n = worn.len() as f64;
    let cv = if worn.is_empty() {
        0.0
    } else {
        let mean = worn.iter().sum::<f64>() / n;
        let var = worn.iter().map(|h| (h - mean).powi(2)).sum::<f64>() / n;
        var.sqrt() / mean
    };
    SurfaceMetrics {
        peak_m: peak,
        peak_deg: angle.to_degrees(),
        arc_deg: n * p.cell_width().to_degrees(),
        cv,
        ranges_deg: p
            .concentrated_ranges(RANGE_FRACTION)
            .iter()
            .map(|r| r.degrees())
            .collect(),
    }
}

/// Wear measures of one joint after a stage.
#[derive(Debug, Clone, PartialEq)]
pub struct JointMetrics {
    /// Joint name.
    pub name: String,
    /// Bearing surface.
    pub bearing: SurfaceMetrics,
    /// Pin surface.
    pub pin: SurfaceMetrics,
    /// Volume removed from both surfaces, m³.
    pub volume_m3: f64,
    /// What the noise of these measures comes from (empty when the run measured none, and in
    /// the replicas' own measures).
    pub samples: NoiseSamples,
}

/// The samples the noise of a joint's wear measures is read from.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct NoiseSamples {
    /// The measures of each jackknife replica of the surfaces (`wear::Replicas`): the noise of
    /// a smooth measure is their spread.
    pub replicas: Vec<JointMetrics>,
    /// The measures on surfaces one noise away (`wear::Replicas::plausible_surfaces`): the
    /// noise of a measure that moves in jumps (a worn arc, a count) is their spread.
    pub plausible: Vec<JointMetrics>,
    /// The share of the jackknife's noise at the stage's end (levelling and persistence).
    pub levelling: LevellingShares,
    /// Width of one wear cell, deg: the step a worn arc moves in.
    pub cell_deg: f64,
}

/// The share of a joint's jackknife noise there at the stage's end: the run's levelled noise
/// over the jackknife's (`wear::JointNoise::levelled`: below 1 where the worn geometry levels
/// the fluctuations out, above where consecutive sub-steps' persist; 1: not measured).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LevellingShares {
    /// Of the bearing's peak depth.
    pub bearing: f64,
    /// Of the pin's peak depth.
    pub pin: f64,
    /// Of the worn volume.
    pub volume: f64,
}

impl Default for LevellingShares {
    fn default() -> Self {
        Self {
            bearing: 1.0,
            pin: 1.0,
            volume: 1.0,
        }
    }
}

impl LevellingShares {
    /// The shares at a stage's end from the run's levelled noise there and the jackknife's.
    fn of(levelled: Option<&wear::JointNoise>, jackknife: Option<&wear::JointNoise>) -> Self {
        let (Some(levelled), Some(jackknife)) = (levelled, jackknife) else {
            return Self::default();
        };
        let share = |l: f64, j: f64| {
            if j > 0.0 && l.is_finite() {
                (l / j).max(0.0)
            } else {
                1.0
            }
        };
        Self {
            bearing: share(levelled.bearing_peak_depth, jackknife.bearing_peak_depth),
            pin: share(levelled.pin_peak_depth, jackknife.pin_peak_depth),
            volume: share(levelled.worn_volume, jackknife.worn_volume),
        }
    }
}

impl JointMetrics {
    /// The measures of `j`'s surfaces, with the noise samples `replicas` give (levelled by
    /// `levelling`).
    fn new(
        name: &str,
        j: &WornJoint,
        replicas: Option<&wear::Replicas>,
        levelling: LevellingShares,
    ) -> Self {
        let (bearing, pin) = (j.bearing(), j.pin());
        let measured = |[b, p]: [Vec<f64>; 2]| -> Option<JointMetrics> {
            // A replica may dip a barely worn cell below zero: no wear there.
            let clamp = |h: Vec<f64>| h.into_iter().map(|x| x.max(0.0)).collect::<Vec<f64>>();
            let b = WornProfile::from_depths(bearing.side(), bearing.nominal_radius(), clamp(b));
            let p = WornProfile::from_depths(pin.side(), pin.nominal_radius(), clamp(p));
            let (b, p) = (b.ok()?, p.ok()?);
            Some(JointMetrics {
                name: name.to_string(),
                bearing: surface_metrics(&b),
                pin: surface_metrics(&p),
                volume_m3: b.worn_volume(j.hinge_width()) + p.worn_volume(j.hinge_width()),
                samples: NoiseSamples::default(),
            })
        };
        let mut metrics = Self {
            name: name.to_string(),
            bearing: surface_metrics(bearing),
            pin: surface_metrics(pin),
            volume_m3: j.worn_volume(),
            samples: NoiseSamples::default(),
        };
        if let Some(r) = replicas {
            let (depth_b, depth_p) = (bearing.depth(), pin.depth());
            let depth_share = metrics.depth_share(&levelling);
            metrics.samples = NoiseSamples {
                replicas: r
                    .surfaces(depth_b, depth_p)
                    .into_iter()
                    .filter_map(measured)
                    .collect(),
                plausible: r
                    .plausible_surfaces(depth_b, depth_p, depth_share)
                    .into_iter()
                    .filter_map(measured)
                    .collect(),
                levelling,
                cell_deg: bearing.cell_width().to_degrees(),
            };
        }
        metrics
    }

    /// The levelling's share of the deeper surface's peak: the one the measures of the
    /// profiles' shape take.
    fn depth_share(&self, levelling: &LevellingShares) -> f64 {
        if self.bearing.peak_m >= self.pin.peak_m {
            levelling.bearing
        } else {
            levelling.pin
        }
    }

    /// The jackknife's standard error of `value` over the replicas, times `share`.
    fn jackknife(&self, value: impl Fn(&JointMetrics) -> f64, share: f64) -> Option<f64> {
        let values: Vec<f64> = self.samples.replicas.iter().map(value).collect();
        wear::jackknife_error(&values).map(|n| n * share)
    }

    /// The sampling noise of `measure` of these surfaces (`None` when the run measured
    /// none): for a smooth measure (volume, peak depth, depth variation) the jackknife's
    /// standard error over the replicas times the levelling's share; for one that moves in
    /// jumps (worn arc, concentrated ranges) the spread over surfaces one levelled noise away
    /// (`wear::discrete_noise`, in steps of a cell and of one range).
    pub fn noise(&self, measure: WearMeasure) -> Option<f64> {
        let value = measure_value(measure);
        let samples = &self.samples;
        let plausible = || samples.plausible.iter().map(value).collect::<Vec<f64>>();
        match measure {
            WearMeasure::Volume => self.jackknife(value, samples.levelling.volume),
            WearMeasure::PeakDepth | WearMeasure::DepthVariation => {
                self.jackknife(value, self.depth_share(&samples.levelling))
            }
            WearMeasure::Arc => wear::discrete_noise(value(self), &plausible(), samples.cell_deg),
            WearMeasure::ConcentratedRanges => wear::discrete_noise(value(self), &plausible(), 1.0),
        }
    }

    /// The noise of the bearing's and the pin's peak depth, m (`None` when not measured):
    /// the jackknife's, levelled.
    pub fn peak_noises(&self) -> [Option<f64>; 2] {
        let levelling = &self.samples.levelling;
        [
            self.jackknife(|m| m.bearing.peak_m, levelling.bearing),
            self.jackknife(|m| m.pin.peak_m, levelling.pin),
        ]
    }
    /// Deeper of the two surfaces' peaks, m.
    pub fn peak_m(&self) -> f64 {
        self.bearing.peak_m.max(self.pin.peak_m)
    }
    /// Mean worn arc of the two surfaces, deg.
    pub fn arc_deg(&self) -> f64 {
        0.5 * (self.bearing.arc_deg + self.pin.arc_deg)
    }
    /// Mean coefficient of variation of the two surfaces.
    pub fn cv(&self) -> f64 {
        0.5 * (self.bearing.cv + self.pin.cv)
    }
    /// Concentrated ranges on both surfaces.
    pub fn range_count(&self) -> usize {
        self.bearing.ranges_deg.len() + self.pin.ranges_deg.len()
    }
}

/// The value of `measure` of a joint's surfaces, in the unit the report gives it.
fn measure_value(measure: WearMeasure) -> fn(&JointMetrics) -> f64 {
    match measure {
        WearMeasure::Volume => |m| m.volume_m3 * 1e9,
        WearMeasure::Arc => JointMetrics::arc_deg,
        WearMeasure::PeakDepth => |m| m.peak_m() * 1e6,
        WearMeasure::DepthVariation => JointMetrics::cv,
        WearMeasure::ConcentratedRanges => |m| m.range_count() as f64,
    }
}

/// Wear measures per joint after stage `stage` (0-based) of a run.
pub fn wear_metrics(outcome: &RunOutcome, stage: usize) -> Vec<JointMetrics> {
    outcome
        .wear
        .iter()
        .filter_map(|h| {
            h.stages.get(stage).map(|j| {
                let replicas = h.stage_replicas.get(stage);
                let levelling = LevellingShares::of(
                    stage_end(h, stage).and_then(|k| h.life_noise.get(k)?.as_ref()),
                    replicas.and_then(|r| r.joint_noise(j)).as_ref(),
                );
                JointMetrics::new(&h.name, j, replicas, levelling)
            })
        })
        .collect()
}

/// The index into `h.life` of stage `stage`'s (0-based) last point.
fn stage_end(h: &sim::JointWearHistory, stage: usize) -> Option<usize> {
    h.life.iter().rposition(|p| p.stage == stage + 1)
}

/// Wear measures per joint after the last stage of a run.
pub fn final_wear(outcome: &RunOutcome) -> Vec<JointMetrics> {
    let last = outcome
        .wear
        .iter()
        .map(|h| h.stages.len())
        .max()
        .unwrap_or(0);
    wear_metrics(outcome, last.saturating_sub(1))
}

/// The comparisons of a `low` and a `high` run: the `response` quantities on unworn and then
/// on worn surfaces, then the `wear` quantities after the last stage, joint by joint.
pub fn compare_runs(
    low: &RunOutcome,
    high: &RunOutcome,
    response: &[ResponseMeasure],
    wear: &[WearMeasure],
) -> Vec<Comparison> {
    let mut out = Vec::new();
    let responses = [
        (
            "unworn",
            Some((&low.summary.response, &low.response)),
            Some((&high.summary.response, &high.response)),
        ),
        (
            "worn",
            low.summary
                .worn_response
                .as_ref()
                .zip(low.worn_response.as_ref()),
            high.summary
                .worn_response
                .as_ref()
                .zip(high.worn_response.as_ref()),
        ),
    ];
    let cycles = |run: &RunOutcome, r: &Response| {
        CycleMaxima::of(r, run.summary.transient_window_s, run.summary.period_s)
    };
    for (label, a, b) in responses {
        let (Some((a, ra)), Some((b, rb))) = (a, b) else {
            continue;
        };
        let maxima = [cycles(low, ra), cycles(high, rb)];
        for measure in response {
            out.extend(response_comparisons(*measure, label, [a, b], &maxima));
        }
    }
    out.extend(wear_comparisons(&final_wear(low), &final_wear(high), wear));
    out
}

/// Per drive cycle after the start-up window, the largest `|Δx|` and `|Δy|` of the response
/// body from the ideal mechanism: the samples the noise of the run's largest deviation comes
/// from.
struct CycleMaxima {
    x: Vec<f64>,
    y: Vec<f64>,
    /// The energy every clearance joint dissipated in each whole cycle after the window, J.
    dissipated: Vec<f64>,
}

impl CycleMaxima {
    fn of(r: &Response, window: f64, period: f64) -> Self {
        let mut maxima = Self {
            x: Vec::new(),
            y: Vec::new(),
            dissipated: Vec::new(),
        };
        if !period.is_finite() || period <= 0.0 {
            return maxima;
        }
        maxima.dissipated = cycle_dissipation(r, window, period);
        for (k, t) in r.times.iter().enumerate() {
            if *t < window {
                continue;
            }
            let cycle = ((t - window) / period) as usize;
            if maxima.x.len() <= cycle {
                maxima.x.resize(cycle + 1, 0.0);
                maxima.y.resize(cycle + 1, 0.0);
            }
            let gap = |a: &[f64], b: &[f64]| match (a.get(k), b.get(k)) {
                (Some(a), Some(b)) => (a - b).abs(),
                _ => 0.0,
            };
            maxima.x[cycle] = maxima.x[cycle].max(gap(&r.motion.x, &r.ideal.x));
            maxima.y[cycle] = maxima.y[cycle].max(gap(&r.motion.y, &r.ideal.y));
        }
        maxima
    }
}

/// The energy the clearance joints dissipated in each whole cycle `[w + cT, w + (c + 1)T)`
/// after the window `w`, read from their running totals at the first output at or after
/// each cycle's bounds (to a millionth of a period).
fn cycle_dissipation(r: &Response, window: f64, period: f64) -> Vec<f64> {
    let total = |k: usize| -> f64 {
        r.contact
            .iter()
            .map(|c| c.dissipated.get(k).copied().unwrap_or(0.0))
            .sum()
    };
    let slack = 1e-6 * period;
    let at = |t: f64| r.times.iter().position(|s| *s >= t - slack);
    let mut out = Vec::new();
    let mut start = at(window);
    let mut cycle = 1.0;
    while let Some(from) = start {
        let bound = window + cycle * period;
        if r.times.last().is_none_or(|last| *last < bound - slack) {
            break;
        }
        let Some(to) = at(bound) else { break };
        out.push(total(to) - total(from));
        start = Some(to);
        cycle += 1.0;
    }
    out
}

/// The standard error of the dissipation per cycle over `cycles` cycles, from the spread of
/// the whole cycles' dissipation after the window (`per_cycle`, taken as independent: the
/// motion is chaotic): `sd/√cycles`; `None` with fewer than two such cycles.
fn dissipation_noise(per_cycle: &[f64], cycles: u32) -> Option<f64> {
    let n = per_cycle.len();
    if n < 2 || cycles == 0 || per_cycle.iter().any(|e| !e.is_finite()) {
        return None;
    }
    let mean = per_cycle.iter().sum::<f64>() / n as f64;
    let variance = per_cycle.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
    Some((variance / f64::from(cycles)).sqrt())
}

/// The jackknife noise of the largest of `maxima` (one per cycle): how far it moves when
/// a cycle is left out (`None` for fewer than two cycles).
fn largest_noise(maxima: &[f64]) -> Option<f64> {
    let leave_out: Vec<f64> = (0..maxima.len())
        .map(|c| {
            maxima
                .iter()
                .enumerate()
                .filter(|(k, _)| *k != c)
                .map(|(_, m)| *m)
                .fold(0.0, f64::max)
        })
        .collect();
    wear::jackknife_error(&leave_out)
}

fn response_comparisons(
    measure: ResponseMeasure,
    label: &str,
    [a, b]: [&ResponseSummary; 2],
    maxima: &[CycleMaxima; 2],
) -> Vec<Comparison> {
    let deviation = |r: &ResponseSummary, f: fn(&sim::Deviation) -> f64| {
        r.deviation_after_transient
            .as_ref()
            .map_or(f64::NAN, |d| f(d) * 1e3)
    };
    match measure {
        ResponseMeasure::PeakForce => a
            .joints
            .iter()
            .zip(&b.joints)
            .map(|(ja, jb)| {
                // Not measured (a window covering the run) compares as NaN: inconclusive.
                let stat = |p: &Option<sim::PeakStats>, f: fn(&sim::PeakStats) -> f64| {
                    p.as_ref().map_or(f64::NAN, |p| f(p) * 1e-3)
                };
                let (pa, pb) = (
                    &ja.normal_force_after_transient,
                    &jb.normal_force_after_transient,
                );
                Comparison {
                    quantity: format!("{label}: median cycle peak F_n {} (kN)", ja.name),
                    low: stat(pa, |p| p.cycle_median),
                    high: stat(pb, |p| p.cycle_median),
                    noise: combined([
                        pa.as_ref().map(|p| p.cycle_median_noise * 1e-3),
                        pb.as_ref().map(|p| p.cycle_median_noise * 1e-3),
                    ]),
                }
            })
            .collect(),
        ResponseMeasure::Deviation => vec![
            Comparison {
                quantity: format!("{label}: rod-3 max |Δx| (mm)"),
                low: deviation(a, |d| d.x_m),
                high: deviation(b, |d| d.x_m),
                noise: combined(
                    maxima
                        .each_ref()
                        .map(|m| largest_noise(&m.x).map(|n| n * 1e3)),
                ),
            },
            Comparison {
                quantity: format!("{label}: rod-3 max |Δy| (mm)"),
                low: deviation(a, |d| d.y_m),
                high: deviation(b, |d| d.y_m),
                noise: combined(
                    maxima
                        .each_ref()
                        .map(|m| largest_noise(&m.y).map(|n| n * 1e3)),
                ),
            },
        ],
        ResponseMeasure::Dissipation => vec![Comparison {
            quantity: format!("{label}: energy dissipated per cycle (J)"),
            low: a.dissipated_per_cycle_j,
            high: b.dissipated_per_cycle_j,
            noise: combined([
                dissipation_noise(&maxima[0].dissipated, a.cycles),
                dissipation_noise(&maxima[1].dissipated, b.cycles),
            ]),
        }],
    }
}

/// The `measures` of the joints' wear in a `low` and a `high` case, joint by joint.
pub fn wear_comparisons(
    low: &[JointMetrics],
    high: &[JointMetrics],
    measures: &[WearMeasure],
) -> Vec<Comparison> {
    let mut out = Vec::new();
    for (a, b) in low.iter().zip(high) {
        for measure in measures {
            let quantity = match measure {
                WearMeasure::Volume => format!("worn volume {} (mm³)", a.name),
                WearMeasure::Arc => {
                    format!("worn arc {} (deg, depth ≥ {ARC_FRACTION}·peak)", a.name)
                }
                WearMeasure::PeakDepth => format!("peak depth {} (µm)", a.name),
                WearMeasure::DepthVariation => {
                    format!("irregularity {}: CV of depth over the worn arc", a.name)
                }
                WearMeasure::ConcentratedRanges => {
                    format!("irregularity {}: concentrated ranges (count)", a.name)
                }
            };
            let value = measure_value(*measure);
            out.push(Comparison {
                quantity,
                low: value(a),
                high: value(b),
                noise: combined([a.noise(*measure), b.noise(*measure)]),
            });
        }
    }
    out
}

/// The noise of a difference of two values with independent noises `noises`:
/// `√(σ₁² + σ₂²)`; NaN (the comparison cannot be judged on its noise, so it reads as not
/// measured) when either is unknown.
fn combined(noises: [Option<f64>; 2]) -> f64 {
    match noises {
        [Some(a), Some(b)] => a.hypot(b),
        _ => f64::NAN,
    }
}

/// Stage `low` against stage `high` (0-based) of one run: the `measures` of the wear after
/// each.
pub fn compare_stages(
    run: &RunOutcome,
    low: usize,
    high: usize,
    measures: &[WearMeasure],
) -> Vec<Comparison> {
    wear_comparisons(&wear_metrics(run, low), &wear_metrics(run, high), measures)
}

/// A trend verdict for the summary.
#[derive(Debug, Clone)]
pub struct TrendVerdict {
    /// Study name.
    pub study: &'static str,
    /// The paper's claim.
    pub claim: String,
    /// Our verdict.
    pub verdict: Verdict,
    /// Quantities: how many grew, of how many.
    pub grew: usize,
    /// How many shrank (moved against the paper).
    pub shrank: usize,
    /// Number of quantities.
    pub total: usize,
}

fn trend_verdict(study: &'static str, claim: &str, c: &[Comparison]) -> TrendVerdict {
    TrendVerdict {
        study,
        claim: claim.to_string(),
        verdict: judge_trend(c),
        grew: c.iter().filter(|c| c.verdict() == Verdict::Holds).count(),
        shrank: c
            .iter()
            .filter(|c| c.verdict() == Verdict::DoesNotHold)
            .count(),
        total: c.len(),
    }
}

/// The trends of `results`' studies, with their comparisons and the labels of their two
/// cases (the case the paper says is smaller first).
pub fn trends(results: &StudyResults) -> Vec<(TrendVerdict, Vec<Comparison>, [String; 2])> {
    let mut out = Vec::new();
    for kind in &results.studies {
        let StudyKind::Paper(study) = kind else {
            continue;
        };
        let claim = &study.claim;
        let Some((comparisons, labels)) = judge_claim(claim, results) else {
            continue;
        };
        out.push((
            trend_verdict(study.name, claim.trend, &comparisons),
            comparisons,
            labels,
        ));
    }
    out
}

/// The comparisons a claim is judged on, and its cases' labels, with the case the paper says
/// is smaller as `low`; `None` when a case's run is missing.
fn judge_claim(claim: &Claim, results: &StudyResults) -> Option<(Vec<Comparison>, [String; 2])> {
    match claim.cases {
        Cases::Scenes {
            first,
            second,
            response,
        } => {
            let (low, high) =
                smaller_first(claim.direction, results.run(first)?, results.run(second)?);
            Some((
                compare_runs(&low.outcome, &high.outcome, response, claim.wear),
                [low.key.clone(), high.key.clone()],
            ))
        }
        Cases::Stages {
            scene,
            first,
            second,
        } => {
            let run = results.run(scene)?;
            let (low, high) = smaller_first(claim.direction, first, second);
            Some((
                compare_stages(
                    &run.outcome,
                    low.saturating_sub(1),
                    high.saturating_sub(1),
                    claim.wear,
                ),
                [format!("stage {low}"), format!("stage {high}")],
            ))
        }
    }
}

/// The two cases with the one the paper says is smaller first.
fn smaller_first<T>(direction: Direction, first: T, second: T) -> (T, T) {
    match direction {
        Direction::Grows => (first, second),
        Direction::Shrinks => (second, first),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sim::ContactSeries;

    /// Two joints dissipating known amounts in each cycle after a window: the cycles' sums come
    /// back from the running totals, and their noise is the spread over √cycles.
    #[test]
    fn each_whole_cycles_dissipation_is_read_from_the_running_totals() {
        let (window, period, step) = (0.1, 1.0, 0.01);
        let per_cycle = [4.0, 5.5, 3.0, 4.5];
        let times: Vec<f64> = (0..=430).map(|k| f64::from(k) * step).collect();
        // Dissipated at a steady rate within each cycle, split 3:1 between the joints.
        let total = |t: f64| -> f64 {
            if t < window {
                return 7.0 * t / window;
            }
            let c = ((t - window) / period).floor() as usize;
            let done: f64 = per_cycle.iter().take(c).sum();
            let rate = per_cycle.get(c).copied().unwrap_or(0.0);
            7.0 + done + rate * ((t - window) / period - c as f64)
        };
        let series = |share: f64| ContactSeries {
            dissipated: times.iter().map(|t| share * total(*t)).collect(),
            ..Default::default()
        };
        let response = Response {
            times: times.clone(),
            contact: vec![series(0.75), series(0.25)],
            ..Default::default()
        };
        let cycles = cycle_dissipation(&response, window, period);
        // 4.3 s hold four whole cycles after the window.
        assert_eq!(cycles.len(), 4, "{cycles:?}");
        for (got, want) in cycles.iter().zip(per_cycle) {
            assert!((got - want).abs() < 1e-9, "{cycles:?}");
        }
        let mean = per_cycle.iter().sum::<f64>() / 4.0;
        let sd = (per_cycle.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / 3.0).sqrt();
        let noise = dissipation_noise(&cycles, 5).unwrap();
        assert!((noise - sd / 5f64.sqrt()).abs() < 1e-9, "{noise}");
        assert!(dissipation_noise(&cycles[..1], 5).is_none());
    }
}
