//! Bad input ends in a named error (never a panic, hang or a
//! silently wrong run), and `check` rejects what `run` would.

use lgres::scenes;
use scene::{SceneError, load_str};
use sim::{ContactSeries, RunError, RunOptions, check_assembly};

/// `extends = "lgres"` plus `patch`, parsed and validated.
fn patched(patch: &str) -> Result<scene::ValidScene, SceneError> {
    load_str(
        &format!("extends = \"lgres\"\n{patch}\n"),
        "patch",
        lgres::scenes::BUILTINS,
    )
}

/// The error text of a patch that must be rejected, checked to name `field`.
fn rejected(patch: &str, field: &str) -> String {
    let e = patched(patch).expect_err("must be rejected").to_string();
    assert!(e.contains(field), "{field} not named in: {e}");
    e
}

/// The default scene's text with `from` replaced by `to`.
fn edited(from: &str, to: &str) -> String {
    let text = scenes::source("lgres").unwrap();
    assert!(text.contains(from), "{from}");
    text.replacen(from, to, 1)
}

#[test]
fn output_interval_tiny_is_rejected_naming_the_field() {
    rejected(
        "[solver]\noutput_interval = 1e-300",
        "solver.output_interval = 1e-300",
    );
}

#[test]
fn period_huge_is_rejected_naming_the_field() {
    rejected("[run]\nperiod = 1e300", "run.period = 1e300");
}

#[test]
fn cycles_ten_million_is_rejected_naming_the_field() {
    rejected("[run]\ncycles = 10000000", "run.cycles = 10000000");
}

#[test]
fn cycles_zero_is_rejected_naming_the_field() {
    rejected("[run]\ncycles = 0", "run.cycles = 0: must be at least 1");
}

#[test]
fn too_many_bodies_or_wear_cells_are_rejected_naming_the_field() {
    let bodies: String = (0..1001)
        .map(|k| {
            format!("[[bodies]]\nname = \"b{k}\"\nmass = 1.0\ninertia = 1.0\nx = 0.0\ny = 0.0\ntheta_deg = 0.0\n")
        })
        .collect();
    rejected(&bodies, "bodies = 1006: at most 1000");
    rejected(
        "[run]\nwear_stages = 1000\n[[clearance_joints]]\nname = \"A\"\nwear = { k_d = 1.8e-13, width = 0.1, cells = 100000 }",
        "run.wear_stages = 1000",
    );
}

#[test]
fn transient_window_huge_is_rejected_naming_the_field() {
    rejected(
        "[run]\ntransient_window = 1e300",
        "run.transient_window = 1e300",
    );
}

#[test]
fn body_omega_huge_is_rejected_naming_the_field() {
    rejected(
        "[[bodies]]\nname = \"rod1\"\nomega = 1e300",
        "bodies[0].omega = 1e300",
    );
}

#[test]
fn baumgarte_beta_huge_or_negative_is_rejected_naming_the_field() {
    for beta in ["1e300", "-1e300", "-1.0"] {
        rejected(
            &format!("[solver]\nbaumgarte_beta = {beta}"),
            &format!("solver.baumgarte_beta = {:?}", beta.parse::<f64>().unwrap()),
        );
    }
}

#[test]
fn slider_pose_huge_is_rejected_naming_the_field() {
    rejected(
        "[[bodies]]\nname = \"slide_rod\"\nx = 1e300",
        "bodies[4].x = 1e300",
    );
}

#[test]
fn coulomb_friction_is_rejected_suggesting_ambrosio() {
    let e = rejected(
        "[[clearance_joints]]\nname = \"A\"\nfriction = { law = \"coulomb\", coefficient = 0.1 }",
        "clearance_joints[0].friction.law = \"coulomb\"",
    );
    assert!(e.contains("ambrosio"), "{e}");
}

