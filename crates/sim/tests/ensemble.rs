//! A wear sub-step's cycles spread over trajectories on threads (`run.trajectories`): the
//! same surfaces whatever the thread count, and refused when they do not divide `K`.

use sim::{RunError, RunOptions, RunOutcome, run_scene};

/// The worn slider-crank, one stage in two sub-steps or more, `K = 2` on `trajectories`.
fn scene(trajectories: u32) -> Result<scene::ValidScene, scene::SceneError> {
    scene_with(trajectories, "")
}

/// [`scene`] with more `[run]` settings.
fn scene_with(trajectories: u32, extra: &str) -> Result<scene::ValidScene, scene::SceneError> {
    let text = format!(
        r#"
extends = "slider-crank"
[[clearance_joints]]
name = "rod-slider"
wear = {{ k_d = 1.8e-13, width = 0.02, cells = 360 }}
[run]
cycles = 1
wear_stages = 1
cycles_per_stage = 2
trajectories = {trajectories}
amplification = 4000.0
animation = false
{extra}
"#
    );
    scene::load_str(&text, "ensemble", lgres::scenes::BUILTINS)
}

/// `scene` run on `threads` threads, and its surfaces after every stage, per wearing joint.
fn on_threads(
    scene: &scene::ValidScene,
    threads: usize,
) -> Result<(RunOutcome, Vec<Vec<wear::WornJoint>>), RunError> {
    let options = RunOptions {
        threads: Some(threads),
        ..RunOptions::default()
    };
    let outcome = run_scene("ensemble", scene, &options, &mut ())?;
    let surfaces = outcome.wear.iter().map(|h| h.stages.clone()).collect();
    Ok((outcome, surfaces))
}

type TestResult<T = ()> = Result<T, Box<dyn std::error::Error>>;

/// `scene` run on 1 and on 2 threads, `check` called with the thread count, the outcome and
/// its wear summary after each; fails unless both runs leave the same surfaces, bit for bit.
/// Returns those surfaces.
fn on_one_and_two_threads(
    scene: &scene::ValidScene,
    mut check: impl FnMut(usize, &RunOutcome, &sim::WearSummary) -> TestResult,
) -> TestResult<Vec<Vec<wear::WornJoint>>> {
    let mut worn = Vec::new();
    for threads in [1, 2] {
        let (outcome, surfaces) = on_threads(scene, threads)?;
        let wear = outcome.summary.wear.as_ref().ok_or("stages ran")?;
        check(threads, &outcome, wear)?;
        worn.push(surfaces);
    }
    assert!(
        worn[0] == worn[1],
        "1 and 2 threads gave different surfaces"
    );
    Ok(worn.swap_remove(1))
}

#[test]
fn the_threads_change_no_bit_of_the_worn_surfaces() -> TestResult {
    on_one_and_two_threads(&scene(2)?, |threads, _, wear| {
        assert_eq!(wear.trajectories, 2);
        // Sub-steps after the first continue the trajectories.
        assert!(wear.substeps_per_stage[0] >= 2);
        // Two trajectories are the two halves of the convergence check.
        assert!(wear.stage_halves[0].is_some());
        eprintln!(
            "{threads} thread(s): {} sub-steps, peak bearing depth {:.6e} m",
            wear.substeps_per_stage[0], wear.joints[0].bearing_peak_depth_m
        );
        assert!(wear.joints[0].bearing_peak_depth_m > 0.0);
        Ok(())
    })?;
    Ok(())
}

/// The phases a run began (the response, the stages' runs).
struct Phases(Vec<String>);

impl sim::Progress for Phases {
    fn phase(&mut self, label: &str, _cycles: f64) {
        self.0.push(label.to_string());
    }
}

#[test]
fn trajectories_must_divide_the_cycles_of_a_sub_step() -> TestResult {
    // The scene's K = 2 on 3 trajectories; K overridden to 3 on the scene's 2; the flags'
    // 2 trajectories with K = 3.
    let cases = [
        (scene(3)?, RunOptions::default()),
        (
            scene(2)?,
            RunOptions {
                cycles_per_stage: Some(3),
                ..RunOptions::default()
            },
        ),
        (
            scene(1)?,
            sim::overrides::RunOverrides {
                cycles_per_stage: Some(3),
                trajectories: Some(2),
                ..Default::default()
            }
            .run_options(),
        ),
    ];
    for (scene, options) in cases {
        let mut phases = Phases(Vec::new());
        match run_scene("ensemble", &scene, &options, &mut phases) {
            Err(e @ RunError::Trajectories { .. }) => {
                assert!(e.is_bad_input());
                let text = e.to_string();
                assert!(
                    text.contains("run.trajectories") && text.contains("must divide"),
                    "{text}"
                );
                // Refused before any simulation began.
                assert!(phases.0.is_empty(), "{text}; phases begun: {:?}", phases.0);
            }
            Err(other) => {
                return Err(format!("expected RunError::Trajectories, got {other}").into());
            }
            Ok(_) => return Err("trajectories that do not divide K ran".into()),
        }
    }
    // The quick default (K = 2 on 2 trajectories) whatever the scene's own K.
    let options = sim::overrides::RunOverrides::default().run_options();
    assert_eq!(
        (options.cycles_per_stage, options.trajectories),
        (Some(2), Some(2))
    );
    Ok(())
}

