//! A run to the clearance limit on the worn slider-crank: where the stages stop, the B lives
//! under the wear coefficient's scatter, and the rescaling they rest on, through the whole
//! run (twice `k_d` reaches the limit at half the cycles).

use scene::ValidScene;
use sim::{RunOptions, WearSummary, run_scene};

/// The slider-crank's joint wearing at `k_d` with a scatter of 0.4 in `ln k_d`, run until
/// its largest local clearance reaches 0.6 mm (from 0.5) in sub-steps of at most 2 %, stages
/// of 2e5 cycles, at most `max_cycles`.
fn scene(k_d: f64, max_cycles: f64) -> ValidScene {
    let text = format!(
        r#"
extends = "slider-crank"
[[clearance_joints]]
name = "rod-slider"
wear = {{ k_d = {k_d:e}, width = 0.02, cells = 360, k_d_scatter = 0.4 }}
[run]
cycles = 1
wear_stages = 1
cycles_per_stage = 2
amplification = 1e5
animation = false
clearance_limit = 0.0006
max_clearance_change = 0.02
until_limit = true
max_cycles = {max_cycles:e}
"#
    );
    scene::load_str(&text, "life", lgres::scenes::BUILTINS).unwrap()
}

fn wear(scene: &ValidScene) -> WearSummary {
    let outcome = run_scene("life", scene, &RunOptions::default(), &mut ()).unwrap();
    outcome.summary.wear.unwrap()
}

/// Φ⁻¹(0.1), a published constant.
const Z10: f64 = -1.281_551_565_544_600_5;

#[test]
fn a_run_stops_at_the_limit_and_twice_k_d_gets_there_in_half_the_cycles() {
    let base = wear(&scene(1.8e-13, 2e5));
    let joint = &base.joints[0];
    let limit = joint.clearance_limit.as_ref().unwrap();
    let cycles = limit.cycles.expect("the limit is reached");
    eprintln!(
        "0.6 mm after {cycles:.4e} cycles in {} sub-steps",
        base.substeps_per_stage[0]
    );
    // The stages stopped at the sub-step that reached it, inside the first stage.
    assert_eq!(base.stages, 1);
    assert!(cycles <= base.cycles_applied && base.cycles_applied < 2e5);
    assert!(joint.max_local_clearance_m >= 0.0006);
    assert!(base.substeps_per_stage[0] >= 5);
    let life = base.life.as_ref().unwrap();
    assert!(life.until_limit && life.ended.starts_with("every wearing joint reached"));
    // B50 is the simulated life, B10 exp(0.4 Φ⁻¹(0.1)) of it; their noise scales alike.
    // (Each B life is a bisection of the distribution to a relative 1e-13.)
    assert!((limit.b50_cycles.unwrap() / cycles - 1.0).abs() < 1e-12);
    let ratio = limit.b10_cycles.unwrap() / cycles;
    assert!((ratio - (0.4 * Z10).exp()).abs() < 1e-12, "{ratio}");
    let noise = limit.cycles_noise.expect("measured");
    assert!((limit.b10_noise.unwrap() / noise - ratio).abs() < 1e-6);
    // One wearing joint: the mechanism's life is the joint's.
    let m = life.mechanism.unwrap();
    assert!((m.b10_cycles / limit.b10_cycles.unwrap() - 1.0).abs() < 1e-12);
    // Twice the wear coefficient: the same surfaces at half the cycles (sub-steps are sized
    // by the clearance change, each half as long; no stage boundary falls before the limit).
    let fast = wear(&scene(3.6e-13, 2e5));
    let fast_cycles = fast.joints[0]
        .clearance_limit
        .as_ref()
        .unwrap()
        .cycles
        .unwrap();
    assert_eq!(fast.substeps_per_stage, base.substeps_per_stage);
    assert!(
        (fast_cycles / cycles - 0.5).abs() < 1e-12,
        "{fast_cycles} against {cycles}"
    );
    assert_eq!(
        fast.joints[0].bearing_peak_depth_m,
        joint.bearing_peak_depth_m
    );
}

#[test]
fn a_budget_that_ends_first_says_so_and_gives_no_life() {
    // A fraction of the cycles the limit takes: the run ends at the budget, short of it.
    let short = wear(&scene(1.8e-13, 1e3));
    assert!(
        (short.cycles_applied - 1e3).abs() < 1e-6,
        "{}",
        short.cycles_applied
    );
    let limit = short.joints[0].clearance_limit.as_ref().unwrap();
    assert_eq!((limit.cycles, limit.b10_cycles), (None, None));
    let life = short.life.as_ref().unwrap();
    assert!(
        life.ended.starts_with("run.max_cycles = 1.000e3 was spent")
            && life.ended.ends_with("before rod-slider reached the limit"),
        "{}",
        life.ended
    );
    assert!(life.mechanism.is_none());
}
