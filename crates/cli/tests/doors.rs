//! Issue 35's doors, through the `wearsim` binary: each test names the door it holds (closed
//! pipes, the lock, bounds on work, `check` against `run`, the sweep's `[run]` table and files,
//! the description, `extends`, a symlinked `--out`).

#![cfg(unix)]

use std::path::Path;
use std::process::{Command, Output, Stdio};

mod common;
use common::{
    assert_case_exit, assert_exit, check, lgres_with, listing, quick_precision, run_into, scratch,
    scratch_out, stderr, wearsim, wearsim_out, write_file,
};
mod lock_holder;
use lock_holder::LockHolder;

/// Runs `wearsim args` with standard output (and, if `stderr_too`, standard error) a pipe
/// whose reading end is already closed: every write fails with a broken pipe.
fn into_closed_pipe(args: &[&str], stderr_too: bool) -> Output {
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let err = if stderr_too {
        Stdio::from(writer.try_clone().unwrap())
    } else {
        Stdio::piped()
    };
    Command::new(env!("CARGO_BIN_EXE_wearsim"))
        .args(args)
        .stdout(writer)
        .stderr(err)
        .output()
        .expect("wearsim runs")
}

/// The exit of a program a closed pipe ended (128 + SIGPIPE).
const CLOSED_PIPE: i32 = 141;

#[test]
fn closed_pipes_end_quietly_and_leave_the_output_folder_whole() {
    for args in [&["scenes"][..], &["check", "lgres"]] {
        let o = into_closed_pipe(args, false);
        assert_eq!(
            o.status.code(),
            Some(CLOSED_PIPE),
            "{args:?}: {}",
            stderr(&o)
        );
        assert!(!stderr(&o).contains("panicked"), "{args:?}: {}", stderr(&o));
    }
    // Progress lines and the summary into the same closed pipe (`run … 2>&1 | head -1`).
    let (dir, out) = scratch_out("closed-pipe");
    let o = into_closed_pipe(
        &[
            "run",
            "lgres",
            "--cycles",
            "1",
            "--stages",
            "0",
            "--no-animation",
            "--out",
            out.to_str().unwrap(),
        ],
        true,
    );
    assert_eq!(o.status.code(), Some(CLOSED_PIPE));
    assert_eq!(listing(&dir), ["out"], "nothing beside --out");
    assert!(
        out.join("summary.json").is_file(),
        "the run's folder is whole"
    );
}

#[test]
fn a_lock_held_by_a_live_run_is_refused_even_before_its_pid_is_written() {
    let (dir, out) = scratch_out("lock-live");
    // A live owner that has created its lock file but not yet written its pid.
    LockHolder::take(&dir.join(".out.lock")).refuses(|| run_into("lgres-ideal", &out));
    assert!(!out.exists());
    assert_eq!(
        listing(&dir),
        [".out.lock"],
        "the owner's lock file is kept"
    );
    // Released (its owner ended): taken.
    let o = run_into("lgres-ideal", &out);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(listing(&dir), ["out"]);
}

/// A small deterministic generator (xorshift), so every run sees the same cases.
struct Cases(u64);

impl Cases {
    fn below(&mut self, n: u64) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0 % n
    }
}

