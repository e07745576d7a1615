//! Staged extrapolation with synthetic runners (no integrator).

mod common;

use approx::assert_relative_eq;
use common::*;
use contact::SurfaceProfile;
use std::convert::Infallible;
use wear::{
    Extrapolation, FormingBound, GeometryLimits, RunContext, StagePlan, StageWear, StagingError,
    WearError, WornJoint, WornProfile, run_stages,
};

/// Wear localized around cell 250 (bearing) and 260 (pin), proportional to the current local
/// clearance `c0 + h/2` of each cell: it accelerates as the joint opens.
fn clearance_proportional(joint: &WornJoint, rate: f64) -> StageWear {
    let c0 = joint.nominal_clearance();
    let worn = |surface: &WornProfile, at: usize| -> Vec<f64> {
        let bump = |k: usize| (-((k as f64 - at as f64) / 8.0).powi(2)).exp();
        let depth = surface.depth().iter().enumerate();
        depth
            .map(|(k, h)| rate * (c0 + h / 2.0) * bump(k))
            .collect()
    };
    StageWear::from_depths(joint, worn(joint.bearing(), 250), worn(joint.pin(), 260)).unwrap()
}

/// Each joint's [`clearance_proportional`] wear at its own rate: a runner's result.
fn proportional(joints: &[WornJoint], rates: &[f64]) -> Result<Vec<StageWear>, Infallible> {
    Ok(joints
        .iter()
        .zip(rates)
        .map(|(joint, &rate)| clearance_proportional(joint, rate))
        .collect())
}

/// Largest relative change of the clearance of aligned cell pairs, `c0 + (h_b + h_p)/2`.
fn measured_change(before: &WornJoint, after: &WornJoint, shift: isize) -> f64 {
    let n = before.bearing().cells() as isize;
    (0..n)
        .map(|k| {
            let j = (k + shift).rem_euclid(n) as usize;
            let c = |w: &WornJoint| {
                w.nominal_clearance() + 0.5 * (w.bearing().depth()[k as usize] + w.pin().depth()[j])
            };
            c(after) / c(before) - 1.0
        })
        .fold(0.0, f64::max)
}

/// The paper's plan, adaptive in the clearance change only (no shape bounds).
fn fraction_only(stages: usize) -> StagePlan {
    StagePlan::paper(stages).with_extrapolation(Extrapolation::Adaptive {
        max_fraction: Extrapolation::DEFAULT_FRACTION,
        max_substeps: Extrapolation::DEFAULT_MAX_SUBSTEPS,
        max_slope_change: f64::INFINITY,
        max_curvature_change: f64::INFINITY,
    })
}

#[test]
fn adaptive_split_obeys_fraction_and_sums_to_factor() {
    let mut joints = vec![joint(1000), joint(500)];
    let plan = fraction_only(2);
    let mut calls = Vec::new();
    let mut history = vec![joints.clone()];
    let reports = run_stages(&mut joints, &plan, |ctx: RunContext, js: &[WornJoint]| {
        calls.push(ctx);
        if ctx.substep > 0 {
            // The runner sees the surfaces updated by the previous sub-step.
            assert_ne!(js, &history.last().unwrap()[..]);
        }
        history.push(js.to_vec());
        proportional(js, &[1e-4, 2e-5])
    })
    .unwrap();
    history.push(joints.clone());
    assert_eq!(reports.len(), 2);
    let mut index = 0;
    for report in &reports {
        assert!(report.warning.is_none());
        let sum: f64 = report.substeps.iter().map(|s| s.amplification).sum();
        assert_relative_eq!(sum, plan.amplification, max_relative = 1e-12);
        // One run per sub-step, weighted with its amplification.
        let amplifications: Vec<f64> = report.substeps.iter().map(|s| s.amplification).collect();
        assert_eq!(report.run_weights, amplifications);
        // 1e-4 per unit per surface half: amplification 1000 per 10 % sub-step.
        assert!(
            report.substeps.len() >= 20,
            "{} sub-steps",
            report.substeps.len()
        );
        for s in &report.substeps {
            assert!(
                s.max_change_fraction <= 0.1 * (1.0 + 1e-9),
                "{}",
                s.max_change_fraction
            );
            // Independent check on the surfaces themselves, for every pairing shift.
            let (before, after) = (&history[index + 1][0], &history[index + 2][0]);
            for shift in [-10, 0, 10] {
                assert!(measured_change(before, after, shift) <= 0.1 * (1.0 + 1e-9));
            }
            assert_eq!(
                s.max_depth,
                s.joints
                    .iter()
                    .map(|j| j.max_bearing_depth.max(j.max_pin_depth))
                    .fold(0.0, f64::max)
            );
            index += 1;
        }
    }
    assert_eq!(calls.len(), index);
    assert_eq!(
        calls[0],
        RunContext {
            stage: 0,
            substep: 0,
            applied: 0.0
        }
    );
    assert_eq!(calls.last().unwrap().stage, 1);
}