#[test]
fn pin_outside_its_bearing_is_rejected_naming_the_field() {
    let scene = patched("[[clearance_joints]]\nname = \"A\"\npin_point = [0.57, 0.0]").unwrap();
    let e = check_assembly("t", &scene, &RunOptions::default()).unwrap_err();
    assert!(e.is_bad_input(), "{e}");
    let text = e.to_string();
    assert!(
        text.contains("clearance_joints[0] (A)") && text.contains("outside its bearing"),
        "{text}"
    );
    let e = sim::run_scene("outside", &scene, &Default::default(), &mut ()).unwrap_err();
    assert!(
        matches!(e, RunError::PinOutsideBearing { index: 0, .. }),
        "{e}"
    );
}

#[test]
fn extreme_masses_are_rejected_naming_the_field() {
    rejected(
        "[[bodies]]\nname = \"rod2\"\nmass = 1e-9",
        "bodies[1].mass = 1e-9",
    );
    rejected("[[bodies]]\nname = \"rod2\"\nmass = 1e12", "bodies[1].mass");
}

#[test]
fn atol_velocity_huge_is_rejected_naming_the_field() {
    rejected(
        "[solver]\natol_velocity = 1e300",
        "solver.atol_velocity = 1e300",
    );
    rejected(
        "[solver]\natol_position = 1e-3",
        "solver.atol_position = 0.001",
    );
    // The shipped tolerances pass.
    patched("[solver]\natol_velocity = 1e-5").unwrap();
}

#[test]
fn joint_names_unsafe_in_file_names_are_rejected() {
    for (name, why) in [
        ("x/../../../E", "used in output file names"),
        ("a/b", "used in output file names"),
        ("..", "used in output file names"),
        ("bad\\u0000name", "control characters"),
    ] {
        let e = rejected(
            &format!(
                "[[clearance_joints]]\nname = \"A\"\n[[clearance_joints]]\nname = \"{name}\"\nbearing_body = \"rod3\"\nbearing_point = [0.645, 0.0]\nbearing_radius = 0.05\npin_body = \"rod2\"\npin_point = [0.56, 0.0]\nclearance = 0.0005\nbearing_material = {{ youngs_modulus = 200e9, poisson_ratio = 0.3 }}\npin_material = {{ youngs_modulus = 200e9, poisson_ratio = 0.3 }}\nnormal_law = {{ law = \"hertz\" }}\nfriction = {{ law = \"none\" }}"
            ),
            "clearance_joints[2].name",
        );
        assert!(e.contains(why), "{e}");
    }
    let long = "n".repeat(300);
    rejected(
        &format!(
            "[[drivers]]\nname = \"{long}\"\ntarget = {{ kind = \"body-coordinate\", body = \"slide_rod\", coordinate = \"y\" }}\nlaw = {{ kind = \"constant\", value = 0.0 }}"
        ),
        "at most 64 characters",
    );
}

#[test]
fn extra_array_elements_are_rejected_with_and_without_extends() {
    let text = edited("point = [-0.500, 0.0]", "point = [-0.500, 0.0, 99.0]");
    let e = load_str(&text, "plain", lgres::scenes::BUILTINS)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("exactly two numbers") && e.contains("line"),
        "{e}"
    );
    let e = rejected(
        "[[revolute_joints]]\nname = \"O1\"\npoint = [-0.5, 0.0, 99.0]",
        "revolute_joints[0].point",
    );
    assert!(
        e.contains("exactly two numbers") && e.contains("line 4"),
        "{e}"
    );
}

#[test]
fn extends_empty_array_replaces_the_base_array() {
    let s = load_str(
        "extends = \"slider-crank\"\nclearance_joints = []\n",
        "patch",
        lgres::scenes::BUILTINS,
    )
    .unwrap();
    assert!(s.clearance_joints.is_empty());
}

