//! The `wearsim` binary's output folders: replaced whole, locked, refused when foreign or not a
//! folder, kept whole through signals, names that would escape them refused, special files
//! refused without leaving anything behind.

use std::path::Path;
use std::process::Command;

mod common;
use common::{
    QUICK_STUDY, assert_case_exit, assert_exit, listing, quick_precision, run_into, scratch,
    scratch_out, stderr, wearsim, wearsim_out, write_scene,
};
mod lock_holder;
use lock_holder::LockHolder;

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
        assert_case_exit(name, &o, 2, "clearance_joints[0].name");
        assert_eq!(listing(&dir), ["scene.toml"], "{name}");
    }
}

/// A folder as an earlier run (or its user) left it at `out`: each `(path, text)` written, the
/// folders on its way created; a path ending in `/` is an empty folder.
fn lay_out(out: &Path, files: &[(&str, &str)]) {
    for (path, text) in files {
        match path.strip_suffix('/') {
            Some(folder) => std::fs::create_dir_all(out.join(folder)).unwrap(),
            None => {
                let file = out.join(path);
                std::fs::create_dir_all(file.parent().unwrap()).unwrap();
                std::fs::write(file, text).unwrap();
            }
        }
    }
}

#[test]
fn run_replaces_the_output_folder_whole() {
    let (dir, out) = scratch_out("replace");
    lay_out(
        &out,
        &[
            ("summary.json", "{\"old\": true}"),
            ("wear_Z_stage1.csv", "old"),
        ],
    );
    let o = run_into("lgres-ideal", &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(!summary.contains("\"old\""), "{summary}");
    assert!(!out.join("wear_Z_stage1.csv").exists());
    assert!(listing(&out).iter().all(|n| !n.starts_with('.')));
    assert_eq!(listing(&dir), ["out"], "staging folder or lock left behind");
}

#[test]
fn folder_with_foreign_files_is_refused_and_kept() {
    let (dir, out) = scratch_out("foreign");
    lay_out(&out, &[("sub/", ""), ("notes.txt", "mine")]);
    let o = run_into("lgres-ideal", &out);
    assert_exit(&o, 2, "does not write");
    assert_eq!(listing(&out), ["notes.txt", "sub"]);
    assert_eq!(listing(&dir), ["out"]);
}

#[test]
fn second_run_into_a_locked_folder_is_refused() {
    let (dir, out) = scratch_out("lock");
    // A live process (this test) holds the lock: refused at once, naming it, nothing written.
    let o = LockHolder::live(&dir.join(".out.lock")).refuses(|| run_into("lgres-ideal", &out));
    let holder = format!("process {}", std::process::id());
    assert!(stderr(&o).contains(&holder), "{}", stderr(&o));
    assert!(!out.exists());
    // A lock whose process is gone (killed run: the system released it) is taken over.
    std::fs::write(dir.join(".out.lock"), "999999999").unwrap();
    let o = run_into("lgres-ideal", &out);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(listing(&dir), ["out"]);
}

#[test]
fn signals_leave_the_previous_folder_and_no_temporary_files() {
    let (dir, out) = scratch_out("signal");
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
}

#[test]
fn study_folder_is_locked_refused_when_foreign_and_kept_when_interrupted() {
    let (dir, out) = scratch_out("study-staged");
    // A previous study: a report and one scene's run folder.
    lay_out(
        &out,
        &[
            ("report.md", "previous report"),
            ("lgres/summary.json", "{}"),
        ],
    );
    let study = |out: &Path| {
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
    LockHolder::live(&dir.join(".out.lock")).refuses(|| study(&out).wait_with_output().unwrap());
    unchanged("locked");
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
    assert_exit(&o, 2, "lgres/notes.txt");
    assert_eq!(listing(&out.join("lgres")), ["notes.txt", "summary.json"]);
}

#[test]
fn precision_into_a_locked_folder_is_refused_and_releases_its_lock() {
    let (dir, out) = scratch_out("precision-lock");
    let precision = |out: &Path| wearsim(&quick_precision(out.to_str().unwrap()));
    // Held as a live run holds it (an advisory lock on the file).
    LockHolder::live(&dir.join(".out.lock")).refuses(|| precision(&out));
    assert!(!out.exists());
    std::fs::remove_file(dir.join(".out.lock")).unwrap();
    let o = precision(&out);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.join("precision.md").exists());
    assert_eq!(listing(&dir), ["out"], "lock left behind");
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
            assert_case_exit(&format!("{args:?}"), &o, 2, "output folder");
        }
    }
    assert_eq!(listing(&dir), ["a-file"], "nothing left behind");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine");

    let o = wearsim(&["precision", "--duration", "1e300"]);
    assert_exit(&o, 2, "duration");
    let o = wearsim(&["precision", "--repeats", "0"]);
    assert_exit(&o, 2, "--repeats");
}