#[test]
fn constant_wear_extrapolates_linearly_whatever_the_split() {
    let joint0 = joint(200);
    let fixed = |j: &WornJoint| {
        let b: Vec<f64> = (0..200)
            .map(|k| if (40..60).contains(&k) { 1e-8 } else { 0.0 })
            .collect();
        StageWear::from_depths(j, b.clone(), b).unwrap()
    };
    let mut adaptive = vec![joint0.clone()];
    let r = run_stages(&mut adaptive, &fraction_only(1), |_, js: &[WornJoint]| {
        Ok::<_, Infallible>(vec![fixed(&js[0])])
    })
    .unwrap();
    assert!(r[0].substeps.len() > 1);
    let mut jump = vec![joint0];
    let plan = StagePlan::paper(1).with_extrapolation(Extrapolation::single_jump());
    let r = run_stages(&mut jump, &plan, |_, js: &[WornJoint]| {
        Ok::<_, Infallible>(vec![fixed(&js[0])])
    })
    .unwrap();
    assert_eq!(r[0].substeps.len(), 1);
    for k in 0..200 {
        assert_relative_eq!(
            adaptive[0].bearing().depth()[k],
            jump[0].bearing().depth()[k],
            max_relative = 1e-12
        );
    }
    assert_relative_eq!(jump[0].bearing().depth()[50], 20_000.0 * 1e-8);
}

#[test]
fn single_jump_warns_only_when_too_large() {
    let plan = StagePlan::paper(1).with_extrapolation(Extrapolation::single_jump());
    let mut big = vec![joint(1000)];
    let r = run_stages(&mut big, &plan, |_, js: &[WornJoint]| {
        proportional(js, &[1e-4])
    })
    .unwrap();
    let warning = r[0].warning.expect("a ×20,000 jump of 2 c0 must warn");
    assert!(warning.change_fraction > 1.0);
    assert_eq!(warning.limit, 0.1);
    // Stages count from 1 in the text, as in the outputs.
    assert!(warning.to_string().contains("stage 1:"), "{warning}");
    let mut small = vec![joint(1000)];
    let r = run_stages(&mut small, &plan, |_, js: &[WornJoint]| {
        proportional(js, &[1e-7])
    })
    .unwrap();
    assert!(r[0].warning.is_none());
    assert!(r[0].substeps[0].max_change_fraction < 0.1);
}