/// `check` and `run` (cut short by a one-step budget, so a scene it accepts fails with 1)
/// on fuzzed `run.trajectories`, `run.cycles_per_stage` and the flags that override them:
/// `check` passes exactly what `run` does not refuse as bad input.
#[test]
fn check_and_run_agree_on_fuzzed_stage_settings_and_flags() {
    let (dir, out) = scratch_out("check-run");
    let mut cases = Cases(0x2545_F491_4F6C_DD1D);
    let (mut accepted, mut refused) = (0, 0);
    for _ in 0..24 {
        let trajectories = 1 + cases.below(6);
        let k = 1 + cases.below(8);
        let scene = lgres_with(
            &dir,
            &format!(
                "[run]\ncycles = 1\nwear_stages = 1\nanimation = false\n\
                 trajectories = {trajectories}\ncycles_per_stage = {k}\n"
            ),
        );
        let mut flags: Vec<String> = vec!["--max-steps".into(), "1".into()];
        match cases.below(4) {
            0 => {}
            1 => flags.extend([
                "--cycles-per-stage".into(),
                (1 + cases.below(8)).to_string(),
            ]),
            2 => flags.extend(["--cycles-per-stage".into(), "20000".into()]),
            _ => flags.extend(["--trajectories".into(), (1 + cases.below(6)).to_string()]),
        }
        if cases.below(2) == 0 {
            flags.extend(["--trajectories".into(), (1 + cases.below(70)).to_string()]);
        }
        let flags: Vec<&str> = flags.iter().map(String::as_str).collect();
        let scene = scene.to_str().unwrap();
        let check = wearsim(&[&["check", scene][..], &flags].concat());
        let run = wearsim(&[&["run", scene, "--out", out.to_str().unwrap()][..], &flags].concat());
        let (c, r) = (check.status.code(), run.status.code());
        assert!(
            matches!(c, Some(0 | 2)),
            "{flags:?}: check {c:?}: {}",
            stderr(&check)
        );
        assert!(
            matches!(r, Some(1 | 2)),
            "{flags:?}: run {r:?}: {}",
            stderr(&run)
        );
        assert_eq!(
            c == Some(2),
            r == Some(2),
            "scene trajectories {trajectories}, K {k}, {flags:?}: check says {}, run says {}",
            stderr(&check),
            stderr(&run)
        );
        if c == Some(0) {
            accepted += 1;
        } else {
            refused += 1;
        }
    }
    eprintln!("check against run: {accepted} accepted, {refused} refused");
    assert!(
        accepted > 0 && refused > 0,
        "{accepted} accepted, {refused} refused"
    );
}

#[test]
fn check_refuses_the_issues_trajectories_and_cycles_per_stage() {
    let dir = scratch("check-k");
    let scene = lgres_with(&dir, "[run]\ntrajectories = 3\ncycles_per_stage = 2\n");
    let o = wearsim(&["check", scene.to_str().unwrap(), "--cycles-per-stage", "2"]);
    assert_exit(&o, 2, "run.trajectories = 3");
    let o = wearsim(&["check", "lgres", "--cycles-per-stage", "20000"]);
    assert_exit(&o, 2, "run.cycles_per_stage");
    assert!(
        stderr(&o).contains("in scene lgres as run (K = 20000"),
        "{}",
        stderr(&o)
    );
}

/// Every setting of the issue's item 4 is refused by `check`, naming its field.
#[test]
fn settings_without_a_bound_on_work_are_refused_naming_the_field() {
    let dir = scratch("bounds");
    let cases = [
        ("[run]\nmax_substeps = 4294967295", "run.max_substeps"),
        (
            "[run]\nmax_clearance_change = 1e-300",
            "run.max_clearance_change",
        ),
        ("[run]\nmax_slope_change = 5e-324", "run.max_slope_change"),
        (
            "[run]\nmax_curvature_change = 1e-9",
            "run.max_curvature_change",
        ),
        ("[run]\nwear_tolerance = 1e-200", "run.wear_tolerance"),
        ("[run]\nwear_noise = 0", "run.wear_noise"),
        (
            "[run]\nforming_clearance_change = 1e-9",
            "run.forming_clearance_change",
        ),
        ("[run]\nforming_depth = -1", "run.forming_depth"),
        ("[run]\namplification = 1e300", "run.amplification"),
        (
            "[[clearance_joints]]\nname = \"B\"\ncontact = { width = 1e6 }",
            "clearance_joints[1].contact.width",
        ),
        (
            "[[clearance_joints]]\nname = \"B\"\ncontact = { layer_modulus = 1e20 }",
            "clearance_joints[1].contact.layer_modulus",
        ),
        (
            "[[clearance_joints]]\nname = \"B\"\ncontact = { layer_modulus = 1e300 }",
            "clearance_joints[1].contact.layer_modulus",
        ),
    ];
    for (patch, field) in cases {
        let scene = lgres_with(&dir, &format!("{patch}\n"));
        let o = check(&scene);
        assert_case_exit(patch, &o, 2, field);
    }
    let o = wearsim(&["study", "wear-stages", "--stage-cycles", "1e20"]);
    assert_exit(&o, 2, "stage-cycles = 1e20");
}

