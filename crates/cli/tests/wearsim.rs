//! The `wearsim` binary: exit codes and messages on good and bad scenes.

use std::path::PathBuf;
use std::process::{Command, Output};

fn wearsim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_wearsim"))
        .args(args)
        .output()
        .expect("wearsim runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

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
    ] {
        assert!(out.join(file).is_file(), "{file} missing");
    }
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
