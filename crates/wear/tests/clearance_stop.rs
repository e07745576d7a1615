//! Running stages to a clearance limit ([`wear::ClearanceStop`]) with synthetic runners: where
//! the stages stop, how the cycle budget cuts them, and the rescaling in `k_d` the life
//! distributions rest on (twice the wear rate reaches the same surfaces at half the
//! amplification, bit for bit).

mod common;

use common::*;
use std::convert::Infallible;
use wear::{
    ClearanceStop, Extrapolation, StagePlan, StageReport, StageWear, WornJoint, run_stages,
};

/// Wear in cells 40..60 of both surfaces, each surface's depth growing at `rate·(c0 + h/2)`
/// per unit amplification: where both surfaces are `h` deep the local clearance `c = c0 + h`
/// grows as `dc/da = rate·(c + c0)/2`, so `c + c0 = 2 c0 e^{rate·a/2}`.
fn opening(joint: &WornJoint, rate: f64) -> StageWear {
    let c0 = joint.nominal_clearance();
    let cells = joint.bearing().cells();
    let depths = |surface: &[f64]| -> Vec<f64> {
        (0..cells)
            .map(|k| {
                if (40..60).contains(&k) {
                    rate * (c0 + surface[k] / 2.0)
                } else {
                    0.0
                }
            })
            .collect()
    };
    StageWear::from_depths(
        joint,
        depths(joint.bearing().depth()),
        depths(joint.pin().depth()),
    )
    .unwrap()
}

/// Stages of 20 000, each sub-step changing a local clearance by at most 10 %, to `stop`.
fn plan(stop: ClearanceStop) -> StagePlan {
    StagePlan::paper(1)
        .with_extrapolation(Extrapolation::Adaptive {
            max_fraction: Extrapolation::DEFAULT_FRACTION,
            max_substeps: Extrapolation::DEFAULT_MAX_SUBSTEPS,
            max_slope_change: f64::INFINITY,
            max_curvature_change: f64::INFINITY,
        })
        .with_clearance_stop(Some(stop))
}

/// Runs `plan` on two joints opening at `rates`; returns the reports and the joints.
fn run(plan: &StagePlan, rates: [f64; 2]) -> (Vec<StageReport>, Vec<WornJoint>) {
    let mut joints = vec![joint(200), joint(200)];
    let reports = run_stages(&mut joints, plan, |_, js: &[WornJoint]| {
        Ok::<_, Infallible>(
            js.iter()
                .zip(rates)
                .map(|(j, rate)| opening(j, rate))
                .collect::<Vec<_>>(),
        )
    })
    .unwrap();
    (reports, joints)
}

#[test]
fn stages_go_on_until_the_last_joint_reaches_the_limit() {
    let limit = 1.5 * CLEARANCE;
    // The slower joint reaches 1.5 c0 after 2 ln 1.25 / 2e-5 ≈ 22 314 of amplification: in
    // the second stage of 20 000, although the plan names one stage.
    let (reports, joints) = run(&plan(ClearanceStop::new(limit, 1e9)), [1e-4, 2e-5]);
    assert_eq!(reports.len(), 2, "{reports:#?}");
    assert!(!reports[0].reached_clearance_limit);
    assert!(reports[1].reached_clearance_limit);
    assert!(joints.iter().all(|j| j.max_local_clearance() >= limit));
    // It stops at the first sub-step that takes the slower joint there: before it, short.
    let substeps: Vec<_> = reports.iter().flat_map(|r| &r.substeps).collect();
    let before = substeps[substeps.len() - 2];
    assert!(before.joints[1].max_local_clearance < limit, "{before:?}");
    // The first stage was whole. The explicit sub-steps grow the clearance in steps of the
    // rate at their start, which lags the exponential: the limit takes a little more
    // amplification than the exact 2 ln 1.25 / r, by about the error of the fast joint's 10 %
    // steps (and the last sub-step overshoots the limit by up to one step).
    assert_eq!(reports[0].applied(), 20_000.0);
    let applied: f64 = reports.iter().map(StageReport::applied).sum();
    let exact = 2.0 * 1.25f64.ln() / 2e-5;
    assert!(
        applied >= exact && applied < exact * 1.1,
        "{applied} against {exact}"
    );
    // Nothing follows.
    assert_eq!(
        plan(ClearanceStop::new(limit, 1e9)).next_stage(&reports),
        None
    );
}

#[test]
fn the_cycle_budget_cuts_the_last_stage() {
    // A limit out of reach: 2.5 stages' worth of amplification, then the run ends.
    let stop = ClearanceStop::new(100.0 * CLEARANCE, 50_000.0);
    let (reports, joints) = run(&plan(stop), [1e-6, 1e-6]);
    let applied: Vec<f64> = reports.iter().map(StageReport::applied).collect();
    assert_eq!(reports.len(), 3, "{applied:?}");
    assert!((applied[0] - 20_000.0).abs() < 1e-9 && (applied[1] - 20_000.0).abs() < 1e-9);
    assert!((applied[2] - 10_000.0).abs() < 1e-6, "{applied:?}");
    assert!(reports.iter().all(|r| !r.reached_clearance_limit));
    assert!(
        joints
            .iter()
            .all(|j| j.max_local_clearance() < 100.0 * CLEARANCE)
    );
}

#[test]
fn without_a_stop_the_plan_counts_its_stages() {
    let counted = StagePlan::paper(3);
    // A stage of the stop's plan to hand over as done (it applied all 20 000).
    let (done, _) = run(
        &plan(ClearanceStop::new(100.0 * CLEARANCE, 20_000.0)),
        [1e-6, 1e-6],
    );
    assert_eq!(done.len(), 1);
    // Three stages, whatever they applied; then none.
    assert_eq!(counted.next_stage(&[]), Some(counted));
    assert_eq!(counted.next_stage(&done), Some(counted));
    let three = [done[0].clone(), done[0].clone(), done[0].clone()];
    assert_eq!(counted.next_stage(&three), None);
}

#[test]
fn twice_the_wear_rate_reaches_the_same_surfaces_at_half_the_amplification() {
    // One long stage, so that no stage boundary cuts a sub-step: the sub-steps are sized by
    // the clearance change alone, each half as long at twice the rate, and every update
    // `a · w` is the same product (halving and doubling are exact in binary).
    let stop = ClearanceStop::new(1.5 * CLEARANCE, 1e9);
    let long = plan(stop).with_amplification(1e7);
    let (slow, slow_joints) = run(&long, [1e-4, 2e-5]);
    let (fast, fast_joints) = run(&long, [2e-4, 4e-5]);
    assert_eq!(slow_joints, fast_joints);
    let steps = |r: &[StageReport]| -> Vec<f64> {
        r.iter()
            .flat_map(|r| r.substeps.iter().map(|s| s.amplification))
            .collect()
    };
    let (a, b) = (steps(&slow), steps(&fast));
    assert_eq!(a.len(), b.len());
    for (a, b) in a.iter().zip(&b) {
        assert_eq!(*b, 0.5 * a);
    }
}