#[test]
fn substep_limit_and_runner_errors_surface() {
    let plan = StagePlan::paper(1).with_extrapolation(Extrapolation::Adaptive {
        max_fraction: 0.1,
        max_substeps: 3,
        max_slope_change: f64::INFINITY,
        max_curvature_change: f64::INFINITY,
    });
    let mut js = vec![joint(1000)];
    let err = run_stages(&mut js, &plan, |_, js: &[WornJoint]| {
        proportional(js, &[1e-4])
    })
    .unwrap_err();
    assert!(
        matches!(
            err,
            StagingError::Wear(WearError::SubstepLimit {
                stage: 0,
                limit: 3,
                ..
            })
        ),
        "{err}"
    );
    // Stages are counted from 1 in messages, and the setting is named.
    let text = err.to_string();
    assert!(
        text.contains("stage 1:") && text.contains("(run.max_substeps)"),
        "{text}"
    );

    let err = run_stages(&mut js, &plan, |_, _: &[WornJoint]| {
        Err::<Vec<StageWear>, _>("integrator diverged")
    })
    .unwrap_err();
    assert_eq!(err.to_string(), "stage runner failed: integrator diverged");

    let err = run_stages(&mut js, &plan, |_, _: &[WornJoint]| {
        Ok::<_, Infallible>(Vec::new())
    })
    .unwrap_err();
    assert!(matches!(
        err,
        StagingError::Wear(WearError::JointCount {
            expected: 1,
            found: 0
        })
    ));
}

#[test]
fn shape_bounds_limit_slope_and_curvature_of_each_substep() {
    // A smooth bump (Gaussian, 8 cells wide) on both surfaces; bounds chosen so that the
    // curvature one governs.
    let bump = |k: usize| 1e-9 * (-((k as f64 - 500.0) / 8.0).powi(2)).exp();
    let wear = |j: &WornJoint| {
        let b: Vec<f64> = (0..1000).map(bump).collect();
        StageWear::from_depths(j, b.clone(), b).unwrap()
    };
    let plan = StagePlan::paper(1).with_extrapolation(Extrapolation::Adaptive {
        max_fraction: 1.0,
        max_substeps: 1000,
        max_slope_change: 0.05,
        max_curvature_change: 0.25,
    });
    let mut js = vec![joint(1000)];
    let mut before = js[0].clone();
    let mut changes = Vec::new();
    let r = run_stages(&mut js, &plan, |_, current: &[WornJoint]| {
        // Independent measure of the previous update: the change of the spline's own
        // curvature of c = R_i − R_j at the cell centres (bearing and pin cells aligned),
        // relative to c0 plus the curvature the surfaces had before it.
        let after = &current[0];
        let c0 = after.nominal_clearance();
        let angle = |k: usize| (k as f64 + 0.5) * std::f64::consts::TAU / 1000.0;
        let largest =
            |f: &dyn Fn(f64) -> f64| (0..1000).map(|k| f(angle(k)).abs()).fold(0.0, f64::max);
        let scale = c0
            + largest(&|a| before.bearing().sample(a).curvature)
            + largest(&|a| before.pin().sample(a).curvature);
        let change = largest(&|a| {
            after.bearing().sample(a).curvature
                - after.pin().sample(a).curvature
                - before.bearing().sample(a).curvature
                + before.pin().sample(a).curvature
        });
        changes.push(change / scale);
        before = after.clone();
        Ok::<_, Infallible>(vec![wear(after)])
    })
    .unwrap();
    let substeps = &r[0].substeps;
    assert!(substeps.len() > 5, "{} sub-steps", substeps.len());
    let sum: f64 = substeps.iter().map(|s| s.amplification).sum();
    assert_relative_eq!(sum, 20_000.0, max_relative = 1e-12);
    for s in substeps {
        let j = &s.joints[0];
        assert!(
            j.curvature_change <= 0.25 * (1.0 + 1e-9),
            "{}",
            j.curvature_change
        );
        assert!(j.slope_change <= 0.05 * (1.0 + 1e-9), "{}", j.slope_change);
    }
    // The measured relative curvature change of each sub-step (skip the first call: nothing
    // applied yet) equals the bound that governed it.
    for (measured, s) in changes[1..].iter().zip(substeps) {
        assert!(
            (measured - s.joints[0].curvature_change).abs() <= 1e-6 * s.joints[0].curvature_change,
            "measured {measured}, bound {}",
            s.joints[0].curvature_change
        );
    }
}

