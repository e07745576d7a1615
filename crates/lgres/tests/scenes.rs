//! Shipped scenes parse, validate and are geometrically consistent; bad input is rejected with
//! the field named.

use lgres::scenes::{self, BUILTINS};
use lgres::studies::STUDIES;
use scene::{self, Coordinate, DriverTarget, Scene, SceneError};

fn issues(err: SceneError) -> Vec<String> {
    match err {
        SceneError::Invalid { issues, .. } => issues.iter().map(ToString::to_string).collect(),
        other => panic!("expected a validation error, got {other}"),
    }
}

/// Scene text loaded against the built-in scenes (the errors name it `t`).
fn load(text: &str) -> Result<scene::ValidScene, SceneError> {
    scene::load_str(text, "t", BUILTINS)
}

/// The issues `load` finds in scene text it must refuse.
fn refused(text: &str) -> Vec<String> {
    issues(load(text).expect_err("must be refused"))
}

/// The default scene's text with `from` replaced by `to` (which must occur).
fn edited(from: &str, to: &str) -> String {
    let text = scenes::source("lgres").unwrap();
    assert!(
        text.contains(from),
        "test fixture: {from:?} not in lgres.toml"
    );
    text.replacen(from, to, 1)
}

/// The default scene's text with `lines` added to its `[run]` table.
fn with_run(lines: &str) -> String {
    edited(
        "transient_window = 0.1",
        &format!("transient_window = 0.1\n{lines}"),
    )
}

fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

#[test]
fn every_builtin_parses_and_validates() {
    for b in BUILTINS {
        let s = scenes::builtin(b.name).unwrap_or_else(|e| panic!("{}: {e}", b.name));
        assert!(!s.description.is_empty() && !s.inertia_convention.is_empty());
    }
    for study in STUDIES {
        for name in study.scenes {
            assert!(scenes::source(name).is_some(), "{}: {name}", study.name);
        }
    }
    assert!(scenes::builtin("nope").is_err());
}

/// Pure geometry: every ideal joint, the concentric clearance joints, the guide and the drive
/// hold at the initial poses to the table's rounding.
#[test]
fn lgres_initial_configuration_satisfies_the_constraints() {
    const TOL: f64 = 1e-4;
    let s = scenes::builtin("lgres").unwrap();
    for j in &s.revolute_joints {
        let a = s.initial_point(&j.body, j.point).unwrap();
        let b = s.initial_point(&j.other, j.other_point).unwrap();
        assert!(distance(a, b) < TOL, "joint {}: {a:?} vs {b:?}", j.name);
    }
    for c in &s.clearance_joints {
        let a = s.initial_point(&c.bearing_body, c.bearing_point).unwrap();
        let b = s.initial_point(&c.pin_body, c.pin_point).unwrap();
        assert!(distance(a, b) < TOL, "joint {} not concentric", c.name);
    }
    // docs/model.md §6 positions of A and B.
    let a = s.initial_point("rod3", [0.645, 0.0]).unwrap();
    assert!(distance(a, [1.28973, 0.02633]) < TOL);
    let b = s.initial_point("rocker", [0.285, 0.0]).unwrap();
    assert!(distance(b, [0.245, 0.575]) < TOL);
    for p in &s.prismatic_joints {
        let q = s.initial_point(&p.body, p.point).unwrap();
        let o = s.initial_point(&p.other, p.other_point).unwrap();
        let [dx, dy] = p.direction;
        let normal_offset = ((q[0] - o[0]) * dy - (q[1] - o[1]) * dx) / dx.hypot(dy);
        assert!(normal_offset.abs() < TOL, "prismatic {}", p.name);
    }
    let slide = s.bodies.iter().find(|b| b.name == "slide_rod").unwrap();
    assert!((slide.theta.deg() - 90.0).abs() < 1e-9);
    let d = &s.drivers[0];
    assert!(matches!(
        &d.target,
        DriverTarget::BodyCoordinate { body, coordinate: Coordinate::Y } if body == "slide_rod"
    ));
    assert!((d.law.eval(0.0)[0] - slide.y).abs() < TOL);
    assert!((s.cycle_period().unwrap() - 1.0).abs() < 1e-12);
    // 15 coordinates − 11 equations; the ideal reference is kinematically driven.
    assert_eq!(s.constraint_count(), 11);
    assert_eq!(s.degrees_of_freedom(), 4);
    assert_eq!(
        scenes::builtin("lgres-ideal").unwrap().degrees_of_freedom(),
        0
    );
    assert_eq!(s.idealized().degrees_of_freedom(), 0);
}