#[test]
fn extends_can_change_a_law_kind() {
    let s = patched(
        "[[clearance_joints]]\nname = \"A\"\nnormal_law = { law = \"hertz\" }\nfriction = { law = \"none\" }",
    )
    .unwrap();
    assert!(matches!(
        s.clearance_joints[0].normal_law,
        scene::NormalLawParams::Hertz(_)
    ));
}

/// A patch that sets the drive law's `omega` replaces the base's `rpm` (it failed with "give
/// rpm or omega, not both", the base's rpm merged in unseen); giving both in one table is
/// still refused. And a bad `extends` value is shown once quoted, as written.
#[test]
fn extends_patch_choosing_omega_replaces_the_base_rpm() {
    let s = patched("[[drivers]]\nname = \"drive\"\nlaw.omega = 5.0").unwrap();
    assert_eq!(s.drivers[0].law.omega(), Some(5.0));
    rejected(
        "[[drivers]]\nname = \"drive\"\nlaw = { kind = \"harmonic\", offset = 0.895, \
         amplitude = 0.09, rpm = 30.0, omega = 5.0 }",
        "drivers[0].law",
    );
    let e = load_str("extends = \"nope\"\n", "patch", lgres::scenes::BUILTINS)
        .unwrap_err()
        .to_string();
    assert!(e.contains("extends = \"nope\": no built-in"), "{e}");
}

#[test]
fn extends_duplicate_names_in_a_patch_are_rejected() {
    rejected(
        "[[bodies]]\nname = \"rod1\"\nmass = 7.0\n[[bodies]]\nname = \"rod1\"\nmass = 8.0",
        "bodies[1].name = \"rod1\": duplicate name",
    );
}

#[test]
fn extends_type_error_keeps_the_field_path_and_line() {
    let e = rejected(
        "[[bodies]]\nname = \"rod2\"\nmass = \"heavy\"",
        "bodies[1].mass (line 4)",
    );
    assert!(e.contains("invalid type"), "{e}");
}

#[test]
fn extends_merging_twenty_thousand_bodies_finishes_and_is_rejected() {
    // A hang guard, not a timing: the merge is linear, and validation bounds the count.
    let bodies: String = (0..20_000)
        .map(|k| {
            format!("[[bodies]]\nname = \"b{k}\"\nmass = 1.0\ninertia = 1.0\nx = 0.0\ny = 0.0\ntheta_deg = 0.0\n")
        })
        .collect();
    rejected(&bodies, "bodies = 20005: at most 1000");
}

#[test]
fn check_rejects_a_mechanism_missing_a_clearance_joint_like_run() {
    // Joint B removed: the slide rod and the rocker are no longer connected, so the ideal
    // mechanism is not fully driven. `check` must fail as `run` does, as bad input.
    let text = scenes::source("lgres").unwrap();
    let cut = text.find("# Joint B").unwrap();
    let end = text[cut..].find("[solver]").unwrap() + cut;
    let scene = load_str(
        &format!("{}{}", &text[..cut], &text[end..]),
        "no B",
        lgres::scenes::BUILTINS,
    )
    .unwrap();
    let e = check_assembly("t", &scene, &RunOptions::default()).unwrap_err();
    assert!(e.is_bad_input(), "{e}");
    assert!(e.to_string().contains("kinematic analysis"), "{e}");
}

#[test]
fn check_rejects_an_unassemblable_mechanism_naming_the_joints() {
    // Rod 1's ground pin moved far away: the loop cannot close.
    let text = edited("other_point = [0.0, 1.518]", "other_point = [0.0, 5.0]");
    let scene = load_str(&text, "unassemblable", lgres::scenes::BUILTINS).unwrap();
    let e = check_assembly("t", &scene, &RunOptions::default()).unwrap_err();
    assert!(e.is_bad_input(), "{e}");
    let message = e.to_string();
    assert!(!message.contains("[]"), "{message}");
    assert!(
        ["O1", "C", "O3", "D", "P", "drive", "A", "B"]
            .iter()
            .any(|j| message.contains(j)),
        "{message}"
    );
}