/// A run that replaces an existing folder keeps the folder's permissions (a read-only folder
/// stayed 555 only until the first run made it 755).
#[cfg(unix)]
#[test]
fn replaced_folder_keeps_its_permissions() {
    use std::os::unix::fs::PermissionsExt;
    let (_dir, out) = scratch_out("mode");
    let o = run_into("lgres-ideal", &out);
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o555)).unwrap();
    let o = run_into("lgres-ideal", &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let mode = std::fs::metadata(&out).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode, 0o555);
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o755)).unwrap();
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
        let o = wearsim_out(
            &[
                "run",
                "lgres",
                "--cycles",
                "1",
                "--surfaces",
                surfaces.to_str().unwrap(),
            ],
            &out,
        );
        assert_case_exit(special, &o, 2, "wear_B_stage1.csv: not a regular file");
        assert_eq!(
            listing(&dir),
            ["worn"],
            "{special}: lock or staging left behind"
        );
    }
}

/// Every command that writes an output folder, in its cheapest form (the arguments before
/// `--out`); `sweep_file` is a sweep file for `sweep`.
fn folder_writers(sweep_file: &Path) -> Vec<Vec<String>> {
    let precision = quick_precision("");
    [
        &["run", "slider-crank", "--cycles", "1", "--no-animation"][..],
        &QUICK_STUDY[..],
        &["sweep", sweep_file.to_str().unwrap()][..],
        &precision[..precision.len() - 2],
        &["stress", "--quick"][..],
    ]
    .iter()
    .map(|args| args.iter().map(ToString::to_string).collect())
    .collect()
}

/// A one-sample sweep file of the slider-crank in `dir`.
fn tiny_sweep(dir: &Path) -> std::path::PathBuf {
    common::write_file(
        dir,
        "tiny.toml",
        "scene = \"slider-crank\"\nmetrics = [\"response.joints.rod-slider.max_penetration_m\"]\n\
         [run]\ncycles = 1\n[[vary]]\npath = \"clearance_joints.rod-slider.clearance\"\n\
         values = [4e-4]\n",
    )
}

/// Output folders nested in either direction, under every command that writes one: while
/// another live run holds a folder that contains `--out` (one or two levels up) or that lies
/// inside it (one or two levels down), the command is refused at once naming that folder, and
/// leaves no lock or staging of its own.
#[test]
fn folders_inside_or_around_a_held_folder_are_refused_under_every_command() {
    let dir = scratch("nested");
    let sweep_file = tiny_sweep(&dir);
    for args in folder_writers(&sweep_file) {
        for depth in ["inner", "a/inner"] {
            let case = format!("{} {depth}", args[0]);
            let outer = dir.join("outer");
            let inner = outer.join(depth);
            let command = |out: &Path| {
                let mut all = args.clone();
                all.extend(["--out".into(), out.to_str().unwrap().into()]);
                Command::new(env!("CARGO_BIN_EXE_wearsim"))
                    .args(&all)
                    .output()
                    .unwrap()
            };
            // Another run holds the outer folder: --out inside it is refused.
            let o = LockHolder::live(&dir.join(".outer.lock")).refuses(|| command(&inner));
            assert!(
                stderr(&o).contains("which contains it"),
                "{case}: {}",
                stderr(&o)
            );
            assert!(!inner.exists(), "{case}");
            let parent = inner.parent().unwrap();
            assert!(listing(parent).is_empty() || parent == outer, "{case}");
            std::fs::remove_file(dir.join(".outer.lock")).unwrap();
            std::fs::remove_dir_all(&outer).unwrap();
            // Another run holds a folder inside: --out around it is refused.
            std::fs::create_dir_all(&inner).unwrap();
            let lock = parent.join(".inner.lock");
            let o = LockHolder::live(&lock).refuses(|| command(&outer));
            assert!(stderr(&o).contains("inside it"), "{case}: {}", stderr(&o));
            assert_eq!(listing(parent), [".inner.lock", "inner"], "{case}");
            std::fs::remove_dir_all(&outer).unwrap();
            assert_eq!(listing(&dir), ["tiny.toml"], "{case}: lock or staging left");
        }
    }
}