#[test]
fn variants_change_only_what_they_say() {
    let base = scenes::builtin("lgres").unwrap();
    let c02 = scenes::builtin("lgres-c02").unwrap();
    assert!(c02.clearance_joints.iter().all(|c| c.clearance == 2e-4));
    assert_eq!(c02.bodies, base.bodies);
    let fast = scenes::builtin("lgres-105rpm").unwrap();
    assert!((fast.cycle_period().unwrap() - 60.0 / 105.0).abs() < 1e-12);
    assert_eq!(fast.drivers.len(), 1);
    let two = scenes::builtin("lgres-2stages").unwrap();
    assert_eq!(two.run.wear_stages, 2);
    assert_eq!(two.run.cycles_per_stage, 100);
    let printed = scenes::builtin("lgres-printed-inertia").unwrap();
    assert_eq!(printed.bodies[2].inertia, 9.69e-3);
    assert_eq!(printed.bodies[2].mass, base.bodies[2].mass);
    assert_ne!(printed.inertia_convention, base.inertia_convention);
    let ideal = scenes::builtin("lgres-ideal").unwrap();
    assert_eq!(ideal.active_clearance_joints().count(), 0);
}

#[test]
fn default_tolerances_scale_with_the_clearance() {
    let t = scenes::builtin("lgres").unwrap().tolerances();
    assert!((t.position - 1e-7).abs() < 1e-20);
    let t = scenes::builtin("lgres-c02").unwrap().tolerances();
    assert!((t.position - 4e-8).abs() < 1e-20);
}

#[test]
fn scene_round_trips_through_toml() {
    for b in BUILTINS {
        let s = scenes::builtin(b.name).unwrap();
        let again = scene::load_str(&s.to_toml(), "round trip", lgres::scenes::BUILTINS).unwrap();
        // Degrees → radians → degrees may move the last bit of an angle.
        for (x, y) in s.bodies.iter().zip(&again.bodies) {
            assert!((x.theta.rad() - y.theta.rad()).abs() < 1e-14);
        }
        let strip = |mut s: Scene| {
            s.bodies
                .iter_mut()
                .for_each(|b| b.theta = Default::default());
            s
        };
        assert_eq!(
            strip(s.into_scene()),
            strip(again.into_scene()),
            "{}",
            b.name
        );
    }
}

#[test]
fn older_law_spellings_load_as_contacts_own() {
    let old = edited(
        "law = \"hertz-lankarani-nikravesh\", exponent = 1.5, restitution = 0.9, impact_velocity_floor = 1e-4",
        "law = \"lankarani_nikravesh\", exponent = 1.5, restitution = 0.9, onset_velocity_floor = 2e-4",
    );
    let new = edited(
        "v0 = 1e-4, v1 = 1e-3",
        "stick_velocity = 1e-4, slip_velocity = 1e-3",
    );
    let (old, new) = (
        scene::load_str(&old, "old", lgres::scenes::BUILTINS).unwrap(),
        scene::load_str(&new, "new", lgres::scenes::BUILTINS).unwrap(),
    );
    let shipped = lgres::scenes::builtin("lgres").unwrap();
    assert_eq!(new, shipped);
    assert_ne!(old, shipped);
    let scene::NormalLawParams::LankaraniNikravesh(d) = old.clearance_joints[0].normal_law else {
        panic!("{:?}", old.clearance_joints[0].normal_law);
    };
    assert_eq!(d.onset_velocity_floor, 2e-4);
    // What `to_toml` writes is contact's spelling, and it loads again.
    let again = scene::load_str(&shipped.to_toml(), "again", lgres::scenes::BUILTINS).unwrap();
    assert_eq!(again, shipped);
}

