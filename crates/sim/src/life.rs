//! Life curves: how each wearing joint's wear grows over the drive cycles the stages stand
//! for, one point per sub-step, and when its largest local clearance reaches the maintenance
//! limit `run.clearance_limit`; with it, each joint's and the mechanism's B lives under the
//! wear coefficients' scatter, how the stages ended ([`LifeSummary`]), and the run's life
//! distributions sampled for a table and a figure ([`life_distributions`]; the distributions
//! themselves are `crate::life_distribution`'s).

use scene::{KdCorrelation, RunSettings};
use wear::{JointNoise, StageReport, WornJoint};

use super::life_distribution::{
    BLives, JointLife, LifeDistribution, LifeOf, MechanismLife, SampledLives, b_lives,
    cycles_with_noise, sample,
};
use super::{ClearanceLimitReport, JointWearSummary, LifePoint, LifeSummary, WearSummary};

/// Per joint of `initial` (the surfaces the stages started from, in the stages' order), its
/// life curve: a point at 0 cycles, then one after every sub-step of `reports`, each standing
/// for its amplification × `k` drive cycles, counted over the whole run. Returns the curves
/// and the cycles of the whole run.
///
/// The cycles of a stage accumulate in the order the staging does (`Σ amplification`, then
/// × `k`), so a stage that ended at the validity limits ends at exactly its
/// `cycles_applied_at_limits`.
pub(super) fn life_curves(
    initial: &[WornJoint],
    reports: &[StageReport],
    k: u32,
) -> (Vec<Vec<LifePoint>>, f64) {
    let mut curves: Vec<Vec<LifePoint>> = initial
        .iter()
        .map(|j| {
            vec![LifePoint {
                stage: 0,
                substep: 0,
                cycles: 0.0,
                bearing_peak_depth_m: j.bearing().peak().depth,
                pin_peak_depth_m: j.pin().peak().depth,
                worn_volume_m3: j.worn_volume(),
                max_local_clearance_m: j.max_local_clearance(),
                wear_stiffness: 0.0,
            }]
        })
        .collect();
    let k = f64::from(k);
    let mut before = 0.0;
    for report in reports {
        let mut used = 0.0;
        for (n, step) in report.substeps.iter().enumerate() {
            used += step.amplification;
            let cycles = before + used * k;
            for (curve, j) in curves.iter_mut().zip(&step.joints) {
                curve.push(LifePoint {
                    stage: report.stage + 1,
                    substep: n + 1,
                    cycles,
                    bearing_peak_depth_m: j.max_bearing_depth,
                    pin_peak_depth_m: j.max_pin_depth,
                    worn_volume_m3: j.worn_volume,
                    max_local_clearance_m: j.max_local_clearance,
                    wear_stiffness: j.wear_stiffness,
                });
            }
        }
        before += used * k;
    }
    (curves, before)
}

/// The first abscissa at which a curve of `(cycles, clearance)` points, in order of cycles,
/// reaches `limit`: linear between the two points that straddle it, the first point's cycles
/// when that is already at the limit, `None` when no point reaches it.
///
/// Within a sub-step every cell deepens linearly in the cycles, so the largest clearance is
/// convex between two points and the chord reaches the limit no later than the surfaces do:
/// for a maintenance limit the estimate errs early.
pub fn cycles_to_reach(curve: impl IntoIterator<Item = (f64, f64)>, limit: f64) -> Option<f64> {
    let mut previous: Option<(f64, f64)> = None;
    for (cycles, clearance) in curve {
        if clearance >= limit {
            return Some(match previous {
                Some((c0, v0)) => c0 + (limit - v0) / (clearance - v0) * (cycles - c0),
                None => cycles,
            });
        }
        previous = Some((cycles, clearance));
    }
    None
}