#[test]
fn geometry_limits_end_a_stage_at_the_limit() {
    // The bump of `clearance_proportional` grows the slope bound by about 1.6e-4 c0/rad per
    // unit amplification: the slope limit 0.3 is reached long before the stage's 20 000.
    let plan = fraction_only(1).with_geometry_limits(Some(GeometryLimits::new(0.3, f64::INFINITY)));
    let mut js = vec![joint(1000)];
    let reports = run_stages(&mut js, &plan, |_, current: &[WornJoint]| {
        proportional(current, &[1e-6])
    })
    .unwrap();
    let report = &reports[0];
    let applied = report.ended_at_limits.expect("ended at the limits");
    let sum: f64 = report.substeps.iter().map(|s| s.amplification).sum();
    assert_relative_eq!(applied, sum, max_relative = 1e-12);
    assert!(applied < 20_000.0, "{applied}");
    // The surfaces end at the slope limit, measured independently on the splines: the sum of
    // the two surfaces' largest slopes over c0 (cell centres; the maximum between them is
    // within a fraction of a percent for this smooth bump).
    let j = &js[0];
    let c0 = j.nominal_clearance();
    let largest = |slope: &dyn Fn(f64) -> f64| {
        (0..1000)
            .map(|k| slope((k as f64 + 0.5) * std::f64::consts::TAU / 1000.0).abs())
            .fold(0.0, f64::max)
    };
    let bound =
        (largest(&|a| j.bearing().sample(a).slope) + largest(&|a| j.pin().sample(a).slope)) / c0;
    assert!((bound - 0.3).abs() < 0.3 * 2e-3, "slope bound {bound}");
}

#[test]
fn forming_bound_refines_a_joint_until_its_groove_is_deep_then_lets_go() {
    // Joint 0 wears fast (its deeper peak passes half its clearance early in the stage),
    // joint 1 fifty times slower (it stays under 5 % of its clearance all stage).
    let rates = [1e-4, 2e-6];
    let run = |plan: &StagePlan| {
        let mut joints = vec![joint(1000), joint(500)];
        let c0: Vec<f64> = joints.iter().map(|j| j.nominal_clearance()).collect();
        let reports = run_stages(&mut joints, plan, |_, js: &[WornJoint]| {
            proportional(js, &rates)
        })
        .unwrap();
        (reports.into_iter().next().unwrap(), c0)
    };
    let plain = fraction_only(1);
    let forming = plain.with_forming_bound(Some(FormingBound::new(0.01, 0.5)));
    let (report, c0) = run(&forming);
    let (unbounded, _) = run(&plain);
    let sum: f64 = report.substeps.iter().map(|s| s.amplification).sum();
    assert_relative_eq!(sum, forming.amplification, max_relative = 1e-12);
    let peak = |j: &wear::JointSubstep| j.max_bearing_depth.max(j.max_pin_depth);
    let mut before = [0.0, 0.0];
    let (mut forming_steps, mut released) = (0, 0);
    for s in &report.substeps {
        let fast = &s.joints[0];
        if before[0] < 0.5 * c0[0] {
            forming_steps += 1;
            assert!(fast.change_fraction <= 0.01 * (1.0 + 1e-9), "{fast:?}");
        } else {
            // The slow joint still forms, but its bound is far from binding: the fast joint
            // takes the plan's own 10 %.
            assert!(before[1] < 0.5 * c0[1]);
            assert!(fast.change_fraction <= 0.1 * (1.0 + 1e-9));
            released += usize::from(fast.change_fraction > 0.099);
        }
        before = [0, 1].map(|i| peak(&s.joints[i]));
    }
    assert!(before[1] < 0.05 * c0[1], "slow joint {:e}", before[1]);
    // While the fast joint forms, its local clearance c0 + (h_b + h_p)/2 grows by about half
    // (both surfaces wear alike): ln 1.5 / ln 1.01 ≈ 41 sub-steps of 1 %, a few more because
    // the two surfaces' bumps are ten cells apart.
    assert!((40..=50).contains(&forming_steps), "{forming_steps}");
    assert!(released > 0);
    // Past the depth, about as many sub-steps as the plan alone takes from there.
    let deep = |s: &wear::SubstepReport| peak(&s.joints[0]) >= 0.5 * c0[0];
    let unbounded_after = unbounded.substeps.iter().filter(|s| deep(s)).count();
    let after = report.substeps.iter().filter(|s| deep(s)).count();
    assert!(
        after.abs_diff(unbounded_after) <= 1,
        "{after} vs {unbounded_after}"
    );
    assert!(report.substeps.len() > unbounded.substeps.len() + 15);
    let invalid = plain.with_forming_bound(Some(FormingBound::new(0.0, 0.5)));
    let err = run_stages(&mut [joint(100)], &invalid, |_, js: &[WornJoint]| {
        proportional(js, &[1e-4])
    })
    .unwrap_err();
    assert!(err.to_string().contains("forming.max_fraction"), "{err}");
}