#[test]
fn sweep_run_table_and_sweep_files_are_checked_up_front_with_exit_2() {
    let (dir, out) = scratch_out("sweep-doors");
    let sweep = |run: &str| {
        format!(
            "scene = \"slider-crank\"\nmetrics = [\"response.joints.rod-slider.max_penetration_m\"]\n\
             [run]\n{run}\n[[vary]]\npath = \"clearance_joints.rod-slider.clearance\"\n\
             values = [5e-4]\n"
        )
    };
    for (run, field) in [
        ("max_wall_time = nan", "run.max_wall_time"),
        ("rtol = 1.0", "run.rtol"),
        ("max_steps = 0", "run.max_steps"),
        ("cycles = 10001", "run.cycles"),
        ("trajectories = 65", "run.trajectories"),
        (
            "cycles_per_stage = 3\ntrajectories = 2\nstages = 1",
            "run.trajectories",
        ),
    ] {
        let file = write_file(&dir, "s.toml", &sweep(run));
        let o = wearsim_out(&["sweep", file.to_str().unwrap()], &out);
        assert_case_exit(run, &o, 2, field);
        assert!(
            !stderr(&o).contains("command-line"),
            "{run}: {}",
            stderr(&o)
        );
        assert!(!out.exists(), "{run}: nothing written");
    }
    let missing = dir.join("missing.toml");
    let not_utf8 = dir.join("latin1.toml");
    std::fs::write(&not_utf8, b"scene = \"caf\xe9\"\n").unwrap();
    for file in [missing.as_path(), &dir, not_utf8.as_path()] {
        let o = wearsim_out(&["sweep", file.to_str().unwrap()], &out);
        assert_eq!(
            o.status.code(),
            Some(2),
            "{}: {}",
            file.display(),
            stderr(&o)
        );
    }
}

/// `o` (of `command`) is a refusal (exit 2) that printed no control character raw (ESC, BEL).
#[track_caller]
fn refused_printing_no_control_characters(o: &Output, command: &str) {
    assert_eq!(o.status.code(), Some(2), "{command}: {}", stderr(o));
    let printed = [o.stdout.as_slice(), o.stderr.as_slice()].concat();
    assert!(
        !printed.contains(&0x1b) && !printed.contains(&0x07),
        "{command}: {}",
        stderr(o)
    );
}

#[test]
fn control_characters_in_the_description_are_refused_and_never_printed_raw() {
    let dir = scratch("description");
    let scene = lgres_with(&dir, "description = \"\\u001b]0;owned\\u0007\\u001b[2J\"\n");
    let unused = dir.join("unused");
    let (scene, unused) = (scene.to_str().unwrap(), unused.to_str().unwrap());
    for args in [&["check", scene][..], &["run", scene, "--out", unused]] {
        let o = wearsim(args);
        refused_printing_no_control_characters(&o, args[0]);
        assert!(stderr(&o).contains("description"), "{}", stderr(&o));
    }
    assert!(!Path::new(unused).exists());
    // Line breaks and tabs stay allowed.
    let scene = lgres_with(&dir, "description = \"two\\nlines\\tand a tab\"\n");
    let o = check(&scene);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn extends_switches_a_joints_contact_model() {
    let dir = scratch("extends-model");
    let scene = lgres_with(
        &dir,
        "[[clearance_joints]]\nname = \"B\"\n\
         contact = { model = \"line-of-centres\" }\n",
    );
    let o = check(&scene);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("line-of-centres"), "{text}");
    // Naming the model the base already has keeps the base's fields.
    let scene = lgres_with(
        &dir,
        "[[clearance_joints]]\nname = \"B\"\n\
         contact = { model = \"thin-gap\", reference_speed = 0.1 }\n",
    );
    let merged = scene::load_path(&scene, lgres::scenes::BUILTINS).unwrap();
    let b = merged
        .clearance_joints
        .iter()
        .find(|j| j.name == "B")
        .unwrap();
    let scene::ContactSpec::ThinGap(scene::ThinGapSpec(contact)) = b.contact else {
        panic!("not the thin gap: {:?}", b.contact)
    };
    assert_eq!(contact.cells, Some(500));
    assert_eq!(contact.reference_speed, Some(0.1));
}

