//! Error-controlled extrapolation ([`Extrapolation::Controlled`]) against a closed form, with
//! and without sampling noise.

mod common;

use common::*;
use std::convert::Infallible;
use wear::{
    Extrapolation, RunContext, StagePlan, StageReport, StageWear, WearSample, WornJoint, run_stages,
};

/// Amplification of the test stage.
const STAGE: f64 = 20_000.0;
/// Peak wear rate on fresh surfaces, m per unit amplification.
const RATE: f64 = 3e-7;
/// Depth over which the rate falls (m): `w = RATE·b/(1 + h/DECAY)`, a running-in that slows
/// wear 11-fold over the stage while the peak depth reaches twice the clearance, as the
/// LGRES joints' do.
const DECAY: f64 = 100e-6;

/// The bump the wear falls on: a Gaussian 8 cells wide around cell `at`.
fn bump(k: usize, at: usize) -> f64 {
    (-((k as f64 - at as f64) / 8.0).powi(2)).exp()
}

/// The exact depth after `n` units of amplification of a cell whose fresh rate is `rate`:
/// `h + h²/(2·DECAY) = rate·n`.
fn exact(rate: f64, n: f64) -> f64 {
    DECAY * ((1.0 + 2.0 * rate * n / DECAY).sqrt() - 1.0)
}

/// The rate on the joint's current surfaces, bearing around cell 250, pin around 260.
fn running_in(joint: &WornJoint) -> StageWear {
    let rate = |depth: &[f64], at: usize| -> Vec<f64> {
        depth
            .iter()
            .enumerate()
            .map(|(k, h)| RATE * bump(k, at) / (1.0 + h / DECAY))
            .collect()
    };
    StageWear::from_depths(
        joint,
        rate(joint.bearing().depth(), 250),
        rate(joint.pin().depth(), 260),
    )
    .unwrap()
}

/// Largest difference from the closed form over both surfaces, relative to the peak depth.
fn error_against_exact(joint: &WornJoint, n: f64) -> f64 {
    let mut worst: f64 = 0.0;
    for (depth, at) in [(joint.bearing().depth(), 250), (joint.pin().depth(), 260)] {
        for (k, h) in depth.iter().enumerate() {
            worst = worst.max((h - exact(RATE * bump(k, at), n)).abs());
        }
    }
    worst / exact(RATE, n)
}

fn controlled(tolerance: f64) -> StagePlan {
    controlled_above(tolerance, 0.05)
}

/// [`controlled`] with the floor `min_fraction` (no sub-step is cut below its step).
fn controlled_above(tolerance: f64, min_fraction: f64) -> StagePlan {
    StagePlan::paper(1)
        .with_amplification(STAGE)
        .with_extrapolation(Extrapolation::Controlled {
            tolerance,
            min_fraction,
            max_fraction: 0.5,
            max_runs: 10_000,
        })
}

fn adaptive(fraction: f64) -> StagePlan {
    StagePlan::paper(1)
        .with_amplification(STAGE)
        .with_extrapolation(Extrapolation::Adaptive {
            max_fraction: fraction,
            max_substeps: 10_000,
            max_slope_change: f64::INFINITY,
            max_curvature_change: f64::INFINITY,
        })
}

/// Runs one stage of `plan` with the exact rate; the report, the runs and the error.
fn noiseless(plan: &StagePlan) -> (StageReport, usize, f64) {
    let mut js = vec![joint(1000)];
    let mut runs = 0;
    let mut reports = run_stages(&mut js, plan, |_, current: &[WornJoint]| {
        runs += 1;
        Ok::<_, Infallible>(vec![running_in(&current[0])])
    })
    .unwrap();
    (reports.remove(0), runs, error_against_exact(&js[0], STAGE))
}

#[test]
fn controlled_steps_follow_the_closed_form_with_fewer_runs_than_fixed_bounds() {
    let (fixed, fixed_runs, fixed_error) = noiseless(&adaptive(0.05));
    assert_eq!(fixed_runs, fixed.substeps.len());
    println!("adaptive 5 %: {fixed_runs} runs, error {fixed_error:.2e}");
    let mut previous = f64::INFINITY;
    for tolerance in [0.2, 0.1, 0.05] {
        let (report, runs, error) = noiseless(&controlled(tolerance));
        println!(
            "controlled {tolerance}: {} sub-steps, {runs} runs ({} rejected), error {error:.2e}",
            report.substeps.len(),
            report.rejected_runs()
        );
        // Every run is one call, and the weights spread exactly the stage's amplification.
        assert_eq!(report.run_weights.len(), runs);
        let applied: f64 = report.substeps.iter().map(|s| s.amplification).sum();
        let weights: f64 = report.run_weights.iter().sum();
        assert!((applied - STAGE).abs() <= 1e-9 * STAGE, "{applied}");
        assert!((weights - STAGE).abs() <= 1e-9 * STAGE, "{weights}");
        // Accepted sub-steps meet the tolerance, but for the running-in's first ones, which
        // the floor (the fixed bound's step) lets through.
        let over = report
            .substeps
            .iter()
            .filter(|s| s.error_estimate.expect("controlled sub-steps carry one") > tolerance)
            .count();
        assert!(over <= 2, "{over} sub-steps above the tolerance");
        for s in &report.substeps {
            assert!(s.max_change_fraction <= 0.5 * (1.0 + 1e-9));
        }
        // The step is second order, the estimate conservative: the stage's error is far
        // below the tolerance, falls with it, and beats the fixed bound's with fewer runs.
        assert!(error < tolerance / 5.0, "error {error} at {tolerance}");
        assert!(error < previous, "error {error} did not fall");
        assert!(2 * runs < fixed_runs && error < fixed_error);
        previous = error;
    }
}

