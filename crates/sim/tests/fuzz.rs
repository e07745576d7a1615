//! Scene fuzzing: mutants of the shipped `lgres` and `slider-crank` scenes —
//! numbers scaled by 1e±3/1e±6, signs flipped, set to 0/NaN/±inf, integers set to edge values,
//! keys deleted, array elements duplicated, names swapped — are parsed, validated and checked
//! like `wearsim check`; every one that passes validation is also briefly run like `wearsim run`. No
//! mutant may panic or outlast its budget, and `check` and `run` must agree on bad input: a
//! scene `check` passes may fail to run (a run failure) but never as bad input, and one that
//! `check` rejects is rejected by `run` too. The seed is fixed, so every CI run sees the same
//! mutants. Run with `--nocapture` to see the counts.

use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

use scene::{Scene, load_str};
use sim::{RunOptions, check_assembly, run_scene};

/// One step of a path into a TOML value.
#[derive(Debug, Clone)]
enum Seg {
    Key(String),
    Index(usize),
}

type Path = Vec<Seg>;

/// Every path below `v`, with the value it leads to.
fn walk<'a>(v: &'a toml::Value, at: &Path, out: &mut Vec<(Path, &'a toml::Value)>) {
    match v {
        toml::Value::Table(t) => {
            for (k, child) in t {
                let mut p = at.clone();
                p.push(Seg::Key(k.clone()));
                out.push((p.clone(), child));
                walk(child, &p, out);
            }
        }
        toml::Value::Array(a) => {
            for (i, child) in a.iter().enumerate() {
                let mut p = at.clone();
                p.push(Seg::Index(i));
                out.push((p.clone(), child));
                walk(child, &p, out);
            }
        }
        _ => {}
    }
}

fn get_mut<'a>(v: &'a mut toml::Value, path: &[Seg]) -> Option<&'a mut toml::Value> {
    path.iter().try_fold(v, |v, seg| match seg {
        Seg::Key(k) => v.as_table_mut()?.get_mut(k),
        Seg::Index(i) => v.as_array_mut()?.get_mut(*i),
    })
}

/// A mutation: what to do, which candidate (modulo their count), a parameter.
#[derive(Debug, Clone, Copy)]
struct Mutation {
    kind: u8,
    pick: usize,
    param: u8,
}

fn mutate(scene: &mut toml::Value, m: Mutation) {
    let mut all = Vec::new();
    walk(scene, &Vec::new(), &mut all);
    let pick = |filter: &dyn Fn(&toml::Value, &Path) -> bool| -> Option<Path> {
        let candidates: Vec<&Path> = all
            .iter()
            .filter(|(p, v)| filter(v, p))
            .map(|(p, _)| p)
            .collect();
        (!candidates.is_empty()).then(|| candidates[m.pick % candidates.len()].clone())
    };
    let number = |v: &toml::Value, _: &Path| v.is_float() || v.is_integer();
    let as_f64 = |v: &toml::Value| v.as_float().or(v.as_integer().map(|i| i as f64));
    match m.kind % 7 {
        // Scale by 1e-6, 1e-3, 1e3 or 1e6.
        0 => {
            if let Some(p) = pick(&number)
                && let Some(v) = get_mut(scene, &p)
            {
                let factor = [1e-6, 1e-3, 1e3, 1e6][usize::from(m.param % 4)];
                *v = toml::Value::Float(as_f64(v).unwrap_or(1.0) * factor);
            }
        }
        // Flip the sign.
        1 => {
            if let Some(p) = pick(&number)
                && let Some(v) = get_mut(scene, &p)
            {
                let flipped = match &*v {
                    toml::Value::Integer(i) => toml::Value::Integer(-*i),
                    other => toml::Value::Float(-as_f64(other).unwrap_or(1.0)),
                };
                *v = flipped;
            }
        }
        // Zero, NaN, ±inf.
        2 => {
            if let Some(p) = pick(&number)
                && let Some(v) = get_mut(scene, &p)
            {
                let x = [0.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY][usize::from(m.param % 4)];
                *v = toml::Value::Float(x);
            }
        }
        // Delete a key.
        3 => {
            if let Some(p) = pick(&|_, p: &Path| matches!(p.last(), Some(Seg::Key(_))))
                && let Some((Seg::Key(k), parent)) = p.split_last()
                && let Some(t) = get_mut(scene, parent).and_then(toml::Value::as_table_mut)
            {
                t.remove(k);
            }
        }
        // Duplicate an element of an array of tables.
        4 => {
            if let Some(p) =
                pick(&|v, p: &Path| v.is_table() && matches!(p.last(), Some(Seg::Index(_))))
                && let Some((Seg::Index(i), parent)) = p.split_last()
                && let Some(a) = get_mut(scene, parent).and_then(toml::Value::as_array_mut)
            {
                let copy = a[*i].clone();
                a.push(copy);
            }
        }
        // Swap two names.
        5 => {
            let is_name = |_: &toml::Value, p: &Path| matches!(p.last(), Some(Seg::Key(k)) if k == "name" || k == "body" || k == "other" || k == "pin_body" || k == "bearing_body");
            let names: Vec<Path> = all
                .iter()
                .filter(|(p, v)| is_name(v, p))
                .map(|(p, _)| p.clone())
                .collect();
            if names.len() >= 2 {
                let a = &names[m.pick % names.len()];
                let b = &names[(m.pick / 7 + usize::from(m.param) + 1) % names.len()];
                let va = get_mut(scene, a).cloned();
                let vb = get_mut(scene, b).cloned();
                if let (Some(va), Some(vb)) = (va, vb) {
                    if let Some(x) = get_mut(scene, a) {
                        *x = vb;
                    }
                    if let Some(x) = get_mut(scene, b) {
                        *x = va;
                    }
                }
            }
        }
        // Integer edge values (counts: cycles, stages, cells).
        _ => {
            if let Some(p) = pick(&|v: &toml::Value, _: &Path| v.is_integer())
                && let Some(v) = get_mut(scene, &p)
            {
                let x = [0, -1, i64::from(u32::MAX) + 1, 10_000_000][usize::from(m.param % 4)];
                *v = toml::Value::Integer(x);
            }
        }
    }
}