/// `--out` naming the current folder, or a folder that contains it, is refused (a run
/// replaces its folder whole: the shell would be left in a deleted folder), by the commands
/// whose folder is replaced; nothing is created.
#[cfg(unix)]
#[test]
fn the_current_folder_or_one_around_it_is_refused_as_out() {
    use std::os::unix::fs::MetadataExt;
    let dir = scratch("cwd");
    let here = dir.join("here");
    std::fs::create_dir_all(&here).unwrap();
    let inode = std::fs::metadata(&here).unwrap().ino();
    let sweep_file = tiny_sweep(&dir);
    for args in folder_writers(&sweep_file).into_iter().take(2) {
        let (absolute, around) = (here.to_str().unwrap(), dir.to_str().unwrap());
        for (out, says) in [
            (".", "is the current folder or contains it"),
            ("./", "is the current folder or contains it"),
            (absolute, "is the current folder or contains it"),
            (around, "is the current folder or contains it"),
            ("..", "names no folder of its own"),
            ("../here", "must not contain `..`"),
        ] {
            let o = Command::new(env!("CARGO_BIN_EXE_wearsim"))
                .args(&args)
                .args(["--out", out])
                .current_dir(&here)
                .output()
                .unwrap();
            let case = format!("{} --out {out}", args[0]);
            assert_case_exit(&case, &o, 2, says);
            assert_eq!(std::fs::metadata(&here).unwrap().ino(), inode, "{case}");
            assert!(listing(&here).is_empty(), "{case}");
            assert_eq!(listing(&dir), ["here", "tiny.toml"], "{case}");
        }
    }
    // The root has no folder name; the message does not claim `.` is refused.
    let o = wearsim(&["run", "slider-crank", "--out", "/"]);
    assert_exit(&o, 2, "names no folder of its own");
    assert!(!stderr(&o).contains("`.`"), "{}", stderr(&o));
}

/// A lock that cannot be written (a full disk; here a file size limit of 0, which fails the
/// same write) is removed again, as every other failure removes it.
#[cfg(unix)]
#[test]
fn a_lock_that_cannot_be_written_is_not_left_behind() {
    let (dir, out) = scratch_out("full");
    let o = Command::new("sh")
        .args([
            "-c",
            "trap '' XFSZ; ulimit -f 0; exec \"$0\" run slider-crank --cycles 1 --no-animation \
             --out \"$1\"",
            env!("CARGO_BIN_EXE_wearsim"),
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_ne!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stderr(&o).contains(".out.lock"), "{}", stderr(&o));
    assert!(listing(&dir).is_empty(), "left: {:?}", listing(&dir));
}

/// `--surfaces` for a scene none of whose joints wears is refused naming the flag (it was
/// accepted and ignored), before anything is written.
#[test]
fn surfaces_for_a_scene_without_wear_are_refused() {
    let dir = scratch("no-wear");
    let surfaces = dir.join("worn");
    std::fs::create_dir_all(&surfaces).unwrap();
    for scene in ["slider-crank", "lgres-ideal"] {
        let o = wearsim_out(
            &[
                "run",
                scene,
                "--cycles",
                "1",
                "--no-animation",
                "--surfaces",
                surfaces.to_str().unwrap(),
            ],
            &dir.join("out"),
        );
        assert_case_exit(scene, &o, 2, "--surfaces");
        assert_case_exit(scene, &o, 2, "no clearance joint with wear");
        assert_eq!(listing(&dir), ["worn"], "{scene}");
    }
}
