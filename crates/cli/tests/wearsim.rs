//! The `wearsim` binary: exit codes and messages on good and bad scenes.

use std::path::PathBuf;
use std::process::{Command, Output};

mod common;
use common::{listing, scratch, stderr, wearsim};
mod lock_holder;
use lock_holder::LockHolder;

/// A copy of the default scene with `from` replaced by `to`, in a temporary file.
fn edited_scene(tag: &str, from: &str, to: &str) -> PathBuf {
    let text = lgres::scenes::source("lgres").unwrap();
    assert!(text.contains(from));
    let path = std::env::temp_dir().join(format!("wearsim-{tag}-{}.toml", std::process::id()));
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    path
}

#[test]
fn check_default_scene_succeeds() {
    let o = wearsim(&["check", "lgres"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("degrees of freedom"), "{out}");
    assert!(out.contains(": 4"), "{out}");
}

#[test]
fn bad_value_exits_2_naming_the_field() {
    let path = edited_scene("bad", "clearance = 0.0005", "clearance = -0.0005");
    let o = wearsim(&["check", path.to_str().unwrap()]);
    std::fs::remove_file(&path).unwrap();
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("clearance_joints[0].clearance = -0.0005: must be positive"),
        "{e}"
    );
    assert!(!e.contains("panicked"));
}

#[test]
fn unknown_key_is_rejected_with_its_line() {
    let path = edited_scene("unknown", "mass = 6.32", "mass = 6.32\ncolour = \"red\"");
    let o = wearsim(&["check", path.to_str().unwrap()]);
    std::fs::remove_file(&path).unwrap();
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("colour") && e.contains("line"), "{e}");
}

