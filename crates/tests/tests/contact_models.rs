//! A contact model added the way docs/architecture.md says — one module of `contact`
//! implementing `ContactModel` plus its scene value — runs a scene end to end: the test model
//! `linear-spring` on the elastic LGRES. The run, its energy audit and its validity ask the
//! model, not a flag: the verdict names the model and judges the one measure it names, and an
//! undamped, frictionless spring neither dissipates nor creates energy.

use scene::{LinearSpringSpec, ValidScene};
use sim::{RunOptions, run_scene};

/// A stiffness of the order of the Hertz law's secant at the start-up impacts (~30 kN at
/// ~30 µm).
const STIFFNESS: f64 = 1e9;

#[test]
fn the_test_model_runs_a_scene_from_its_scene_value() {
    let mut scene = lgres::scenes::builtin("lgres-elastic")
        .expect("built-in")
        .into_scene();
    scene.run.cycles = 1;
    scene.run.wear_stages = 0;
    for joint in &mut scene.clearance_joints {
        joint.contact = LinearSpringSpec {
            stiffness: STIFFNESS,
        }
        .into();
        // Exact on round surfaces only: the test model takes no wear.
        joint.wear = None;
        assert!(
            joint
                .contact_description()
                .starts_with("linear-spring contact"),
            "{}",
            joint.contact_description()
        );
    }
    let scene = ValidScene::new(scene, "lgres-elastic").expect("a valid scene");
    let outcome =
        run_scene("lgres-elastic", &scene, &RunOptions::default(), &mut ()).expect("runs");
    let r = &outcome.summary.response;
    eprintln!(
        "elastic LGRES on the linear spring: dissipated {:.2e} J per cycle (A {:.2e}, B {:.2e}); \
         peaks A {:.1} kN, B {:.1} kN",
        r.dissipated_per_cycle_j,
        r.joints[0].contact_dissipation_per_cycle_j,
        r.joints[1].contact_dissipation_per_cycle_j,
        r.joints[0].normal_force_all.max / 1e3,
        r.joints[1].normal_force_all.max / 1e3,
    );
    // The same bound as the worn foundation's and line of centres' elastic check: 0.05 J per
    // cycle against stored energies of joules per impact.
    assert!(r.dissipated_per_cycle_j.abs() < 0.05, "{r:?}");
    assert_eq!(r.damping_per_cycle_j, 0.0);
    assert_eq!(r.friction_per_cycle_j, 0.0);
    assert!(r.energy_warnings.is_empty(), "{:?}", r.energy_warnings);
    for j in &r.joints {
        assert!(j.normal_force_all.max > 0.0, "{} carried no load", j.name);
        let v = j.validity.as_ref().expect("measured");
        assert_eq!(v.model, "linear-spring");
        assert!(v.loaded_frames > 0, "{v:?}");
        // Round surfaces: the one measure it names is zero, the foundation's are not taken.
        assert_eq!(v.max_slope_ratio, 0.0);
        assert_eq!(v.max_overlap_ratio, 0.0);
        assert_eq!(v.overlap_frames, 0);
        assert!(v.inside, "{v:?}");
    }
}

/// The scene value takes the model's own fields only: serde refuses another model's field
/// or a missing one by name, validation a value the model or the joint cannot take.
#[test]
fn the_scene_value_refuses_what_the_model_does_not_take() {
    let parsed = |contact: &str| {
        scene::load_str(
            &format!(
                "extends = \"lgres-elastic\"\n[[clearance_joints]]\nname = \"A\"\n\
                 contact = {{ {contact} }}\n"
            ),
            "patch",
            lgres::scenes::BUILTINS,
        )
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default()
    };
    let missing = parsed("model = \"linear-spring\"");
    assert!(
        missing.contains("clearance_joints[0].contact")
            && missing.contains("missing field `stiffness`"),
        "{missing}"
    );
    let layer = parsed(&format!(
        "model = \"linear-spring\", stiffness = {STIFFNESS:e}, layer_modulus = 1e14"
    ));
    assert!(layer.contains("unknown field `layer_modulus`"), "{layer}");
    let elsewhere = parsed(&format!("stiffness = {STIFFNESS:e}"));
    assert!(
        elsewhere.contains("unknown field `stiffness`"),
        "{elsewhere}"
    );
    let unknown = parsed("model = \"springy\"");
    assert!(
        unknown.contains("unknown variant `springy`") && unknown.contains("linear-spring"),
        "{unknown}"
    );

    let base = lgres::scenes::builtin("lgres-elastic")
        .expect("built-in")
        .into_scene();
    let with = |stiffness: f64, keep_wear: bool| {
        let mut scene = base.clone();
        let joint = &mut scene.clearance_joints[0];
        joint.contact = LinearSpringSpec { stiffness }.into();
        if !keep_wear {
            joint.wear = None;
        }
        scene
            .validate("lgres-elastic")
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default()
    };
    assert_eq!(with(STIFFNESS, false), "");
    let negative = with(-1.0, false);
    assert!(
        negative.contains("contact.stiffness = -1.0: must be positive"),
        "{negative}"
    );
    assert!(
        base.clearance_joints[0].wear.is_some(),
        "a wear table to refuse"
    );
    let refused = with(STIFFNESS, true);
    assert!(refused.contains("round surfaces only"), "{refused}");
    let absurd = with(1e20, false);
    assert!(
        absurd.contains("contact.stiffness") && absurd.contains("N/m"),
        "{absurd}"
    );
}