/// Error-controlled sub-steps (`run.wear_tolerance`) on the ensemble: the summary counts the
/// runs (the first rate, one per sub-step, the rejected predictions), gives each sub-step's
/// estimate and the halves of the run it applied, and the threads change no bit.
#[test]
fn controlled_sub_steps_are_reported_and_thread_independent() -> TestResult {
    let scene = scene_with(2, "wear_tolerance = 0.05\nmax_clearance_change = 0.02")?;
    on_one_and_two_threads(&scene, |threads, _, wear| {
        let (substeps, runs) = (wear.substeps_per_stage[0], wear.runs_per_stage[0]);
        eprintln!(
            "{threads} thread(s): {substeps} sub-steps, {runs} runs ({} rejected): {}",
            wear.rejected_runs_per_stage[0], wear.extrapolation
        );
        assert!(wear.extrapolation.starts_with("controlled (tolerance 5 %"));
        assert_eq!(runs, substeps + 1 + wear.rejected_runs_per_stage[0]);
        assert!(substeps >= 2);
        for s in &wear.substeps {
            assert!(
                s.error_estimate.is_some() && s.halves_difference.is_some(),
                "{s:?}"
            );
        }
        let applied: f64 = wear.substeps.iter().map(|s| s.amplification).sum();
        assert!((applied - wear.amplification).abs() <= 1e-9 * wear.amplification);
        Ok(())
    })?;
    Ok(())
}

/// Linearly implicit sub-steps (`run.wear_stepping`): the summary says so, each sub-step
/// reports how stiff it was, the step changes the surfaces (against explicit sub-steps of the
/// same scene), and the threads change no bit.
#[test]
fn implicit_sub_steps_are_reported_and_thread_independent() -> TestResult {
    let scene = scene_with(2, "wear_stepping = \"linearly-implicit\"")?;
    let worn = on_one_and_two_threads(&scene, |threads, outcome, wear| {
        eprintln!("{threads} thread(s): {}", wear.extrapolation);
        assert!(
            wear.extrapolation.ends_with(
                "linearly implicit (the wear's stiffness taken from the cycles' contact zones)"
            ),
            "{}",
            wear.extrapolation
        );
        let life = &outcome.wear[0].life;
        assert!(life.len() >= 3, "{life:?}");
        assert!(life[1..].iter().all(|p| p.wear_stiffness > 0.0), "{life:?}");
        Ok(())
    })?;
    let (_, explicit) = on_threads(&scene_with(2, "")?, 2)?;
    assert!(explicit != worn, "the implicit step changed nothing");
    Ok(())
}

/// Finer sub-steps while a groove forms (`run.forming_clearance_change`): every sub-step of a
/// joint still shallower than `forming_depth` keeps to the finer bound, the summary says so
/// and notes that the noise is not calibrated, and the threads change no bit.
#[test]
fn forming_sub_steps_keep_the_finer_bound_and_are_thread_independent() -> TestResult {
    // The stage's 8000 cycles leave the groove far shallower than the clearance: all forming.
    let scene = scene_with(2, "forming_clearance_change = 0.01\nforming_depth = 1.0")?;
    let mut counts = Vec::new();
    on_one_and_two_threads(&scene, |threads, _, wear| {
        eprintln!("{threads} thread(s): {}", wear.extrapolation);
        assert!(
            wear.extrapolation.contains(
                "at most 1 % while a joint's deeper peak is under 100 % of its clearance"
            ),
            "{}",
            wear.extrapolation
        );
        assert!(
            wear.warnings
                .iter()
                .any(|w| w.contains("run.forming_clearance_change the printed noise is not")),
            "{:?}",
            wear.warnings
        );
        for s in &wear.substeps {
            assert!(s.change_fraction <= 0.01 * (1.0 + 1e-9), "{s:?}");
        }
        counts.push(wear.substeps_per_stage[0]);
        Ok(())
    })?;
    let (plain, _) = on_threads(&scene_with(2, "")?, 2)?;
    let plain = plain.summary.wear.as_ref().ok_or("stages ran")?;
    assert!(
        plain.substeps.iter().any(|s| s.change_fraction > 0.011),
        "the plain bound never took more than the forming one: the test shows nothing"
    );
    assert!(counts[0] > plain.substeps_per_stage[0]);
    Ok(())
}