#[test]
fn overrides_are_validated_and_study_rejects_bad_settings() {
    let o = wearsim(&["check", "lgres", "--rtol", "-1"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("solver.rtol"));

    let out = std::env::temp_dir().join(format!("wearsim-ideal-{}", std::process::id()));
    let o = wearsim(&["run", "lgres-ideal", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    for file in [
        "summary.json",
        "response.csv",
        "scene.toml",
        "response_y.png",
        "report.html",
        "mechanism.gif",
    ] {
        assert!(out.join(file).is_file(), "{file} missing");
    }
    // `--no-animation` skips the animation, and the report shows what is there.
    let o = wearsim(&[
        "run",
        "lgres-ideal",
        "--no-animation",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!out.join("mechanism.gif").exists());
    let page = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(!page.contains("mechanism.gif"));
    std::fs::remove_dir_all(&out).unwrap();

    // Bad study settings are bad input, caught before any simulation.
    let o = wearsim(&["study", "clearance", "--cycles-per-stage", "0"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let o = wearsim(&["study", "speed", "--stages", "2"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let o = wearsim(&["check", "no-such-scene"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("no-such-scene"));
}

#[test]
fn scenes_lists_every_builtin() {
    let o = wearsim(&["scenes"]);
    assert!(o.status.success());
    let out = String::from_utf8_lossy(&o.stdout);
    for b in lgres::scenes::BUILTINS {
        assert!(out.contains(b.name), "{}", b.name);
    }
}

/// A fresh, empty temporary folder for one test.
/// `wearsim run SCENE --out OUT`.
fn run_into(scene: &str, out: &std::path::Path) -> Output {
    wearsim(&["run", scene, "--out", out.to_str().unwrap()])
}

fn write_scene(dir: &std::path::Path, text: &str) -> PathBuf {
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn cycles_per_stage_zero_is_rejected_naming_the_flag() {
    let o = wearsim(&["run", "lgres", "--cycles-per-stage", "0"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--cycles-per-stage"), "{}", stderr(&o));
}

#[test]
fn cycles_zero_is_rejected_naming_the_field() {
    let o = wearsim(&["check", "lgres", "--cycles", "0"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("run.cycles = 0"), "{}", stderr(&o));
}

#[test]
fn bad_layer_fields_are_refused_by_check_and_run_naming_the_field() {
    let dir = scratch("reference_speed");
    for (contact, field, why) in [
        (
            "{ reference_speed = 0.0 }",
            "reference_speed",
            "must be positive",
        ),
        (
            "{ reference_speed = -1.0 }",
            "reference_speed",
            "must be positive",
        ),
        (
            "{ reference_speed = nan }",
            "reference_speed",
            "must be a finite number",
        ),
        (
            "{ model = \"line-of-centres\", reference_speed = 0.1 }",
            "reference_speed",
            "only the foundation model takes it",
        ),
        (
            "{ layer = \"pin-in-hole\", layer_modulus = 5e14 }",
            "layer",
            "give one of the two",
        ),
        ("{ layer = \"banana\" }", "layer", "unknown variant"),
    ] {
        let scene = write_scene(
            &dir,
            &format!(
                "extends = \"lgres\"\n[[clearance_joints]]\nname = \"B\"\ncontact = {contact}\n"
            ),
        );
        for command in ["check", "run"] {
            let out = dir.join("out");
            let mut args = vec![command, scene.to_str().unwrap()];
            if command == "run" {
                args.extend(["--out", out.to_str().unwrap()]);
            }
            let o = wearsim(&args);
            assert_eq!(
                o.status.code(),
                Some(2),
                "{command} {contact}: {}",
                stderr(&o)
            );
            let log = stderr(&o);
            assert!(
                log.contains(&format!("clearance_joints[1].contact.{field}")) && log.contains(why),
                "{command} {contact}: {log}"
            );
            assert!(
                !out.exists(),
                "{command} {contact}: wrote {}",
                out.display()
            );
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn transient_window_longer_than_the_run_prints_n_a() {
    let dir = scratch("window");
    let scene = write_scene(
        &dir,
        // The benchmark's 5000 rpm overlaps reach 0.45 of the clearance, beyond the foundation's
        // thin-layer limit (its forces would be withheld): the one-point model shows the peaks.
        "extends = \"slider-crank\"\n[run]\ntransient_window = 0.05\n\
         [[clearance_joints]]\nname = \"rod-slider\"\ncontact = { model = \"line-of-centres\" }\n",
    );
    let out = dir.join("out");
    let o = run_into(scene.to_str().unwrap(), &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    // Standard error is a pipe here, as in a log: progress comes as whole lines, never as a
    // terminal's redrawn bar.
    let log = stderr(&o);
    assert!(
        log.lines().any(|l| l.starts_with("response: 2 cycle(s)"))
            && log.lines().any(|l| l.starts_with("response: done in"))
            && !log.contains('\r'),
        "{log}"
    );
    assert!(text.contains("n/a after 0.05 s"), "{text}");
    assert!(!text.contains("from 0 cycle"), "{text}");
    // The deviations after the window are not 0.0 µm but not available, in the terminal and
    // in summary.json (null, not 0.0).
    assert!(
        text.contains("vs ideal after 0.05 s: n/a") && !text.contains("0.0 µm"),
        "{text}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let response = &summary["response"];
    assert!(
        response["deviation_after_transient"].is_null(),
        "{response}"
    );
    assert!(response["joints"][0]["normal_force_after_transient"].is_null());
    assert!(
        response["deviation"]["x_m"]
            .as_f64()
            .is_some_and(|x| x > 0.0)
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn joint_name_escaping_out_is_rejected_before_any_file_is_written() {
    let dir = scratch("escape");
    let text = lgres::scenes::source("slider-crank").unwrap();
    for name in ["x/../../../E", "a/b", "bad\\u0000name", &"n".repeat(300)] {
        let scene = write_scene(
            &dir,
            &text.replace("name = \"rod-slider\"", &format!("name = \"{name}\"")),
        );
        let out = dir.join("out");
        let o = run_into(scene.to_str().unwrap(), &out);
        assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("clearance_joints[0].name"),
            "{}",
            stderr(&o)
        );
        assert_eq!(listing(&dir), ["scene.toml"], "{name}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn run_replaces_the_output_folder_whole() {
    let dir = scratch("replace");
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("summary.json"), "{\"old\": true}").unwrap();
    std::fs::write(out.join("wear_Z_stage1.csv"), "old").unwrap();
    let o = run_into("lgres-ideal", &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(!summary.contains("\"old\""), "{summary}");
    assert!(!out.join("wear_Z_stage1.csv").exists());
    assert!(listing(&out).iter().all(|n| !n.starts_with('.')));
    assert_eq!(listing(&dir), ["out"], "staging folder or lock left behind");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn folder_with_foreign_files_is_refused_and_kept() {
    let dir = scratch("foreign");
    let out = dir.join("out");
    std::fs::create_dir_all(out.join("sub")).unwrap();
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let o = run_into("lgres-ideal", &out);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("does not write"), "{}", stderr(&o));
    assert_eq!(listing(&out), ["notes.txt", "sub"]);
    assert_eq!(listing(&dir), ["out"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn second_run_into_a_locked_folder_is_refused() {
    let dir = scratch("lock");
    let out = dir.join("out");
    // A live process (this test) holds the lock: refused at once, naming it, nothing written.
    std::fs::write(dir.join(".out.lock"), std::process::id().to_string()).unwrap();
    let held = LockHolder::take(&dir.join(".out.lock"));
    let o = run_into("lgres-ideal", &out);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("another wearsim run"), "{}", stderr(&o));
    let holder = format!("process {}", std::process::id());
    assert!(stderr(&o).contains(&holder), "{}", stderr(&o));
    assert!(!out.exists());
    drop(held);
    // A lock whose process is gone (killed run: the system released it) is taken over.
    std::fs::write(dir.join(".out.lock"), "999999999").unwrap();
    let o = run_into("lgres-ideal", &out);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(listing(&dir), ["out"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn signals_leave_the_previous_folder_and_no_temporary_files() {
    let dir = scratch("signal");
    let out = dir.join("out");
    let o = run_into("lgres-ideal", &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let before = listing(&out);
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    for signal in ["-TERM", "-INT"] {
        // The default scene runs for many seconds; interrupt it while it simulates.
        let child = Command::new(env!("CARGO_BIN_EXE_wearsim"))
            .args(["run", "lgres", "--out", out.to_str().unwrap()])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(1500));
        let kill = Command::new("kill")
            .args([signal, &child.id().to_string()])
            .status()
            .unwrap();
        assert!(kill.success());
        let o = child.wait_with_output().unwrap();
        assert_eq!(o.status.code(), Some(130), "{signal}: {}", stderr(&o));
        assert_eq!(listing(&out), before, "{signal}");
        assert_eq!(
            std::fs::read_to_string(out.join("summary.json")).unwrap(),
            summary
        );
        assert_eq!(listing(&dir), ["out"], "{signal}: staging or lock left");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn study_folder_is_locked_refused_when_foreign_and_kept_when_interrupted() {
    let dir = scratch("study-staged");
    let out = dir.join("out");
    // A previous study: a report and one scene's run folder.
    std::fs::create_dir_all(out.join("lgres")).unwrap();
    std::fs::write(out.join("report.md"), "previous report").unwrap();
    std::fs::write(out.join("lgres").join("summary.json"), "{}").unwrap();
    let study = |out: &std::path::Path| {
        Command::new(env!("CARGO_BIN_EXE_wearsim"))
            .args(["study", "wear-stages", "--out", out.to_str().unwrap()])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap()
    };
    let unchanged = |what: &str| {
        assert_eq!(listing(&out), ["lgres", "report.md"], "{what}");
        assert_eq!(
            std::fs::read_to_string(out.join("report.md")).unwrap(),
            "previous report",
            "{what}"
        );
    };
    // Held by a live process (this test, with an advisory lock on it): refused at once.
    std::fs::write(dir.join(".out.lock"), std::process::id().to_string()).unwrap();
    let held = LockHolder::take(&dir.join(".out.lock"));
    let o = study(&out).wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("another wearsim run"), "{}", stderr(&o));
    unchanged("locked");
    drop(held);
    std::fs::remove_file(dir.join(".out.lock")).unwrap();
    // Interrupted while its scenes run: the previous study stays, nothing hidden is left.
    let child = study(&out);
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    unchanged("interrupted");
    assert_eq!(listing(&dir), ["out"], "staging or lock left");
    // A file the study does not write, inside a scene folder: refused, folder kept.
    std::fs::write(out.join("lgres").join("notes.txt"), "mine").unwrap();
    let o = study(&out).wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("lgres/notes.txt"), "{}", stderr(&o));
    assert_eq!(listing(&out.join("lgres")), ["notes.txt", "summary.json"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn precision_into_a_locked_folder_is_refused_and_releases_its_lock() {
    let dir = scratch("precision-lock");
    let out = dir.join("out");
    let precision = |out: &std::path::Path| {
        wearsim(&[
            "precision",
            "lgres",
            "--methods",
            "bdf",
            "--rtols",
            "1e-3",
            "--repeats",
            "1",
            "--duration",
            "0.02",
            "--out",
            out.to_str().unwrap(),
        ])
    };
    // Held as a live run holds it (an advisory lock on the file).
    std::fs::write(dir.join(".out.lock"), std::process::id().to_string()).unwrap();
    let held = LockHolder::take(&dir.join(".out.lock"));
    let o = precision(&out);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("another wearsim run"), "{}", stderr(&o));
    assert!(!out.exists());
    drop(held);
    std::fs::remove_file(dir.join(".out.lock")).unwrap();
    let o = precision(&out);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.join("precision.md").exists());
    assert_eq!(listing(&dir), ["out"], "lock left behind");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn budgets_and_penetration_end_runs_with_exit_1_naming_the_cause() {
    let dir = scratch("budget");
    let out = dir.join("out");
    let o = wearsim(&[
        "run",
        "slider-crank",
        "--max-steps",
        "10",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("solver.max_steps"), "{}", stderr(&o));
    let o = wearsim(&["check", "slider-crank", "--max-wall-time", "-1"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("solver.max_wall_time"),
        "{}",
        stderr(&o)
    );

    let scene = write_scene(
        &dir,
        "extends = \"lgres\"\n[[clearance_joints]]\nname = \"A\"\n\
         bearing_material = { youngs_modulus = 1e6, poisson_ratio = 0.3 }\n\
         pin_material = { youngs_modulus = 1e6, poisson_ratio = 0.3 }\n\
         [run]\ncycles = 1\nperiod = 0.2\nwear_stages = 0\n",
    );
    let o = run_into(scene.to_str().unwrap(), &out);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("peak penetration"), "{}", stderr(&o));
    assert_eq!(listing(&dir), ["scene.toml"], "nothing written on failure");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn check_fails_like_run_on_a_mechanism_missing_a_clearance_joint() {
    let dir = scratch("missing");
    let text = lgres::scenes::source("lgres").unwrap();
    let cut = text.find("# Joint B").unwrap();
    let end = text[cut..].find("[solver]").unwrap() + cut;
    let scene = write_scene(&dir, &format!("{}{}", &text[..cut], &text[end..]));
    let out = dir.join("out");
    for args in [
        vec!["check", scene.to_str().unwrap()],
        vec![
            "run",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
    ] {
        let o = wearsim(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains("kinematic analysis"), "{}", stderr(&o));
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn sweep_writes_rows_and_names_bad_fields() {
    let dir = std::env::temp_dir().join(format!("wearsim-sweep-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("grid.toml");
    let text = r#"
scene = "slider-crank"
metrics = ["response.joints.rod-slider.max_penetration_m"]
[run]
cycles = 1
[[vary]]
path = "clearance_joints.rod-slider.clearance"
values = [5e-4, -1e-4]
"#;
    std::fs::write(&file, text).unwrap();
    let out = dir.join("out");
    let o = wearsim(&[
        "sweep",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = std::fs::read_to_string(out.join("samples.csv")).unwrap();
    let lines: Vec<&str> = rows.lines().collect();
    assert_eq!(lines.len(), 3, "{rows}");
    assert!(
        lines[1].starts_with("0,5e-4,") && lines[1].contains(",ok,"),
        "{rows}"
    );
    assert!(lines[2].contains(",failed,") && lines[2].contains("clearance_joints[0].clearance"));
    std::fs::write(
        &file,
        text.replace(
            "values = [5e-4, -1e-4]",
            "distribution = \"normal\"\nmean = 5e-4",
        ),
    )
    .unwrap();
    let o = wearsim(&[
        "sweep",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("vary[0].sd"), "{}", stderr(&o));
    let o = wearsim(&["sweep", file.to_str().unwrap(), "--cycles", "2"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--cycles"), "{}", stderr(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn run_prints_when_each_joint_reaches_the_clearance_limit() {
    let dir = scratch("limit");
    let scene = |limit: &str| {
        write_scene(
            &dir,
            &format!(
                "extends = \"slider-crank\"\n\
                 [[clearance_joints]]\n\
                 name = \"rod-slider\"\n\
                 wear = {{ k_d = 1.8e-13, width = 0.02, cells = 360 }}\n\
                 [run]\n\
                 cycles = 1\n\
                 wear_stages = 1\n\
                 cycles_per_stage = 1\n\
                 amplification = 750.0\n\
                 clearance_limit = {limit}\n"
            ),
        )
    };
    let out = dir.join("out");
    let path = scene("0.000505");
    let o = run_into(path.to_str().unwrap(), &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("joint rod-slider reaches 0.505 mm clearance after "),
        "{text}"
    );
    for file in ["wear_life.csv", "wear_life_rod-slider.png"] {
        assert!(out.join(file).is_file(), "{file} missing");
    }
    let path = scene("0.001");
    let o = run_into(path.to_str().unwrap(), &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    // One stage of K = 1 cycle × 750 stands for 750 cycles, all applied.
    assert!(
        text.contains("joint rod-slider does not reach 1.00 mm clearance within 7.5e2 cycles"),
        "{text}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An `--out` that cannot be a run's folder is bad input (exit 2, the folder named), for every
/// command that writes one; nothing is left behind. And the analysis commands' flags are
/// checked before any work: `precision --duration 1e300` panicked on a capacity overflow and
/// `--repeats 0` reported NaN run times.
#[test]
fn bad_out_folders_and_analysis_flags_are_bad_input() {
    let dir = scratch("bad-out");
    let file = dir.join("a-file");
    std::fs::write(&file, "mine").unwrap();
    let through = format!("{}/x/../y", dir.display());
    for out in [
        file.to_str().unwrap(),
        "/",
        through.as_str(),
        "/proc/wearsim-out",
    ] {
        for command in [
            &["run", "lgres-ideal"][..],
            &["precision", "--repeats", "1"][..],
        ] {
            let mut args = command.to_vec();
            args.extend(["--out", out]);
            let o = wearsim(&args);
            assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
            assert!(
                stderr(&o).contains("output folder"),
                "{args:?}: {}",
                stderr(&o)
            );
        }
    }
    assert_eq!(listing(&dir), ["a-file"], "nothing left behind");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine");

    let o = wearsim(&["precision", "--duration", "1e300"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("duration"), "{}", stderr(&o));
    let o = wearsim(&["precision", "--repeats", "0"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--repeats"), "{}", stderr(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A run that replaces an existing folder keeps the folder's permissions (a read-only folder
/// stayed 555 only until the first run made it 755).
#[cfg(unix)]
#[test]
fn replaced_folder_keeps_its_permissions() {
    use std::os::unix::fs::PermissionsExt;
    let dir = scratch("mode");
    let out = dir.join("out");
    let o = run_into("lgres-ideal", &out);
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o555)).unwrap();
    let o = run_into("lgres-ideal", &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let mode = std::fs::metadata(&out).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode, 0o555);
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o755)).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A scene whose ideal mechanism is not fully driven is refused naming the file, its
/// clearance joints and its drivers (it named none of them).
#[test]
fn undriven_mechanism_is_refused_naming_the_scene_joints_and_drivers() {
    let dir = scratch("undriven");
    let scene = write_scene(
        &dir,
        "extends = \"lgres\"\ndrivers = []\n[run]\nperiod = 1.0\n",
    );
    let o = wearsim(&["check", scene.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains(&format!("in scene {}", scene.display()))
            && e.contains("clearance joints A, B")
            && e.contains("drivers (none)")
            && e.contains("15 coordinates and 14 constraint equations"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--surfaces` pointing at a FIFO (it blocked forever) or a link to `/dev/zero` (it aborted on
/// a 4 GiB allocation) is bad input, at once, and leaves no lock or staging folder behind.
#[cfg(unix)]
#[test]
fn special_wear_files_are_refused_and_leave_nothing_behind() {
    let dir = scratch("special");
    let surfaces = dir.join("worn");
    std::fs::create_dir_all(&surfaces).unwrap();
    // Joint A reads a valid (unworn) file; joint B's is the special one.
    let mut valid = String::from("angle [deg],bearing_depth [m],pin_depth [m]\n");
    for k in 0..1000 {
        valid.push_str(&format!("{},0,0\n", (k as f64 + 0.5) * 0.36));
    }
    std::fs::write(surfaces.join("wear_A_stage1.csv"), valid).unwrap();
    let b = surfaces.join("wear_B_stage1.csv");
    let out = dir.join("out");
    for special in ["fifo", "/dev/zero"] {
        let _ = std::fs::remove_file(&b);
        if special == "fifo" {
            let made = Command::new("mkfifo").arg(&b).status();
            assert!(made.is_ok_and(|s| s.success()), "mkfifo");
        } else {
            std::os::unix::fs::symlink(special, &b).unwrap();
        }
        let o = wearsim(&[
            "run",
            "lgres",
            "--cycles",
            "1",
            "--surfaces",
            surfaces.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2), "{special}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.contains("wear_B_stage1.csv: not a regular file"),
            "{special}: {e}"
        );
        assert_eq!(
            listing(&dir),
            ["worn"],
            "{special}: lock or staging left behind"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

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
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(
            stderr(&o).contains(&format!("{flag} does not apply")),
            "{}",
            stderr(&o)
        );
        refused += 1;
    }
    eprintln!("flag fuzz: {refused} of {cases} cases refused at once by name");
    assert_eq!(listing(&dir), ["a-file", "s.toml"], "nothing left behind");
    std::fs::remove_dir_all(&dir).unwrap();
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
