//! The wear process is stiff: a closed form for the linearly implicit sub-step.
//!
//! A pin that does not turn, pressed with a constant load on a pad of Winkler layer (the
//! bearing's layer spans the cells of a fixed arc around the bottom): the overlap on the pad is
//! `d_k = e·u_k − c − (h_k + g_k)/2` (the journal-bearing gap, `h_k`, `g_k` the bearing's and
//! the facing pin cell's depths, half of each in radius), the pin's centre `e` such that
//! `Σ d_k u_k` is the load, and both surfaces wear `w_k = λ d_k` per unit amplification (the
//! overlap closes at `λ d_k`). The wear record says so with one contact zone over the pad.
//! Write
//! `d = Πd + d⊥`, `Π` the projection onto the translation patterns `u_k = (cos θ_k, sin θ_k)`
//! on the pad: `Πd` is fixed by the load, and `d⊥`, the shape of the wear pattern relative
//! to a steady one (a ridge), decays as `exp(−λN)` over `N` units of amplification. An
//! explicit sub-step of `a` multiplies it by `1 − aλ` (unstable past `aλ = 2`), a backward
//! Euler step by `1/(1 + aλ)`.

use std::convert::Infallible;
use std::f64::consts::{FRAC_PI_2, TAU};

use wear::{
    ContactZone, Extrapolation, RunContext, StagePlan, StageWear, WearParams, WearStepping,
    WornJoint, run_stages,
};

const CELLS: usize = 720;
const R_BEARING: f64 = 0.05;
const CLEARANCE: f64 = 5e-4;
/// The pad: cells within this angle of the bottom.
const PAD: f64 = 0.12;
/// The load, as `Σ d_k u_k` (m): about 40 µm of mean overlap on the pad's cells.
const LOAD: [f64; 2] = [0.0, -1.4e-3];
/// Relaxation per unit amplification.
const LAMBDA: f64 = 1e-4;

fn angle(k: usize) -> f64 {
    (k as f64 + 0.5) * TAU / CELLS as f64
}

fn on_pad(k: usize) -> bool {
    (angle(k) - 3.0 * FRAC_PI_2).abs() < PAD
}

/// The pad's direction at cell `k`, `u_k = (cos θ_k, sin θ_k)`.
fn direction(k: usize) -> [f64; 2] {
    let (s, c) = angle(k).sin_cos();
    [c, s]
}

/// The translation `x` with `Σ_pad u_k (u_k·x) = b`: the 2×2 normal equations of a fit by
/// the translation patterns over the pad.
fn translation(b: [f64; 2]) -> [f64; 2] {
    let mut m = [[0.0; 2]; 2];
    for u in (0..CELLS).filter(|&k| on_pad(k)).map(direction) {
        for i in 0..2 {
            for j in 0..2 {
                m[i][j] += u[i] * u[j];
            }
        }
    }
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    [
        (m[1][1] * b[0] - m[0][1] * b[1]) / det,
        (m[0][0] * b[1] - m[1][0] * b[0]) / det,
    ]
}

/// `Σ_pad v_k u_k`.
fn moment(v: impl Fn(usize) -> f64) -> [f64; 2] {
    (0..CELLS)
        .filter(|&k| on_pad(k))
        .fold([0.0; 2], |[x, y], k| {
            let u = direction(k);
            [x + v(k) * u[0], y + v(k) * u[1]]
        })
}

/// `f(k)` on the pad's cells, 0 off it.
fn on_pad_only(f: impl Fn(usize) -> f64) -> Vec<f64> {
    (0..CELLS)
        .map(|k| if on_pad(k) { f(k) } else { 0.0 })
        .collect()
}

/// The pad's overlaps on `joint`'s bearing, with the pin's centre placed to carry the load.
fn overlaps(joint: &WornJoint) -> Vec<f64> {
    let (bearing, pin) = (joint.bearing().depth(), joint.pin().depth());
    let gap = |k: usize| CLEARANCE + 0.5 * (bearing[k] + pin[k]);
    // Σ (e·u_k − c − (h_k + g_k)/2) u_k = LOAD: a 2×2 linear system in e.
    let [bx, by] = moment(gap);
    let e = translation([LOAD[0] + bx, LOAD[1] + by]);
    on_pad_only(|k| {
        let u = direction(k);
        e[0] * u[0] + e[1] * u[1] - gap(k)
    })
}