/// When `curve` reaches `limit` (see [`cycles_to_reach`]), in a number and in words, with
/// its noise from the curve's (`noise`, one per point; see [`crossing_noise`]), and the B
/// lives of a joint whose `ln k_d` scatters by `scatter`.
pub(super) fn clearance_limit(
    curve: &[LifePoint],
    noise: &[Option<JointNoise>],
    limit: f64,
    scatter: f64,
) -> ClearanceLimitReport {
    let cycles = cycles_to_reach(
        curve.iter().map(|p| (p.cycles, p.max_local_clearance_m)),
        limit,
    );
    let cycles_noise = cycles.and_then(|_| {
        crossing_noise(
            curve.iter().zip(noise).map(|(p, n)| {
                (
                    p.cycles,
                    p.max_local_clearance_m,
                    n.map(|n| n.max_local_clearance),
                )
            }),
            limit,
        )
    });
    let message = match (cycles, cycles_noise) {
        (Some(c), Some(noise)) if c > 0.0 => {
            format!("reached after {c:.3e} ± {noise:.1e} cycles (linear between wear sub-steps)")
        }
        (Some(c), _) if c > 0.0 => {
            format!("reached after {c:.3e} cycles (linear between wear sub-steps)")
        }
        (Some(_), _) => {
            "reached at the start: the surfaces the run started from are at the limit".to_string()
        }
        (None, _) => "not reached within the run".to_string(),
    };
    let mut report = ClearanceLimitReport {
        limit_m: limit,
        cycles,
        cycles_noise,
        message,
        k_d_scatter: scatter,
        b10_cycles: None,
        b10_noise: None,
        b50_cycles: None,
        b50_noise: None,
    };
    if let Some(lives) = report.joint_life().and_then(JointLife::b_lives) {
        report.b10_cycles = Some(lives.b10_cycles);
        report.b10_noise = lives.b10_noise;
        report.b50_cycles = Some(lives.b50_cycles);
        report.b50_noise = lives.b50_noise;
    }
    report
}

/// The life to `run.clearance_limit` (`None` without one): how the stages `reports` ended
/// (`cycles_applied` in all) and the mechanism's B lives from its `joints`' (each with its
/// [`ClearanceLimitReport`]).
pub(super) fn life_summary(
    r: &RunSettings,
    joints: &[JointWearSummary],
    reports: &[StageReport],
    cycles_applied: f64,
) -> Option<LifeSummary> {
    let limit = r.clearance_limit?;
    let short: Vec<&str> = joints
        .iter()
        .filter(|j| {
            j.clearance_limit
                .as_ref()
                .is_none_or(|l| l.cycles.is_none())
        })
        .map(|j| j.name.as_str())
        .collect();
    let at_geometry_limits = reports.last().is_some_and(|r| r.ended_at_limits.is_some());
    let ended = if short.is_empty() {
        format!("every wearing joint reached the limit within the {cycles_applied:.3e} cycles run")
    } else {
        let why = if at_geometry_limits {
            "the stages ended at the contact model's validity limits (run.stop_at_validity_limits)"
                .to_string()
        } else if r.until_limit {
            format!(
                "run.max_cycles = {:.3e} was spent",
                r.max_cycles.unwrap_or(cycles_applied)
            )
        } else {
            "the scene's stages ended (run.until_limit = true runs on to the limit)".to_string()
        };
        format!(
            "{why} after {cycles_applied:.3e} cycles, before {} reached the limit",
            short.join(" and ")
        )
    };
    let lives: Option<Vec<JointLife>> = joints
        .iter()
        .map(|j| j.clearance_limit.as_ref()?.joint_life())
        .collect();
    let correlation = r.k_d_correlation;
    let mechanism = lives.and_then(|joints| {
        b_lives(&MechanismLife {
            joints,
            correlation,
        })
    });
    let mechanism_message = match &mechanism {
        Some(b) => format!(
            "B10 {}, B50 {} cycles (the first joint to reach the limit)",
            cycles_with_noise(b.b10_cycles, b.b10_noise),
            cycles_with_noise(b.b50_cycles, b.b50_noise)
        ),
        None if !short.is_empty() => {
            "no mechanism life: not every wearing joint reached the limit".to_string()
        }
        None => "no mechanism life: a joint was at the limit from the start".to_string(),
    };
    let assumption = match correlation {
        _ if joints.len() < 2 => {
            "one wearing joint: its life is rescaled exactly from the simulated one"
        }
        KdCorrelation::Shared => {
            "one factor scales every joint's k_d (run.k_d_correlation = \"shared\"): every \
             life is rescaled exactly from the one simulated life"
        }
        KdCorrelation::Independent => {
            "each joint's k_d scatters on its own (run.k_d_correlation = \"independent\"): \
             each joint's life is rescaled alone, which leaves out how one joint's wear \
             changes the dynamics that wear the other; approximate (on the LGRES, joint A's \
             life moves 13-20 % off the rescaled one when one joint's k_d doubles alone, \
             docs/life.md)"
        }
    }
    .to_string();
    Some(LifeSummary {
        limit_m: limit,
        until_limit: r.until_limit,
        max_cycles: r.max_cycles.filter(|_| r.until_limit),
        ended,
        k_d_correlation: correlation,
        assumption,
        mechanism,
        mechanism_message,
    })
}