#[test]
fn penetration_beyond_half_the_clearance_fails_the_response_run() {
    let scene = scenes::builtin("lgres").unwrap();
    let series = |peak: f64| ContactSeries {
        name: "A".into(),
        clearance: 5e-4,
        penetration: vec![-1e-4, peak, 0.0],
        ..Default::default()
    };
    sim::validity::check_penetration(&scene, "response", &[series(2.4e-4)]).unwrap();
    match sim::validity::check_penetration(&scene, "response", &[series(2.6e-4)]) {
        Err(e @ RunError::PenetrationBeyondLimit { .. }) => {
            let text = e.to_string();
            assert!(
                text.contains("joint A") && text.contains("2.500e-4"),
                "{text}"
            );
            assert!(!e.is_bad_input());
        }
        other => panic!("expected PenetrationBeyondLimit, got {other:?}"),
    }
}

#[test]
fn soft_contact_run_fails_with_penetration_beyond_limit() {
    let scene = patched(
        "[[clearance_joints]]\nname = \"A\"\nbearing_material = { youngs_modulus = 1e6, poisson_ratio = 0.3 }\npin_material = { youngs_modulus = 1e6, poisson_ratio = 0.3 }\n[run]\ncycles = 1\nperiod = 0.2\nwear_stages = 0",
    )
    .unwrap();
    let options = sim::RunOptions::default();
    match sim::run_scene("soft", &scene, &options, &mut ()) {
        Err(RunError::PenetrationBeyondLimit { joint, .. }) => assert_eq!(joint, "A"),
        other => panic!("expected PenetrationBeyondLimit, got {:?}", other.err()),
    }
}

#[test]
fn step_budget_ends_a_run_in_a_failure_naming_the_field() {
    let scene = load_str(
        "extends = \"slider-crank\"\n[solver]\nmax_steps = 10\n",
        "budget",
        lgres::scenes::BUILTINS,
    )
    .unwrap();
    let e = sim::run_scene("budget", &scene, &Default::default(), &mut ()).unwrap_err();
    assert!(!e.is_bad_input());
    assert!(e.to_string().contains("solver.max_steps"), "{e}");
    let scene = load_str(
        "extends = \"slider-crank\"\n[solver]\nmax_wall_time = 1e-12\n",
        "budget",
        lgres::scenes::BUILTINS,
    )
    .unwrap();
    let e = sim::run_scene("budget", &scene, &Default::default(), &mut ()).unwrap_err();
    assert!(e.to_string().contains("solver.max_wall_time"), "{e}");
}

#[test]
fn a_scene_changed_in_code_is_checked_before_a_run_can_take_it() {
    // A library caller can skip `load_str`, but `run_scene` takes a `ValidScene` only: the
    // change is checked and the allocation refused before any run.
    let e = scenes::builtin("lgres")
        .unwrap()
        .edit("code", |s| s.solver.output_interval = 1e-300)
        .unwrap_err();
    assert!(e.to_string().contains("solver.output_interval"), "{e}");
}

