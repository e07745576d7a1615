//! The `wearsim` binary refusing bad scenes and settings: `check` and `run` exit 2 naming the
//! field, line or flag, and `check` fails where `run` would (the other test files: output
//! folders, runs' outputs, every command's flags fuzzed).

mod common;
use common::{
    assert_case_exit, assert_exit, check, edited_scene, lgres_with, run_into, scratch, stderr,
    wearsim, wearsim_out, write_scene,
};

#[test]
fn check_default_scene_succeeds() {
    let o = wearsim(&["check", "lgres"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("degrees of freedom"), "{out}");
    assert!(out.contains(": 4"), "{out}");
}

/// `wearsim check` on the default scene with `from` replaced by `to`, which must exit 2; its
/// standard error.
fn check_edited(tag: &str, from: &str, to: &str) -> String {
    let path = edited_scene(tag, from, to);
    let o = wearsim(&["check", path.to_str().unwrap()]);
    std::fs::remove_file(&path).unwrap();
    assert_eq!(o.status.code(), Some(2));
    stderr(&o)
}

#[test]
fn bad_value_exits_2_naming_the_field() {
    let e = check_edited("bad", "clearance = 0.0005", "clearance = -0.0005");
    assert!(
        e.contains("clearance_joints[0].clearance = -0.0005: must be positive"),
        "{e}"
    );
    assert!(!e.contains("panicked"));
}

#[test]
fn unknown_key_is_rejected_with_its_line() {
    let e = check_edited("unknown", "mass = 6.32", "mass = 6.32\ncolour = \"red\"");
    assert!(e.contains("colour") && e.contains("line"), "{e}");
}

#[test]
fn overrides_are_validated_and_study_rejects_bad_settings() {
    let o = wearsim(&["check", "lgres", "--rtol", "-1"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("solver.rtol"));

    let out = std::env::temp_dir().join(format!("wearsim-ideal-{}", std::process::id()));
    let o = run_into("lgres-ideal", &out);
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
    let o = wearsim_out(&["run", "lgres-ideal", "--no-animation"], &out);
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

/// `study --help` offers every study of the list with its summary, the extrapolation study and
/// `all`; an unknown name is refused with the names offered.
#[test]
fn study_help_lists_every_study() {
    let o = wearsim(&["study", "--help"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let help = String::from_utf8_lossy(&o.stdout);
    for s in lgres::studies::STUDIES {
        assert!(
            help.contains(&format!("- {}: ", s.name)),
            "{}: {help}",
            s.name
        );
    }
    let extrapolation = lgres::studies::EXTRAPOLATION.name;
    assert!(help.contains(&format!("- {extrapolation}: ")), "{help}");
    assert!(help.contains("- all: "), "{help}");
    let o = wearsim(&["study", "no-such-study"]);
    assert_exit(&o, 2, lgres::studies::SPEED_PAPER.name);
}

#[test]
fn cycles_per_stage_zero_is_rejected_naming_the_flag() {
    let o = wearsim(&["run", "lgres", "--cycles-per-stage", "0"]);
    assert_exit(&o, 2, "--cycles-per-stage");
}

#[test]
fn cycles_zero_is_rejected_naming_the_field() {
    let o = wearsim(&["check", "lgres", "--cycles", "0"]);
    assert_exit(&o, 2, "run.cycles = 0");
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
            "",
            "unknown field `reference_speed`, there are no fields (model = \"line-of-centres\")",
        ),
        (
            "{ layer = \"pin-in-hole\", layer_modulus = 5e14 }",
            "layer",
            "give one of the two",
        ),
        (
            "{ layer = \"banana\" }",
            "",
            "unknown variant `banana`, expected `paper` or `pin-in-hole` (model = \"thin-gap\")",
        ),
    ] {
        let scene = lgres_with(
            &dir,
            &format!("[[clearance_joints]]\nname = \"B\"\ncontact = {contact}\n"),
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
            // A field serde refuses is named in the message; the path ends at the table.
            let path = if field.is_empty() {
                "clearance_joints[1].contact".to_string()
            } else {
                format!("clearance_joints[1].contact.{field}")
            };
            assert!(
                log.contains(&path) && log.contains(why),
                "{command} {contact}: {log}"
            );
            assert!(
                !out.exists(),
                "{command} {contact}: wrote {}",
                out.display()
            );
        }
    }
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
        assert_case_exit(&format!("{args:?}"), &o, 2, "kinematic analysis");
    }
}

/// A scene whose ideal mechanism is not fully driven is refused naming the file, its
/// clearance joints and its drivers (it named none of them).
#[test]
fn undriven_mechanism_is_refused_naming_the_scene_joints_and_drivers() {
    let dir = scratch("undriven");
    let scene = lgres_with(&dir, "drivers = []\n[run]\nperiod = 1.0\n");
    let o = check(&scene);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains(&format!("in scene {}", scene.display()))
            && e.contains("clearance joints A, B")
            && e.contains("drivers (none)")
            && e.contains("15 coordinates and 14 constraint equations"),
        "{e}"
    );
}

/// Millimetres in `check`'s lines read as given, without the conversion's round-off
/// (`0.5000001000000001 mm`).
#[test]
fn check_prints_clearances_as_given() {
    let dir = scratch("mm");
    for (clearance, says) in [("0.0005000001", "0.5000001 mm"), ("0.0005", "0.5 mm")] {
        let scene = lgres_with(
            &dir,
            &format!("[[clearance_joints]]\nname = \"A\"\nclearance = {clearance}\n"),
        );
        let o = check(&scene);
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(out.contains(&format!("clearance {says}")), "{out}");
    }
}