#[test]
fn bad_values_name_field_value_and_reason() {
    let text = edited("clearance = 0.0005", "clearance = 0.06");
    let msg = refused(&text);
    assert_eq!(msg.len(), 1, "{msg:?}");
    assert!(msg[0].starts_with("clearance_joints[0].clearance = 0.06: must be smaller"));

    // (the shipped text, its replacement, how the first issue starts)
    let first_issue = [
        ("mass = 6.32", "mass = -1.0", "bodies[0].mass = -1.0"),
        (
            "restitution = 0.9",
            "restitution = 1.2",
            "clearance_joints[0].normal_law.restitution = 1.2: must be in (0, 1]",
        ),
        (
            "v1 = 1e-3",
            "v1 = 1e-5",
            "clearance_joints[0].friction.slip_velocity = 1e-5: must be > stick",
        ),
        (
            "other = \"rod2\"",
            "other = \"rod9\"",
            "revolute_joints[1].other = \"rod9\": no body",
        ),
        ("rpm = 60.0", "rpm = 60.0, omega = 6.0", "drivers[0].law"),
        ("rtol = 1e-6", "rtol = 0.0", "solver.rtol"),
    ];
    for (from, to, start) in first_issue {
        let text = edited(from, to);
        let msg = refused(&text);
        assert!(msg[0].starts_with(start), "{from} → {to}: {msg:?}");
    }

    let text = edited("name = \"rod2\"", "name = \"rod1\"");
    let msg = refused(&text);
    assert!(
        msg.iter()
            .any(|m| m.starts_with("bodies[1].name = \"rod1\": duplicate"))
    );

    let text = edited("x = 0.15441", "x = nan");
    assert!(refused(&text)[0].contains("finite"));
}

#[test]
fn clearance_limit_must_be_positive_and_above_every_initial_clearance() {
    let with = |limit: &str| with_run(&format!("clearance_limit = {limit}"));
    // Below the 0.5 mm of both A and B: one issue per joint, naming the field, value and joint.
    let msg = refused(&with("0.0004"));
    assert_eq!(msg.len(), 2, "{msg:?}");
    for (m, joint) in msg
        .iter()
        .zip(["clearance_joints[0] (A)", "clearance_joints[1] (B)"])
    {
        assert!(
            m.starts_with("run.clearance_limit = 0.0004: must exceed the initial clearance"),
            "{m}"
        );
        assert!(m.contains(joint) && m.contains("0.0005 m"), "{m}");
    }
    // Equal is not above.
    let msg = refused(&with("0.0005"));
    assert_eq!(msg.len(), 2, "{msg:?}");
    let msg = refused(&with("-0.001"));
    assert_eq!(msg, ["run.clearance_limit = -0.001: must be positive"]);
    let msg = refused(&with("inf"));
    assert_eq!(msg, ["run.clearance_limit = inf: must be a finite number"]);
    // A valid limit loads, and survives the round trip through TOML; none is the default.
    let s = load(&with("0.001")).unwrap();
    assert_eq!(s.run.clearance_limit, Some(0.001));
    let again = load(&s.to_toml()).unwrap();
    assert_eq!(again.run.clearance_limit, Some(0.001));
    assert_eq!(scenes::builtin("lgres").unwrap().run.clearance_limit, None);
    assert!(
        !scenes::builtin("lgres")
            .unwrap()
            .to_toml()
            .contains("clearance_limit")
    );
}