#[test]
fn out_through_a_symlink_writes_the_linked_folder_and_keeps_the_link() {
    let dir = scratch("symlink-out");
    let real = dir.join("real");
    std::fs::create_dir(&real).unwrap();
    let link = dir.join("link");
    std::os::unix::fs::symlink(&real, &link).unwrap();
    for _ in 0..2 {
        let o = run_into("lgres-ideal", &link);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(
            std::fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink(),
            "the link stays a link"
        );
        assert!(
            real.join("summary.json").is_file(),
            "written through the link"
        );
        assert_eq!(listing(&dir), ["link", "real"]);
    }
    // A link to nothing is refused, naming it.
    let dangling = dir.join("dangling");
    std::os::unix::fs::symlink(dir.join("nowhere"), &dangling).unwrap();
    let o = run_into("lgres-ideal", &dangling);
    assert_exit(&o, 2, "symbolic link");
}

/// Numbers in messages in their short form (`1e300`, not 301 digits).
#[test]
fn messages_write_extreme_numbers_short() {
    let dir = scratch("messages");
    let out = dir.join("precision");
    let o = wearsim_out(&["precision", "--start-up", "1e300"], &out);
    assert_exit(&o, 2, "1e300 s is longer");
    assert!(stderr(&o).len() < 300, "{}", stderr(&o));
    let o = wearsim(&["study", "wear-stages", "--stage-cycles", "1e-300"]);
    assert_exit(&o, 2, "stage-cycles = 1e-300");
    assert_eq!(listing(&dir), Vec::<String>::new(), "nothing written");
}

/// Closed pipes fuzzed over the commands: every built-in scene through `check`, the lists,
/// refusals, and `precision` and `sweep` runs that write folders, each with standard output
/// (and for the runs standard error too) a closed pipe. Never a panic or an abort: a command
/// that succeeds exits as a closed pipe asks, one that fails keeps its own exit code, and a
/// folder it writes is whole with nothing left beside it.
#[test]
fn every_command_survives_closed_pipes() {
    let dir = scratch("closed-pipes-all");
    let bad = write_file(&dir, "bad.toml", "extends = \"lgres\"\n[run]\ncycles = 0\n");
    let sweep = write_file(
        &dir,
        "s.toml",
        "scene = \"slider-crank\"\nmetrics = [\"response.joints.rod-slider.max_penetration_m\"]\n\
         [run]\ncycles = 1\n[[vary]]\npath = \"clearance_joints.rod-slider.clearance\"\n\
         values = [4e-4, 5e-4]\n",
    );
    let out = dir.join("out");
    let (bad, sweep, out) = (
        bad.to_str().unwrap(),
        sweep.to_str().unwrap(),
        out.to_str().unwrap(),
    );
    let mut cases: Vec<(Vec<&str>, i32, bool)> = lgres::scenes::BUILTINS
        .iter()
        .map(|b| (vec!["check", b.name], CLOSED_PIPE, false))
        .collect();
    cases.extend([
        (vec!["scenes"], CLOSED_PIPE, false),
        (vec!["check", bad], 2, false),
        (vec!["study", "clearance", "--stage-cycles", "0"], 2, false),
        (quick_precision(out).to_vec(), CLOSED_PIPE, true),
        (vec!["sweep", sweep, "--out", out], CLOSED_PIPE, true),
    ]);
    for (args, code, both) in &cases {
        let o = into_closed_pipe(args, *both);
        assert_eq!(o.status.code(), Some(*code), "{args:?}: {}", stderr(&o));
        assert!(!stderr(&o).contains("panicked"), "{args:?}: {}", stderr(&o));
        if *both {
            assert_eq!(
                listing(&dir),
                ["bad.toml", "out", "s.toml"],
                "{args:?}: nothing beside the folder"
            );
            std::fs::remove_dir_all(dir.join("out")).unwrap();
        }
    }
    eprintln!("closed pipes: {} commands", cases.len());
}

/// Text that reaches the terminal from elsewhere than a scene's fields (here a file name in an
/// error message) has its control characters escaped, never printed raw.
#[test]
fn control_characters_never_reach_the_terminal_raw() {
    let dir = scratch("escaped-output");
    let scene = write_file(
        &dir,
        "x\u{1b}]0;owned\u{7}.toml",
        "extends = \"lgres\"\n[run]\ncycles = 0\n",
    );
    let o = check(&scene);
    refused_printing_no_control_characters(&o, "check");
    assert!(
        stderr(&o).contains("x\\u{1b}]0;owned\\u{7}.toml"),
        "{}",
        stderr(&o)
    );
}
