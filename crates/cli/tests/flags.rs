//! Every `wearsim` command's flags, fuzzed: refused at once, by name, with nothing written.

use std::process::{Command, Output};

mod common;
use common::{assert_case_exit, listing, scratch, stderr};

/// Every command's flags, fuzzed: for `run`, `check`, `study`, `precision`, `stress`, `sweep`
/// and `scenes`, every global flag (and `study --stage-cycles`) with bad values (zero, negative, fractional, NaN, ±inf,
/// 1e300, overflowing, garbage; bad folders) and with good values where the command does not
/// use the flag must be refused at once: exit 2 within seconds (no run started and ignored,
/// which is how `stress --rtol nan` or `study --max-wall-time nan` ran for minutes), the flag
/// or the scene field it sets named, and nothing written or left behind.
#[test]
fn fuzzed_flags_of_every_command_are_refused_at_once_by_name() {
    let dir = scratch("flags");
    let file = dir.join("a-file");
    std::fs::write(&file, "x").unwrap();
    let sweep_file = dir.join("s.toml");
    std::fs::write(
        &sweep_file,
        "scene = \"slider-crank\"\nsamples = 2\nseed = 1\nmetrics = [\"response.dissipated_per_cycle_j\"]\n\
         [[vary]]\npath = \"clearance_joints.rod-slider.clearance\"\n\
         distribution = \"uniform\"\nlow = 2e-4\nhigh = 5e-4\n",
    )
    .unwrap();
    let out = dir.join("out");
    let through = format!("{}/a/../b", dir.display());
    let bad: &[(&str, &[&str], &[&str])] = &[
        // (`study` names its own options without dashes: `cycles = 0`.)
        (
            "--cycles",
            &["0", "-1", "1.5", "abc", "99999999999", "nan"],
            &["run.cycles", "cycles = 0"],
        ),
        (
            "--stages",
            &["-1", "1.5", "abc", "99999999999"],
            &["run.wear_stages"],
        ),
        (
            "--rtol",
            &["0", "-1", "nan", "inf", "1", "abc", "1e300"],
            &["solver.rtol"],
        ),
        (
            "--cycles-per-stage",
            &["0", "-1", "1.5", "abc"],
            &["run.cycles_per_stage", "cycles-per-stage"],
        ),
        (
            "--trajectories",
            &["0", "-1", "1.5", "abc", "65", "99999999999"],
            &["run.trajectories"],
        ),
        (
            "--wear-tolerance",
            &["0", "-1", "nan", "inf", "1.5", "abc"],
            &["run.wear_tolerance"],
        ),
        (
            "--max-steps",
            &["0", "-1", "abc", "1e3"],
            &["solver.max_steps"],
        ),
        (
            "--max-wall-time",
            &["0", "-1", "nan", "inf", "abc"],
            &["solver.max_wall_time"],
        ),
        ("--jobs", &["0", "-1", "abc"], &[]),
        ("--surfaces", &["/nonexistent", file.to_str().unwrap()], &[]),
        (
            "--out",
            &[file.to_str().unwrap(), "/", &through, "/proc/wearsim-fuzz"],
            &["output folder"],
        ),
    ];
    let commands: &[&[&str]] = &[
        &["run", "lgres-ideal"],
        &["check", "lgres"],
        &["study", "clearance"],
        &["precision"],
        &["stress", "--quick"],
        &["sweep", sweep_file.to_str().unwrap()],
        &["scenes"],
    ];
    let (mut refused, mut cases) = (0, 0);
    for command in commands {
        for (flag, values, fields) in bad {
            for value in *values {
                let mut args: Vec<&str> = command.to_vec();
                args.extend([*flag, *value]);
                // Commands that write get an output folder (which must stay unwritten).
                if *flag != "--out" && !["check", "scenes"].contains(&command[0]) {
                    args.extend(["--out", out.to_str().unwrap()]);
                }
                cases += 1;
                let o = wearsim_within(&args, std::time::Duration::from_secs(30));
                let e = stderr(&o);
                assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
                let named = e.contains(flag) || fields.iter().any(|f| e.contains(f));
                assert!(named, "{args:?} does not name {flag}: {e}");
                assert!(!out.exists(), "{args:?} wrote {}", out.display());
                refused += 1;
            }
        }
    }
    // A command's own flags: `study --stage-cycles` (a quick study's stage length).
    for value in ["0", "-1", "0.5", "nan", "inf", "-inf", "1e400", "abc"] {
        let args = [
            "study",
            "clearance",
            "--stage-cycles",
            value,
            "--out",
            out.to_str().unwrap(),
        ];
        cases += 1;
        let o = wearsim_within(&args, std::time::Duration::from_secs(30));
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
        assert!(
            e.contains("stage-cycles"),
            "{args:?} does not name the flag: {e}"
        );
        assert!(!out.exists(), "{args:?} wrote {}", out.display());
        refused += 1;
    }
    // Good values of flags a command does not use: refused too, not silently ignored.
    for (command, flag, value) in [
        (&["stress", "--quick"][..], "--rtol", "1e-6"),
        (&["stress", "--quick"][..], "--cycles", "2"),
        (&["study", "clearance"][..], "--max-wall-time", "100"),
        (&["study", "clearance"][..], "--surfaces", "out/lgres"),
        (&["precision"][..], "--surfaces", "out/lgres"),
        (&["precision"][..], "--jobs", "2"),
        (&["study", "clearance"][..], "--trajectories", "2"),
        (&["study", "clearance"][..], "--wear-tolerance", "0.05"),
        (&["check", "lgres"][..], "--jobs", "2"),
        (&["check", "lgres"][..], "--out", "x"),
        (
            &["sweep", sweep_file.to_str().unwrap()][..],
            "--rtol",
            "1e-6",
        ),
    ] {
        let mut args = command.to_vec();
        args.extend([flag, value]);
        cases += 1;
        let o = wearsim_within(&args, std::time::Duration::from_secs(30));
        assert_case_exit(
            &format!("{args:?}"),
            &o,
            2,
            &format!("{flag} does not apply"),
        );
        refused += 1;
    }
    eprintln!("flag fuzz: {refused} of {cases} cases refused at once by name");
    assert_eq!(listing(&dir), ["a-file", "s.toml"], "nothing left behind");
}

/// `wearsim args`, killed (and the test failed) if it runs longer than `limit`: a refusal
/// must come before any simulation.
fn wearsim_within(args: &[&str], limit: std::time::Duration) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_wearsim"))
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("wearsim starts");
    let started = std::time::Instant::now();
    while child.try_wait().expect("waits").is_none() {
        if started.elapsed() > limit {
            let _ = child.kill();
            panic!("{args:?} still running after {limit:?}: work started despite a bad flag");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.wait_with_output().expect("output")
}