#[test]
fn a_run_to_the_limit_needs_the_limit_a_cycle_budget_and_wear() {
    // Each missing piece named, with its field.
    let msg = refused(&with_run("until_limit = true"));
    assert_eq!(msg.len(), 2, "{msg:?}");
    assert!(msg[0].starts_with("run.until_limit = true: needs run.clearance_limit"));
    assert!(
        msg[1].starts_with("run.max_cycles = \"none\": required with run.until_limit"),
        "{msg:?}"
    );
    let msg = refused(&with_run("until_limit = true\nclearance_limit = 0.0008"));
    assert_eq!(msg.len(), 1, "{msg:?}");
    assert!(
        msg[0].starts_with("run.max_cycles = \"none\": required"),
        "{msg:?}"
    );
    // A budget only with the run it bounds; positive, finite, and not too many stages.
    let msg = refused(&with_run("max_cycles = 2e7"));
    assert_eq!(
        msg,
        [
            "run.max_cycles = 20000000.0: only bounds a run with run.until_limit = true (drop it, \
          or set that)"
        ]
    );
    let full = "until_limit = true\nclearance_limit = 0.0008\nmax_cycles = ";
    assert_eq!(
        refused(&with_run(&format!("{full}-1"))),
        ["run.max_cycles = -1.0: must be positive"]
    );
    assert_eq!(
        refused(&with_run(&format!("{full}inf"))),
        ["run.max_cycles = inf: must be a finite number"]
    );
    // 2e6 cycles a stage: 1000 stages at most.
    let msg = refused(&with_run(&format!("{full}3e9")));
    assert_eq!(msg.len(), 1, "{msg:?}");
    assert!(
        msg[0].starts_with("run.max_cycles = 3000000000.0: would take 1500 stages"),
        "{msg:?}"
    );
    // No wear to run on.
    let msg =
        refused(&with_run(&format!("{full}2e7")).replace("wear_stages = 1", "wear_stages = 0"));
    assert!(
        msg.iter()
            .any(|m| m.starts_with("run.until_limit = true: needs wear")),
        "{msg:?}"
    );
    // Valid: loads, survives the round trip; off by default and not written then.
    let s = load(&with_run(&format!(
        "{full}2e7\nk_d_correlation = \"independent\""
    )))
    .unwrap();
    assert!(s.run.until_limit);
    assert_eq!(s.run.max_cycles, Some(2e7));
    assert_eq!(s.run.k_d_correlation, scene::KdCorrelation::Independent);
    let again = load(&s.to_toml()).unwrap();
    assert_eq!(again.run, s.run);
    // Its name in words is the one the file takes.
    let written = format!("k_d_correlation = \"{}\"", s.run.k_d_correlation.name());
    assert!(s.to_toml().contains(&written), "{written}");
    let builtin = scenes::builtin("lgres").unwrap();
    assert!(!builtin.run.until_limit);
    let text = builtin.to_toml();
    for field in [
        "until_limit",
        "max_cycles",
        "k_d_correlation",
        "k_d_scatter",
    ] {
        assert!(!text.contains(field), "{field}");
    }
    // An unknown correlation is refused where it is written, with the ones there are.
    let msg = load(&with_run("k_d_correlation = \"both\""))
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("k_d_correlation") && msg.contains("independent") && msg.contains("shared"),
        "{msg}"
    );
}

#[test]
fn a_wear_coefficients_scatter_is_a_bounded_standard_deviation() {
    let with = |scatter: &str| {
        edited(
            "wear = { k_d = 1.8e-13, hardness = 1.716e9, width = 0.1, cells = 1000 }\n# The same",
            &format!(
                "wear = {{ k_d = 1.8e-13, hardness = 1.716e9, width = 0.1, cells = 1000, \
                 k_d_scatter = {scatter} }}\n# The same"
            ),
        )
    };
    let s = load(&with("0.5")).unwrap();
    let scatter = |s: &scene::Scene, k: usize| s.clearance_joints[k].wear.unwrap().k_d_scatter;
    assert_eq!((scatter(&s, 0), scatter(&s, 1)), (0.5, 0.0));
    assert_eq!(scatter(&load(&s.to_toml()).unwrap(), 0), 0.5);
    assert_eq!(
        refused(&with("-0.1")),
        [
            "clearance_joints[0].wear.k_d_scatter = -0.1: must lie in [0, 3] (the standard \
          deviation of ln k_d; 3 already spreads k_d by a factor of 20 either way)"
        ]
    );
    assert_eq!(refused(&with("4")).len(), 1);
    assert_eq!(
        refused(&with("nan")),
        ["clearance_joints[0].wear.k_d_scatter = NaN: must be a finite number"]
    );
}