/// Points on a sampled life distribution: enough for a smooth curve and a plain table.
pub const LIFE_DISTRIBUTION_POINTS: usize = 201;

/// A run's life distributions to `run.clearance_limit`, sampled
/// ([`crate::life_distribution::sample`]): per wearing joint that reached the limit, and the
/// mechanism's when every one did. `None` without a limit or when none reached it.
pub fn life_distributions(wear: &WearSummary) -> Option<SampledLives> {
    let life = wear.life.as_ref()?;
    let joints: Vec<(String, JointLife, BLives)> = wear
        .joints
        .iter()
        .filter_map(|j| {
            let l = j.clearance_limit.as_ref()?;
            Some((j.name.clone(), l.joint_life()?, l.b_lives()?))
        })
        .collect();
    let mechanism = MechanismLife {
        joints: joints.iter().map(|(_, j, _)| *j).collect(),
        correlation: life.k_d_correlation,
    };
    let mut curves: Vec<(LifeOf, &dyn LifeDistribution, BLives)> = joints
        .iter()
        .map(|(name, joint, lives)| {
            (
                LifeOf::Joint(name.clone()),
                joint as &dyn LifeDistribution,
                *lives,
            )
        })
        .collect();
    if let (Some(lives), true) = (life.mechanism, joints.len() > 1) {
        curves.push((LifeOf::Mechanism, &mechanism, lives));
    }
    sample(&curves, LIFE_DISTRIBUTION_POINTS)
}