/// The pad's overlaps with their translation patterns removed (0 off the pad): the shape
/// that relaxes.
fn shape(d: &[f64]) -> Vec<f64> {
    let x = translation(moment(|k| d[k]));
    on_pad_only(|k| {
        let u = direction(k);
        d[k] - x[0] * u[0] - x[1] * u[1]
    })
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// A joint whose bearing carries a ridge (less worn cells) 1/1000 of the overlap high on the
/// pad, on a groove deep enough that the ridge leaves every depth positive.
fn ridged_joint() -> WornJoint {
    let params = WearParams::new(1e-13, 0.05, CELLS).unwrap();
    let bearing: Vec<f64> = (0..CELLS)
        .map(|k| {
            let x = angle(k) - 3.0 * FRAC_PI_2 - 0.03;
            2e-5 - 8e-8 * (-(x / 0.03).powi(2)).exp()
        })
        .collect();
    let joint = WornJoint::new(&params, R_BEARING, R_BEARING - CLEARANCE).unwrap();
    WornJoint::from_profiles(
        joint.wear_coefficient(),
        joint.hinge_width(),
        wear::WornProfile::from_depths(wear::Side::Bearing, R_BEARING, bearing).unwrap(),
        joint.pin().clone(),
    )
    .unwrap()
}

/// The runner: one unit of amplification's wear on the frozen surfaces, and its contact zone.
fn pad_wear(joint: &WornJoint) -> StageWear {
    let d = overlaps(joint);
    assert!(
        (0..CELLS).filter(|&k| on_pad(k)).all(|k| d[k] > 0.0),
        "the pad stays in contact (the model is linear)"
    );
    let rate: Vec<f64> = d.iter().map(|x| LAMBDA * x).collect();
    let first = (0..CELLS).find(|&k| on_pad(k)).unwrap();
    let zone = ContactZone {
        relaxation: LAMBDA,
        pin_start: angle(first),
        pin_step: TAU / CELLS as f64,
        bearing_start: angle(first),
        bearing_step: TAU / CELLS as f64,
        nodes: (0..CELLS).filter(|&k| on_pad(k)).count() as u32,
    };
    StageWear::from_depths(joint, rate.clone(), rate)
        .unwrap()
        .with_zones([zone])
}

/// `steps` sub-steps of amplification `a` with `stepping`: the ridge's size relative to its
/// start, and the steady part's largest change relative to its size.
fn relax(stepping: WearStepping, a: f64, steps: usize) -> (f64, f64) {
    let mut joints = vec![ridged_joint()];
    let d0 = overlaps(&joints[0]);
    let ridge0 = norm(&shape(&d0));
    let steady = |d: &[f64]| -> Vec<f64> { d.iter().zip(shape(d)).map(|(x, s)| x - s).collect() };
    let steady0 = steady(&d0);
    let plan = StagePlan::new(steps, a, Extrapolation::SingleJump { warn_fraction: 1.0 })
        .with_stepping(stepping);
    run_stages(&mut joints, &plan, |_: RunContext, j: &[WornJoint]| {
        Ok::<_, Infallible>(vec![pad_wear(&j[0])])
    })
    .unwrap();
    let d = overlaps(&joints[0]);
    let moved = steady(&d)
        .iter()
        .zip(&steady0)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
        / steady0.iter().copied().fold(0.0, f64::max);
    (norm(&shape(&d)) / ridge0, moved)
}

#[test]
fn an_explicit_step_past_two_over_lambda_grows_the_ridge_and_the_implicit_one_damps_it() {
    // aλ = 3: explicit multiplies the ridge by −2 a step, backward Euler by 1/4.
    let (a, steps) = (3.0 / LAMBDA, 6);
    let (explicit, _) = relax(WearStepping::Explicit, a, steps);
    let (implicit, moved) = relax(WearStepping::LinearlyImplicit, a, steps);
    let exact = (-3.0 * steps as f64).exp();
    eprintln!(
        "aλ = 3, {steps} steps: ridge ×{explicit:.4} explicit (2^6 = 64), ×{implicit:.3e} \
         implicit (4^-6 = {:.3e}), closed form {exact:.3e}; steady part moved {moved:.1e}",
        0.25_f64.powi(6)
    );
    assert!((explicit / 64.0 - 1.0).abs() < 1e-6, "explicit {explicit}");
    assert!(
        (implicit / 0.25_f64.powi(6) - 1.0).abs() < 1e-6,
        "implicit {implicit}"
    );
    // The load-carrying (translation) part of the overlap is not relaxed away.
    assert!(moved < 1e-9, "steady part moved by {moved}");
}

#[test]
fn the_implicit_step_follows_the_closed_form_within_backward_eulers_error() {
    // aλ = 0.25 over λN = 2: backward Euler's factor (1 + aλ)^-8, whose gap to exp(−λN) is
    // at most (aλ/2)·λN times the larger of the two (first order in aλ).
    let (x, steps) = (0.25, 8);
    let (implicit, moved) = relax(WearStepping::LinearlyImplicit, x / LAMBDA, steps);
    let (explicit, _) = relax(WearStepping::Explicit, x / LAMBDA, steps);
    let exact = (-x * steps as f64).exp();
    let backward = (1.0 + x).powi(-(steps as i32));
    let bound = 0.5 * x * (x * steps as f64) * backward.max(exact);
    eprintln!(
        "aλ = {x}, λN = {}: ridge ×{implicit:.5} implicit (backward Euler {backward:.5}), \
         ×{explicit:.5} explicit ((1 − aλ)^8 = {:.5}), closed form {exact:.5}; gap {:.4} ≤ \
         bound {bound:.4}",
        x * steps as f64,
        (1.0 - x).powi(steps as i32),
        (implicit - exact).abs()
    );
    assert!((implicit / backward - 1.0).abs() < 1e-6);
    assert!((implicit - exact).abs() <= bound);
    assert!(moved < 1e-9, "steady part moved by {moved}");
}

#[test]
fn without_zones_the_implicit_step_is_the_explicit_one() {
    let joint = ridged_joint();
    let wear = pad_wear(&joint);
    let plain = StageWear::from_depths(&joint, wear.bearing().to_vec(), vec![0.0; CELLS]).unwrap();
    assert_eq!(plain.implicit(1e6), (plain, 0));
}
