//! Interrupts at random moments: `run`, `precision`, a quick `study` (two scene
//! runs at once), `sweep` and `stress --quick` are sent SIGINT at moments spread over their
//! whole length, the writing of their files included, by a fixed sequence (every CI run sees
//! the same moments). Whatever the moment, nothing hidden may stay beside or in the output
//! folder (no lock, no staging folder, no temporary file); a staged folder (`run`, `precision`'s
//! files, `study`) is either what it was or the command's whole new output, and every file a
//! command writes in place (`sweep`, `stress`) is whole.
//! The writer threads' race with the handler is covered by `output/tests/interrupt.rs`.

#![cfg(unix)]

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

mod common;
use common::{QUICK_STUDY, listing, scratch_out};

/// Runs `wearsim args` and sends SIGINT after `delay` (unless it ended before); returns its
/// exit code and how long it ran.
fn interrupted(args: &[&str], delay: Duration) -> (Option<i32>, Duration) {
    let started = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_wearsim"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("wearsim starts");
    while started.elapsed() < delay {
        if child.try_wait().expect("waits").is_some() {
            break;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    if child.try_wait().expect("waits").is_none() {
        let _ = Command::new("kill")
            .args(["-INT", &child.id().to_string()])
            .status();
    }
    let status = child.wait().expect("waits");
    (status.code(), started.elapsed())
}

/// The fixed moments, as fractions of an uninterrupted run's length (a few past its end).
fn moments() -> Vec<f64> {
    // A low-discrepancy sequence: spread over [0, 1.15) without a random generator.
    (1..=10)
        .map(|k| (k as f64 * 0.618_034).fract() * 1.15)
        .collect()
}

/// Interrupts `args --out OUT` (`out` inside `dir`, removed first) at the fixed moments, after
/// one uninterrupted run whose folder is the "previous" output; `whole` checks a finished
/// folder. Prints how many of the moments stopped the command and how many came after it had
/// finished.
fn fuzz_interrupts(dir: &Path, out: &Path, args: &[&str], whole: &dyn Fn(&Path)) {
    let args = &[args, &["--out", out.to_str().unwrap()]].concat();
    let _ = std::fs::remove_dir_all(out);
    let (code, length) = interrupted(args, Duration::from_secs(3600));
    assert_eq!(code, Some(0), "{args:?} runs uninterrupted");
    whole(out);
    let (mut stopped, mut finished) = (0, 0);
    for fraction in moments() {
        let delay = length.mul_f64(fraction);
        let (code, _) = interrupted(args, delay);
        match code {
            Some(130) => stopped += 1,
            Some(0) => finished += 1,
            other => panic!("{args:?} at {delay:?}: exit {other:?}"),
        }
        let left: Vec<String> = listing(dir)
            .into_iter()
            .filter(|n| n.starts_with('.'))
            .collect();
        assert!(left.is_empty(), "{args:?} at {delay:?}: left {left:?}");
        // Either untouched (the previous run's whole output) or the new one, whole.
        whole(out);
    }
    eprintln!(
        "{}: {stopped} interrupted, {finished} finished first",
        args[0]
    );
}

// One test per command, so the harness runs them side by side.

#[test]
fn an_interrupted_run_leaves_nothing_behind_at_any_moment() {
    let (dir, out) = scratch_out("interrupts-run");
    let run_whole = |out: &Path| {
        let names = listing(out);
        for f in ["summary.json", "response.csv", "contact.csv", "scene.toml"] {
            assert!(names.contains(&f.to_string()), "{f} missing: {names:?}");
        }
        let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
        assert!(summary.trim_end().ends_with('}'), "summary.json cut short");
    };
    fuzz_interrupts(
        &dir,
        &out,
        &["run", "slider-crank", "--cycles", "1"],
        &run_whole,
    );
}

#[test]
fn an_interrupted_precision_sweep_leaves_nothing_behind_at_any_moment() {
    let (dir, out) = scratch_out("interrupts-precision");
    let precision_whole = |out: &Path| {
        let names = listing(out);
        assert!(names.iter().any(|n| n.ends_with(".csv")), "{names:?}");
        assert!(names.iter().all(|n| !n.starts_with('.')), "{names:?}");
    };
    fuzz_interrupts(
        &dir,
        &out,
        &[
            "precision",
            "slider-crank",
            "--methods",
            "bdf",
            "--rtols",
            "1e-4",
            "--repeats",
            "1",
            // Short: the two rtol = 1e-12 references take most of its time.
            "--duration",
            "0.002",
            "--start-up",
            "0.001",
        ],
        &precision_whole,
    );
}

#[test]
fn an_interrupted_study_leaves_nothing_behind_at_any_moment() {
    let (dir, out) = scratch_out("interrupts-study");

    // A quick study (a stage stands for 1e4 cycles) with two scene runs at once, so the
    // signal also lands while both write their folders and while the report is drawn.
    let study_whole = |out: &Path| {
        let names = listing(out);
        for f in ["report.md", "report.html", "lgres", "lgres-2stages"] {
            assert!(names.contains(&f.to_string()), "{f} missing: {names:?}");
        }
        for scene in ["lgres", "lgres-2stages"] {
            assert!(out.join(scene).join("report.html").is_file(), "{scene}");
        }
        let page = std::fs::read_to_string(out.join("report.html")).unwrap();
        assert!(page.ends_with("</html>\n"), "report.html cut short");
    };
    fuzz_interrupts(
        &dir,
        &out,
        &[&QUICK_STUDY[..], &["--jobs", "2"]].concat(),
        &study_whole,
    );
}

// `sweep` and `stress` write into their folder in place (under a lock): whatever the moment, no
// lock or temporary file stays, and every file there is whole.

#[test]
fn an_interrupted_sweep_leaves_nothing_behind_at_any_moment() {
    let (dir, out) = scratch_out("interrupts-sweep");
    let sweep_file = dir.join("s.toml");
    std::fs::write(
        &sweep_file,
        "scene = \"slider-crank\"\nsamples = 4\nseed = 1\n\
         metrics = [\"response.dissipated_per_cycle_j\"]\n[run]\ncycles = 1\n\
         [[vary]]\npath = \"clearance_joints.rod-slider.clearance\"\n\
         distribution = \"uniform\"\nlow = 3e-4\nhigh = 5e-4\n",
    )
    .unwrap();
    let sweep_whole = |out: &Path| {
        let names = listing(out);
        assert!(names.iter().all(|n| !n.starts_with('.')), "{names:?}");
        if let Ok(rows) = std::fs::read_to_string(out.join("samples.csv")) {
            let lines: Vec<&str> = rows.lines().collect();
            assert!(lines[0].starts_with("sample,"), "{rows}");
            // Fields outside quotes (an error message may hold commas; none holds a newline).
            let fields = |line: &str| {
                let mut quoted = false;
                1 + line
                    .chars()
                    .filter(|c| {
                        quoted ^= *c == '"';
                        *c == ',' && !quoted
                    })
                    .count()
            };
            let columns = fields(lines[0]);
            assert!(lines.iter().all(|l| fields(l) == columns), "{rows}");
            assert!(rows.ends_with('\n'), "samples.csv cut short");
        }
        if names.contains(&"samples.html".to_string()) {
            let page = std::fs::read_to_string(out.join("samples.html")).unwrap();
            assert!(page.ends_with("</html>\n"), "samples.html cut short");
        }
    };
    fuzz_interrupts(
        &dir,
        &out,
        &["sweep", sweep_file.to_str().unwrap(), "--jobs", "2"],
        &sweep_whole,
    );
}

#[test]
fn an_interrupted_stress_battery_leaves_nothing_behind_at_any_moment() {
    let (dir, out) = scratch_out("interrupts-stress");
    let stress_whole = |out: &Path| {
        let names = listing(out);
        assert!(names.iter().all(|n| !n.starts_with('.')), "{names:?}");
        if let Ok(json) = std::fs::read_to_string(out.join("stress.json")) {
            serde_json::from_str::<serde_json::Value>(&json).expect("stress.json whole");
        }
    };
    fuzz_interrupts(&dir, &out, &["stress", "--quick"], &stress_whole);
}

/// A sweep re-run into a finished sweep's folder and interrupted leaves no
/// page or figure of the earlier rows beside its own, and says what the folder holds.
#[test]
fn an_interrupted_sweep_rerun_leaves_no_page_of_other_rows() {
    let (dir, out) = scratch_out("sweep-rerun");
    let file = dir.join("s.toml");
    std::fs::write(
        &file,
        "scene = \"lgres\"\nmetrics = [\"response.joints.A.max_penetration_m\"]\n\
         [run]\ncycles = 1\nstages = 0\n[[vary]]\npath = \"clearance_joints.A.clearance\"\n\
         values = [4e-4, 4.5e-4, 5e-4, 5.5e-4, 6e-4, 6.5e-4, 7e-4, 7.5e-4]\n",
    )
    .unwrap();
    let args = [
        "sweep",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--jobs",
        "1",
    ];
    let (code, length) = interrupted(&args, Duration::from_secs(3600));
    assert_eq!(code, Some(0));
    assert!(out.join("samples.html").is_file() && out.join("scatter.png").is_file());
    // Again, interrupted a fifth of the way in (its samples run one after the other).
    let child = Command::new(env!("CARGO_BIN_EXE_wearsim"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(length / 5);
    let _ = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status();
    let o = child.wait_with_output().unwrap();
    let names = listing(&out);
    match o.status.code() {
        Some(0) => assert!(names.contains(&"samples.html".to_string()), "{names:?}"),
        Some(130) => {
            assert_eq!(names, ["samples.csv"], "only the new rows");
            let said = String::from_utf8_lossy(&o.stderr);
            assert!(said.contains("holds the files written before"), "{said}");
        }
        other => panic!("exit {other:?}"),
    }
    assert_eq!(listing(&dir), ["out", "s.toml"]);
}