/// Issue 35, item 4: every setting that sets how much work a run does, fuzzed over values on
/// both sides of its bound (from the smallest subnormal to the largest finite number): the
/// verdict is the bound's (computed from `scene::limits`), and a refusal names the field.
#[test]
fn work_bounds_hold_over_fuzzed_values() {
    use scene::limits::{
        MAX_CYCLES_PER_STAGE_REPRESENTED, MAX_LENGTH, MAX_SUBSTEPS, MIN_SUBSTEP_FRACTION,
    };
    const MAX_LAYER_MODULUS: f64 = scene::FoundationSpec::MAX_LAYER_MODULUS;
    // Values spread over every decade, and each bound with its neighbours.
    let mut values: Vec<f64> = (-323..=308).step_by(7).map(|e| 10f64.powi(e)).collect();
    for bound in [
        MIN_SUBSTEP_FRACTION,
        MAX_LAYER_MODULUS,
        MAX_LENGTH,
        MAX_CYCLES_PER_STAGE_REPRESENTED,
        1.0,
    ] {
        values.extend([bound, bound * (1.0 - 1e-12), bound * (1.0 + 1e-12)]);
    }
    values.extend([5e-324, f64::MAX]);
    let base = patched("").expect("the default scene loads");
    let k = f64::from(base.run.cycles_per_stage);
    // (field, TOML patch of a value, whether the value is in range).
    type Case = (&'static str, fn(f64) -> String, fn(f64, f64) -> bool);
    let cases: [Case; 10] = [
        (
            "run.max_clearance_change",
            |v| format!("[run]\nmax_clearance_change = {v:e}"),
            |v, _| (MIN_SUBSTEP_FRACTION..=1.0).contains(&v),
        ),
        (
            "run.max_slope_change",
            |v| format!("[run]\nmax_slope_change = {v:e}"),
            |v, _| v >= MIN_SUBSTEP_FRACTION,
        ),
        (
            "run.max_curvature_change",
            |v| format!("[run]\nmax_curvature_change = {v:e}"),
            |v, _| v >= MIN_SUBSTEP_FRACTION,
        ),
        (
            "run.wear_tolerance",
            |v| format!("[run]\nwear_tolerance = {v:e}"),
            |v, _| (MIN_SUBSTEP_FRACTION..=1.0).contains(&v),
        ),
        (
            "run.wear_noise",
            |v| format!("[run]\nwear_noise = {v:e}"),
            |v, _| v > 0.0 && v <= 1.0,
        ),
        (
            "run.forming_clearance_change",
            |v| format!("[run]\nforming_clearance_change = {v:e}"),
            |v, _| (MIN_SUBSTEP_FRACTION..=1.0).contains(&v),
        ),
        (
            "run.forming_depth",
            |v| format!("[run]\nforming_clearance_change = 0.01\nforming_depth = {v:e}"),
            |v, _| v > 0.0 && v <= 1.0,
        ),
        (
            "run.amplification",
            |v| format!("[run]\namplification = {v:e}"),
            |v, k| v > 0.0 && v * k <= MAX_CYCLES_PER_STAGE_REPRESENTED,
        ),
        (
            "contact.width",
            |v| format!("[[clearance_joints]]\nname = \"B\"\ncontact = {{ width = {v:e} }}"),
            |v, _| v > 0.0 && v <= MAX_LENGTH,
        ),
        (
            "contact.layer_modulus",
            |v| {
                format!("[[clearance_joints]]\nname = \"B\"\ncontact = {{ layer_modulus = {v:e} }}")
            },
            |v, _| v > 0.0 && v <= MAX_LAYER_MODULUS,
        ),
    ];
    let mut tried = 0;
    for (field, patch, in_range) in cases {
        for &v in &values {
            tried += 1;
            match patched(&patch(v)) {
                Ok(_) => assert!(in_range(v, k), "{field} = {v:e} accepted"),
                Err(e) => {
                    assert!(!in_range(v, k), "{field} = {v:e} refused: {e}");
                    assert!(e.to_string().contains(field), "{field} not named: {e}");
                }
            }
        }
    }
    for n in [
        0,
        1,
        MAX_SUBSTEPS - 1,
        MAX_SUBSTEPS,
        MAX_SUBSTEPS + 1,
        u32::MAX,
    ] {
        tried += 1;
        let verdict = patched(&format!("[run]\nmax_substeps = {n}"));
        assert_eq!(verdict.is_ok(), (1..=MAX_SUBSTEPS).contains(&n), "{n}");
        if let Err(e) = verdict {
            assert!(e.to_string().contains("run.max_substeps"), "{e}");
        }
    }
    eprintln!("work bounds: {tried} values");
}