/// What the mutants did.
#[derive(Debug, Default)]
struct Counts {
    cases: usize,
    rejected_by_validation: usize,
    rejected_by_check: usize,
    checked_ok: usize,
    run: usize,
    run_ok: usize,
    run_failed: usize,
}

/// Simulated time of a brief run, s, and its per-simulation budgets.
const BRIEF_RUN: f64 = 0.05;
const BRIEF_STEPS: usize = 20_000;
const BRIEF_WALL_S: f64 = 5.0;

fn fuzz(base: &str, cases: u32, seed: u8) -> Counts {
    let text = lgres::scenes::source(base).unwrap();
    let original: toml::Value = toml::from_str(text).unwrap();
    let config = Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    };
    let mut runner = TestRunner::new_with_rng(
        config,
        TestRng::from_seed(RngAlgorithm::ChaCha, &[seed; 32]),
    );
    let mutation = (any::<u8>(), any::<usize>(), any::<u8>())
        .prop_map(|(kind, pick, param)| Mutation { kind, pick, param });
    let strategy = prop::collection::vec(mutation, 1..4);
    let counts = std::cell::RefCell::new(Counts::default());
    let result = runner.run(&strategy, |mutations| {
        let mut scene = original.clone();
        for m in &mutations {
            mutate(&mut scene, *m);
        }
        let mut c = counts.borrow_mut();
        c.cases += 1;
        let Ok(text) = toml::to_string(&scene) else {
            c.rejected_by_validation += 1;
            return Ok(());
        };
        // Brief: one short cycle, no wear stages, coarse output, small budgets.
        let brief = |scene: &mut Scene| {
            scene.run.cycles = 1;
            scene.run.wear_stages = 0;
            scene.run.period = Some(scene.cycle_period().unwrap_or(1.0).min(BRIEF_RUN));
            scene.run.transient_window = scene.run.transient_window.min(BRIEF_RUN / 2.0);
            let interval = scene.solver.output_interval;
            scene.solver.output_interval = interval.max(BRIEF_RUN / 100.0);
            scene.solver.max_steps = Some(BRIEF_STEPS);
            scene.solver.max_wall_time = Some(BRIEF_WALL_S);
        };
        let loaded = load_str(&text, "mutant", lgres::scenes::BUILTINS)
            .and_then(|scene| scene.edit("brief mutant", brief));
        let Ok(scene) = loaded else {
            c.rejected_by_validation += 1;
            return Ok(());
        };
        let checked = check_assembly("t", &scene, &RunOptions::default());
        match &checked {
            Ok(_) => c.checked_ok += 1,
            Err(e) => {
                prop_assert!(e.is_bad_input(), "check failed but not as bad input: {e}");
                c.rejected_by_check += 1;
            }
        }
        c.run += 1;
        let options = RunOptions {
            skip_worn_response: true,
            ..RunOptions::default()
        };
        match (run_scene("mutant", &scene, &options, &mut ()), &checked) {
            (Ok(_), Ok(_)) => c.run_ok += 1,
            (Ok(_), Err(e)) => prop_assert!(false, "check rejected ({e}) but run succeeded"),
            (Err(e), Ok(_)) => {
                prop_assert!(
                    !e.is_bad_input(),
                    "check passed but run says bad input: {e}"
                );
                c.run_failed += 1;
            }
            (Err(e), Err(_)) => {
                prop_assert!(
                    e.is_bad_input(),
                    "check rejected, run failed otherwise: {e}"
                );
            }
        }
        Ok(())
    });
    if let Err(e) = result {
        panic!("{base}: {e}");
    }
    let counts = counts.into_inner();
    eprintln!("{base}: {counts:?}");
    counts
}

#[test]
fn fuzzed_lgres_scenes_never_panic_hang_or_disagree() {
    let c = fuzz("lgres", 4000, 13);
    assert!(c.checked_ok > 100 && c.run > 100, "{c:?}");
}

#[test]
fn fuzzed_slider_crank_scenes_never_panic_hang_or_disagree() {
    let c = fuzz("slider-crank", 4000, 31);
    assert!(c.checked_ok > 100 && c.run > 100, "{c:?}");
}