#[test]
fn unknown_keys_and_syntax_errors_carry_position() {
    let text = edited("mass = 6.32", "mass = 6.32\nmas = 1.0");
    let msg = load(&text).unwrap_err().to_string();
    assert!(msg.contains("mas") && msg.contains("line"), "{msg}");

    let text = edited("rtol = 1e-6", "rtol = 1e-6\nrtoll = 1.0");
    let msg = load(&text).unwrap_err().to_string();
    assert!(msg.contains("rtoll"), "{msg}");

    let text = edited("law = \"ambrosio\"", "law = \"ambrosia\"");
    assert!(load(&text).is_err());

    let msg = load("description = ").unwrap_err().to_string();
    assert!(msg.contains("line 1"), "{msg}");

    // Unknown keys in a variant are rejected too (no position: the document was merged).
    let msg = load("extends = \"lgres\"\n[run]\ncycle = 3\n")
        .unwrap_err()
        .to_string();
    assert!(msg.contains("cycle"), "{msg}");
}

#[test]
fn extends_merges_by_name_and_rejects_unknown_bases() {
    let s = load("extends = \"lgres\"\n[[clearance_joints]]\nname = \"B\"\nclearance = 3e-4\n")
        .unwrap();
    assert_eq!(s.clearance_joints.len(), 2);
    assert_eq!(s.clearance_joints[0].clearance, 5e-4);
    assert_eq!(s.clearance_joints[1].clearance, 3e-4);
    let err = load("extends = \"nothing\"\n").unwrap_err();
    assert!(matches!(err, SceneError::Extends { .. }), "{err}");
}