/// Material removed from one surface, summed here from its cells: `Σ h_k/2 · R Δθ · w`.
fn layer_volume(depth: &[f64], radius: f64) -> f64 {
    let arc = radius * std::f64::consts::TAU / depth.len() as f64;
    depth.iter().map(|h| 0.5 * h * arc * WIDTH).sum()
}

#[test]
fn substeps_report_the_life_curve_of_each_joint() {
    let mut joints = vec![joint(1000), joint(400)];
    let plan = fraction_only(2);
    // The surfaces after every sub-step: the runner of sub-step n + 1 sees those of sub-step n.
    let mut seen: Vec<Vec<WornJoint>> = Vec::new();
    let reports = run_stages(&mut joints, &plan, |_, js: &[WornJoint]| {
        seen.push(js.to_vec());
        proportional(js, &[1e-4, 3e-5])
    })
    .unwrap();
    seen.push(joints.clone());
    let substeps: Vec<_> = reports.iter().flat_map(|r| &r.substeps).collect();
    assert_eq!(seen.len(), substeps.len() + 1);
    for (j, cells) in [1000, 400].into_iter().enumerate() {
        let mut previous = (0.0, CLEARANCE);
        for (n, s) in substeps.iter().enumerate() {
            let step = &s.joints[j];
            let after = &seen[n + 1][j];
            let (b, p) = (after.bearing().depth(), after.pin().depth());
            assert_eq!(b.len(), cells);
            // Worn volume: the joint's own figure, and the cells summed here.
            assert_eq!(step.worn_volume, after.worn_volume());
            assert_relative_eq!(
                step.worn_volume,
                layer_volume(b, R_BEARING) + layer_volume(p, R_PIN),
                max_relative = 1e-12
            );
            // Largest local clearance: c0 + (h_i + h_j)/2 at the two peaks of the cells.
            let peak = |d: &[f64]| d.iter().copied().fold(0.0, f64::max);
            let expected = CLEARANCE + 0.5 * (peak(b) + peak(p));
            assert_relative_eq!(step.max_local_clearance, expected, max_relative = 1e-12);
            assert_eq!(step.max_local_clearance, after.max_local_clearance());
            assert_eq!(step.max_bearing_depth, peak(b));
            assert_eq!(step.max_pin_depth, peak(p));
            // No contact direction sees a larger clearance (sampled at every cell pairing
            // around the peaks, and with the peaks aligned).
            let (pb, pp) = (after.bearing().peak(), after.pin().peak());
            for shift in -20..=20 {
                let a = pb.angle + f64::from(shift) * 1e-3;
                assert!(after.local_clearance(a, pp.angle) <= step.max_local_clearance);
            }
            // Both grow with every sub-step (wear only removes material).
            assert!(step.worn_volume > previous.0, "sub-step {n} of joint {j}");
            assert!(
                step.max_local_clearance > previous.1,
                "sub-step {n} of joint {j}"
            );
            previous = (step.worn_volume, step.max_local_clearance);
        }
    }
    // Stages go on from the surfaces the previous one left: the curve is continuous.
    let first_of_second = &reports[1].substeps[0].joints[0];
    let last_of_first = &reports[0].substeps.last().unwrap().joints[0];
    assert!(first_of_second.worn_volume > last_of_first.worn_volume);
}