/// A deterministic pseudo-random number of unit variance for (`run`, `cell`, `half`).
fn noise(run: u64, cell: u64, half: u64) -> f64 {
    let mut x = run
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(cell.wrapping_mul(0xBF58_476D_1CE4_E5B9))
        .wrapping_add(half.wrapping_mul(0x94D0_49BB_1331_11EB))
        .wrapping_add(1);
    x ^= x >> 31;
    x = x.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    x ^= x >> 29;
    let uniform = (x >> 11) as f64 / (1u64 << 53) as f64;
    (uniform - 0.5) * 12f64.sqrt()
}

/// Runs one stage of `plan` where each run's rate is the sum of two halves, each the exact
/// half rate with independent noise of relative size `sigma` per cell; the halves are
/// reported when `report_halves`. The report, the runs and the error.
fn noisy(plan: &StagePlan, sigma: f64, report_halves: bool) -> (StageReport, usize, f64) {
    let mut js = vec![joint(1000)];
    let mut runs = 0u64;
    let mut reports = run_stages(&mut js, plan, |_: RunContext, current: &[WornJoint]| {
        runs += 1;
        let exact = running_in(&current[0]);
        let half = |h: u64| {
            let perturb = |cells: &[f64], offset: u64| -> Vec<f64> {
                cells
                    .iter()
                    .enumerate()
                    .map(|(k, w)| {
                        0.5 * w * (1.0 + sigma * noise(runs, k as u64 + offset, h)).max(0.0)
                    })
                    .collect()
            };
            StageWear::from_depths(
                &current[0],
                perturb(exact.bearing(), 0),
                perturb(exact.pin(), 1 << 20),
            )
            .unwrap()
        };
        let (first, second) = (half(0), half(1));
        let mut total = first.clone();
        total.add(&second);
        Ok::<_, Infallible>(WearSample {
            wear: vec![total],
            halves: report_halves.then(|| vec![[first, second]]),
        })
    })
    .unwrap();
    (
        reports.remove(0),
        runs as usize,
        rms_against_exact(&js[0], STAGE),
    )
}

/// Root-mean-square difference from the closed form over both surfaces' cells, relative to
/// the closed form's.
fn rms_against_exact(joint: &WornJoint, n: f64) -> f64 {
    let (mut difference, mut size) = (0.0, 0.0);
    for (depth, at) in [(joint.bearing().depth(), 250), (joint.pin().depth(), 260)] {
        for (k, h) in depth.iter().enumerate() {
            let exact = exact(RATE * bump(k, at), n);
            difference += (h - exact).powi(2);
            size += exact * exact;
        }
    }
    (difference / size).sqrt()
}

#[test]
fn halves_keep_sampling_noise_out_of_the_error_estimate() {
    // Each half of a run carries 30 % noise per cell (the rate 21 %).
    let (loose, loose_runs, loose_error) = noisy(&controlled(0.05), 0.3, true);
    let (blind, blind_runs, blind_error) = noisy(&controlled(0.05), 0.3, false);
    // (The noise bound cuts no step below the floor: 0.02 needs steps below the 5 % one.)
    let (tight, tight_runs, tight_error) = noisy(&controlled_above(0.02, 0.01), 0.3, true);
    for (name, report, runs, error) in [
        ("0.05 with halves", &loose, loose_runs, loose_error),
        ("0.05 without halves", &blind, blind_runs, blind_error),
        ("0.02 with halves", &tight, tight_runs, tight_error),
    ] {
        println!(
            "{name}: {} sub-steps, {runs} runs ({} rejected), rms error {error:.4}",
            report.substeps.len(),
            report.rejected_runs()
        );
    }
    // Without halves the noise passes for error and holds the steps at the floor; with them
    // the same accuracy takes fewer runs.
    assert!(
        loose_runs * 3 < blind_runs * 2,
        "{loose_runs} against {blind_runs}"
    );
    assert!(loose_error < 1.5 * blind_error);
    // The noise bound: the stage's error is about the tolerance, and a tighter tolerance
    // buys a smaller error with more runs (noise falls as 1/√runs).
    assert!(loose_error < 0.05 && tight_error < 0.02 * 1.5);
    assert!(tight_error < loose_error && tight_runs > 2 * loose_runs);
}

#[test]
fn a_tolerance_tighter_than_the_noise_holds_the_floor() {
    // At 1e-3 the noise bound alone asks for ρ/(2·tol²) ≈ 2e4 sub-steps (ρ ≈ 0.045 here):
    // it stopped at the 1e4-run limit. It holds the floor, min_fraction's fixed step, as the
    // error estimate does: the stage then takes about the fixed bound's sub-steps.
    let (_, fixed_runs, _) = noiseless(&adaptive(0.05));
    for tolerance in [1e-3, 1e-4] {
        let (report, runs, error) = noisy(&controlled(tolerance), 0.3, true);
        println!(
            "{tolerance:e}: {} sub-steps, {runs} runs, rms error {error:.4}; fixed 0.05: \
             {fixed_runs} runs",
            report.substeps.len()
        );
        assert!(
            runs <= 2 * fixed_runs + 2,
            "{runs} runs against {fixed_runs}"
        );
    }
}

#[test]
fn the_substep_limit_names_the_amplification_left_as_a_person_reads_it() {
    let e = wear::WearError::SubstepLimit {
        stage: 0,
        limit: 400,
        remaining: 49.979_294_314_194_85,
    };
    let said = e.to_string();
    assert!(said.contains("amplification 4.9979e1 left"), "{said}");
}