#[test]
fn files_extend_files_next_to_them() {
    let dir = std::env::temp_dir().join(format!("lgres-extends-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("base.toml"),
        scenes::source("slider-crank").unwrap(),
    )
    .unwrap();
    std::fs::write(
        dir.join("variant.toml"),
        "extends = \"base.toml\"\n[run]\ncycles = 5\n",
    )
    .unwrap();
    let s = scene::load_path(&dir.join("variant.toml"), lgres::scenes::BUILTINS).unwrap();
    assert_eq!(s.run.cycles, 5);
    assert_eq!(s.bodies.len(), 3);
    std::fs::write(dir.join("loop.toml"), "extends = \"loop.toml\"\n").unwrap();
    assert!(scene::load_path(&dir.join("loop.toml"), lgres::scenes::BUILTINS).is_err());
    assert!(scene::load_path(&dir.join("missing.toml"), lgres::scenes::BUILTINS).is_err());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn slider_crank_counts() {
    let s = scenes::builtin("slider-crank").unwrap();
    assert_eq!(s.degrees_of_freedom(), 2);
    assert!((s.cycle_period().unwrap() - 0.012).abs() < 1e-6);
    for j in &s.revolute_joints {
        let a = s.initial_point(&j.body, j.point).unwrap();
        let b = s.initial_point(&j.other, j.other_point).unwrap();
        assert!(distance(a, b) < 1e-12, "{}", j.name);
    }
}

#[test]
fn contact_model_fields_are_validated_naming_the_field() {
    // Joint A's contact table replaced.
    let with = |contact: &str| {
        edited(
            "contact = { model = \"thin-gap\", cells = 500 }",
            &format!("contact = {contact}"),
        )
    };
    let one = |contact: &str| refused(&with(contact));
    assert_eq!(
        one("{ layer_modulus = -5e14 }"),
        ["clearance_joints[0].contact.layer_modulus = -500000000000000.0: must be positive"]
    );
    let msg = one("{ cells = 1500 }");
    assert!(
        msg[0].starts_with(
            "clearance_joints[0].contact.cells = 1500: must be a whole multiple of wear.cells"
        ),
        "{msg:?}"
    );
    // Coarser nodes that span whole cells are taken, but not with linearly implicit steps.
    let coarse = load(&with("{ cells = 500 }")).unwrap();
    assert_eq!(
        foundation(&coarse.clearance_joints[0].contact).cells,
        Some(500)
    );
    let implicit = with("{ cells = 500 }").replacen(
        "[run]\n",
        "[run]\nwear_stepping = \"linearly-implicit\"\n",
        1,
    );
    let msg = refused(&implicit);
    assert!(
        msg[0].starts_with("clearance_joints[0].contact.cells = 500: run.wear_stepping"),
        "{msg:?}"
    );
    let msg = one("{ cells = 4 }");
    assert!(msg[0].starts_with("clearance_joints[0].contact.cells = 4: must lie in 8.."));
    // Simpson's quadrature (the default) pairs the nodes: an odd count is refused, naming the
    // field it came from; the trapezoid takes it, and the quadrature round-trips.
    let odd_wear = |contact: &str| {
        with(contact).replacen(
            "width = 0.1, cells = 1000 }",
            "width = 0.1, cells = 999 }",
            1,
        )
    };
    let msg = refused(&odd_wear("{}"));
    assert!(
        msg[0].starts_with("clearance_joints[0].wear.cells = 999: Simpson's quadrature"),
        "{msg:?}"
    );
    let msg = one("{ cells = 2001, quadrature = \"simpson\" }");
    assert!(
        msg.iter()
            .any(|m| m.starts_with("clearance_joints[0].contact.cells = 2001: Simpson's")),
        "{msg:?}"
    );
    let trapezoid = load(&odd_wear("{ quadrature = \"trapezoid\" }")).unwrap();
    let model = trapezoid.clearance_joints[0].contact_model().unwrap();
    let contact::ContactModelKind::Foundation(layer) = model else {
        panic!("{model:?}")
    };
    assert_eq!(
        (layer.quadrature(), layer.cells()),
        (contact::Quadrature::Trapezoid, 999)
    );
    let again = load(&trapezoid.to_toml()).unwrap();
    assert_eq!(
        foundation(&again.clearance_joints[0].contact).quadrature,
        Some(contact::Quadrature::Trapezoid)
    );
    // Another model's field is refused when the table is read, naming the field and its line.
    let text = with("{ model = \"line-of-centres\", layer_modulus = 5e14 }");
    let line = 1 + text
        .lines()
        .position(|l| l.contains("layer_modulus = 5e14"))
        .expect("the edited line");
    let err = load(&text).unwrap_err().to_string();
    assert!(
        err.contains("unknown field `layer_modulus`") && err.contains(&format!("line {line}")),
        "{err}"
    );
    // An unknown model is a type error naming the field.
    let err = load(&with("{ model = \"winkler\" }")).unwrap_err();
    assert!(err.to_string().contains("model"), "{err}");
    // A valid layer loads and round-trips; the default scene uses the thin gap.
    let s = load(&with("{ layer_modulus = 8e11, width = 0.1 }")).unwrap();
    assert_eq!(
        foundation(&s.clearance_joints[0].contact).layer_modulus,
        Some(8e11)
    );
    let again = load(&s.to_toml()).unwrap();
    assert_eq!(
        again.clearance_joints[0].contact,
        s.clearance_joints[0].contact
    );
    for joint in &scenes::builtin("lgres").unwrap().clearance_joints {
        assert!(matches!(
            joint.contact_model(),
            Ok(contact::ContactModelKind::ThinGap(_))
        ));
    }
    // The wear smoothing is an angle within [0, 30]°.
    let text = with_run("wear_smoothing_deg = -1.0");
    assert_eq!(
        refused(&text),
        [
            "run.wear_smoothing_deg = -1.0: must lie in [0, 30] degrees (0: no smoothing; a \
          Gaussian wider than a contact zone would erase the wear pattern)"
        ]
    );
}

/// Output files are named after the clearance joints: `A` and `A_worn` would both write
/// `contact_force_A_worn.png` (the run said 26 files and the folder had 24), so the second
/// name is refused, naming both. Names that only share a prefix stay allowed.
#[test]
fn joint_names_whose_files_collide_are_refused() {
    let e = load(&edited("name = \"B\"", "name = \"A_worn\"")).unwrap_err();
    let msg = issues(e);
    assert_eq!(msg.len(), 1, "{msg:?}");
    assert!(
        msg[0].starts_with("clearance_joints[1].name = \"A_worn\": both it and")
            && msg[0].contains("clearance_joints[0].name = \"A\"")
            && msg[0].contains("contact_force_A_worn.png"),
        "{msg:?}"
    );
    assert!(load(&edited("name = \"B\"", "name = \"A_2\"")).is_ok());
}

#[test]
fn wear_tolerance_must_lie_in_the_unit_interval_and_needs_sub_steps() {
    for (bad, reason) in [
        ("0.0", "must be positive"),
        ("-0.1", "must be positive"),
        ("1.5", "must lie in (0, 1]"),
        ("nan", "must be a finite number"),
    ] {
        let msg = issues(load(&with_run(&format!("wear_tolerance = {bad}"))).unwrap_err());
        assert_eq!(msg.len(), 1, "{msg:?}");
        assert!(
            msg[0].starts_with("run.wear_tolerance = ") && msg[0].contains(reason),
            "{msg:?}"
        );
    }
    let text = with_run("wear_tolerance = 0.05").replace(
        "adaptive_extrapolation = true",
        "adaptive_extrapolation = false",
    );
    let msg = refused(&text);
    assert!(
        msg[0].contains("needs run.adaptive_extrapolation = true"),
        "{msg:?}"
    );
    // (Linearly implicit sub-steps need a node per wear cell: A and B on 1000.)
    let one_per_cell =
        |text: String| text.replace("contact = { model = \"thin-gap\", cells = 500 }", "");
    let text = one_per_cell(with_run(
        "wear_tolerance = 0.05\nwear_stepping = \"linearly-implicit\"",
    ));
    let msg = refused(&text);
    assert!(
        msg[0].starts_with("run.wear_tolerance = ") && msg[0].contains("linearly-implicit"),
        "{msg:?}"
    );
    let bad = load(&with_run("wear_stepping = \"backward\"")).unwrap_err();
    assert!(bad.to_string().contains("wear_stepping"), "{bad}");
    let s = load(&one_per_cell(with_run(
        "wear_stepping = \"linearly-implicit\"",
    )))
    .unwrap();
    assert_eq!(s.run.wear_stepping, wear::WearStepping::LinearlyImplicit);
    assert_eq!(
        load(&s.to_toml()).unwrap().run.wear_stepping,
        wear::WearStepping::LinearlyImplicit
    );
    let s = load(&with_run("wear_tolerance = 0.05")).unwrap();
    assert_eq!(s.run.wear_tolerance, Some(0.05));
    assert_eq!(load(&s.to_toml()).unwrap().run.wear_tolerance, Some(0.05));
}

/// The forming bound's two settings: each refused where it would change nothing (a depth
/// without the bound it ends, a bound on the single jump's absent sub-steps), and both kept
/// through the scene's own TOML.
#[test]
fn forming_settings_are_refused_where_they_would_change_nothing() {
    let msg = refused(&with_run("forming_depth = 0.16"));
    assert_eq!(msg.len(), 1, "{msg:?}");
    assert!(
        msg[0].starts_with("run.forming_depth = 0.16")
            && msg[0].contains("without run.forming_clearance_change"),
        "{msg:?}"
    );
    let jump = with_run("forming_clearance_change = 0.0025").replace(
        "adaptive_extrapolation = true",
        "adaptive_extrapolation = false",
    );
    let msg = refused(&jump);
    assert_eq!(msg.len(), 1, "{msg:?}");
    assert!(
        msg[0].starts_with("run.forming_clearance_change = 0.0025")
            && msg[0].contains("needs run.adaptive_extrapolation = true"),
        "{msg:?}"
    );
    let s = load(&with_run(
        "forming_clearance_change = 0.0025\nforming_depth = 0.16",
    ))
    .unwrap();
    let bound = s.run.forming_bound().expect("a forming bound");
    assert_eq!(bound, wear::FormingBound::new(0.0025, 0.16));
    assert_eq!(load(&s.to_toml()).unwrap().run.forming_bound(), Some(bound));
    // Unset depth: the documented default; neither set: no bound, and none written.
    let s = load(&with_run("forming_clearance_change = 0.0025")).unwrap();
    assert_eq!(
        s.run.forming_bound(),
        Some(wear::FormingBound::new(
            0.0025,
            scene::DEFAULT_FORMING_DEPTH
        ))
    );
    let s = load(&with_run("")).unwrap();
    assert_eq!(s.run.forming_bound(), None);
    assert!(!s.to_toml().contains("forming"), "{}", s.to_toml());
}

/// The foundation's fields of a joint's contact (the test fails on another model).
fn foundation(contact: &scene::ContactSpec) -> scene::FoundationSpec {
    let scene::ContactSpec::Foundation(spec) = contact else {
        panic!("not the foundation: {contact:?}")
    };
    *spec
}