/// The noise of the cycles at which a curve of `(cycles, clearance, its noise)` points first
/// reaches `limit`, to first order: the clearance's noise there (linear between the two
/// points that straddle the limit) over the chord's slope. The first point, the surfaces the
/// run started from, counts as noise-free when its noise is unknown; `None` when the limit is
/// reached at the first point, never, or where a straddling point's noise is unknown.
pub fn crossing_noise(
    curve: impl IntoIterator<Item = (f64, f64, Option<f64>)>,
    limit: f64,
) -> Option<f64> {
    let mut previous: Option<(f64, f64, Option<f64>)> = None;
    for (index, (cycles, clearance, noise)) in curve.into_iter().enumerate() {
        if clearance >= limit {
            let (c0, v0, n0) = previous?;
            let n0 = if index == 1 { n0.or(Some(0.0)) } else { n0 };
            let (n0, n1) = (n0?, noise?);
            let slope = (clearance - v0) / (cycles - c0);
            if !slope.is_finite() || slope <= 0.0 {
                return None;
            }
            let t = (limit - v0) / (clearance - v0);
            return Some((n0 + t * (n1 - n0)) / slope);
        }
        previous = Some((cycles, clearance, noise));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Clearances in µm at cycles 0, 100, 300, 600 (values exact in binary).
    const CURVE: [(f64, f64); 4] = [(0.0, 500.0), (100.0, 520.0), (300.0, 600.0), (600.0, 610.0)];

    #[test]
    fn limit_is_interpolated_between_the_points_that_straddle_it() {
        // 560 lies halfway from 520 (100 cycles) to 600 (300 cycles): 200 cycles.
        assert_eq!(cycles_to_reach(CURVE, 560.0), Some(200.0));
        // A quarter of the way from 600 (300) to 610 (600): 375 cycles.
        assert_eq!(cycles_to_reach(CURVE, 602.5), Some(375.0));
        // On a point: that point's cycles; at the last point: the end of the run.
        assert_eq!(cycles_to_reach(CURVE, 520.0), Some(100.0));
        assert_eq!(cycles_to_reach(CURVE, 610.0), Some(600.0));
        // Beyond the last point: not reached; at or below the start: reached at once.
        assert_eq!(cycles_to_reach(CURVE, 610.5), None);
        assert_eq!(cycles_to_reach(CURVE, 500.0), Some(0.0));
        assert_eq!(cycles_to_reach(CURVE, 400.0), Some(0.0));
        assert_eq!(cycles_to_reach([], 1.0), None);
        // A flat stretch before the rise does not divide by zero.
        let flat = [(0.0, 500.0), (10.0, 500.0), (20.0, 540.0)];
        assert_eq!(cycles_to_reach(flat, 510.0), Some(12.5));
    }

    #[test]
    fn report_says_when_and_in_words() {
        let point = |cycles: f64, clearance: f64| LifePoint {
            stage: 1,
            substep: 1,
            cycles,
            bearing_peak_depth_m: 0.0,
            pin_peak_depth_m: 0.0,
            worn_volume_m3: 0.0,
            max_local_clearance_m: clearance,
            wear_stiffness: 0.0,
        };
        let curve: Vec<LifePoint> = CURVE.iter().map(|(c, v)| point(*c, v * 1e-6)).collect();
        let r = clearance_limit(&curve, &[], 560e-6, 0.5);
        assert!((r.cycles.unwrap() - 200.0).abs() < 1e-9, "{r:?}");
        assert_eq!(r.limit_m, 560e-6);
        assert!(
            r.message.starts_with("reached after 2.000e2 cycles"),
            "{r:?}"
        );
        // Scatter 0.5: B50 the simulated life, B10 exp(0.5 Φ⁻¹(0.1)) of it.
        assert!((r.b50_cycles.unwrap() - 200.0).abs() < 1e-9, "{r:?}");
        let ratio = r.b10_cycles.unwrap() / 200.0;
        assert!((ratio - (-0.5 * 1.281_551_565_544_600_5_f64).exp()).abs() < 1e-12);
        assert_eq!(r.b10_noise, None);
        let r = clearance_limit(&curve, &[], 1e-3, 0.5);
        assert_eq!(r.cycles, None);
        assert_eq!(r.message, "not reached within the run");
        assert_eq!(r.cycles_noise, None);
        assert_eq!((r.b10_cycles, r.b50_cycles), (None, None));
    }

    #[test]
    fn crossing_noise_is_the_clearance_noise_over_the_slope() {
        // 560 µm is reached halfway from (100, 520) to (300, 600): slope 0.4 µm a cycle, the
        // clearance's noise there halfway from 2 to 4 µm: 3 µm, so 7.5 cycles.
        let noisy = [
            (0.0, 500.0, None),
            (100.0, 520.0, Some(2.0)),
            (300.0, 600.0, Some(4.0)),
        ];
        let close = |x: Option<f64>, y: f64| x.is_some_and(|x| (x - y).abs() < 1e-12);
        assert!(close(crossing_noise(noisy, 560.0), 7.5));
        // Between the start (noise-free) and the first sub-step: a quarter of 2 µm over 0.2.
        assert!(close(crossing_noise(noisy, 505.0), 2.5));
        // Not reached, reached at the start, or a straddling point without noise: none.
        assert_eq!(crossing_noise(noisy, 700.0), None);
        assert_eq!(crossing_noise(noisy, 400.0), None);
        let unknown = [(0.0, 500.0, None), (100.0, 520.0, None)];
        assert_eq!(crossing_noise(unknown, 510.0), None);
    }
}
