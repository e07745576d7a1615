//! A contact model added the way docs/architecture.md says — one module of `contact`
//! implementing `ContactModel` plus its scene value — runs a scene end to end: the test model
//! `linear-spring` on the elastic LGRES. The run, its energy audit and its validity ask the
//! model, not a flag: the verdict names the model and judges the one measure it names, and an
//! undamped, frictionless spring neither dissipates nor creates energy.

use scene::{ContactModelName, ContactSpec, ValidScene};
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
        joint.contact = ContactSpec {
            model: ContactModelName::LinearSpring,
            stiffness: Some(STIFFNESS),
            ..ContactSpec::default()
        };
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

#[test]
fn the_scene_value_refuses_what_the_model_does_not_take() {
    let base = lgres::scenes::builtin("lgres-elastic")
        .expect("built-in")
        .into_scene();
    let with = |contact: ContactSpec| {
        let mut scene = base.clone();
        scene.clearance_joints[0].contact = contact;
        scene
            .validate("lgres-elastic")
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default()
    };
    let missing = with(ContactSpec {
        model: ContactModelName::LinearSpring,
        ..ContactSpec::default()
    });
    assert!(
        missing.contains("stiffness") && missing.contains("needs"),
        "{missing}"
    );
    let layer = with(ContactSpec {
        model: ContactModelName::LinearSpring,
        stiffness: Some(STIFFNESS),
        layer_modulus: Some(1e14),
        ..ContactSpec::default()
    });
    assert!(layer.contains("model = \"linear-spring\""), "{layer}");
    let elsewhere = with(ContactSpec {
        stiffness: Some(STIFFNESS),
        ..ContactSpec::default()
    });
    assert!(
        elsewhere.contains("only the linear-spring model takes it"),
        "{elsewhere}"
    );
    let negative = with(ContactSpec {
        model: ContactModelName::LinearSpring,
        stiffness: Some(-1.0),
        ..ContactSpec::default()
    });
    assert!(negative.contains("stiffness"), "{negative}");
    let mut worn = base.clone();
    let joint = &mut worn.clearance_joints[0];
    joint.contact = ContactSpec {
        model: ContactModelName::LinearSpring,
        stiffness: Some(STIFFNESS),
        ..ContactSpec::default()
    };
    assert!(joint.wear.is_some(), "a wear table to refuse");
    let refused = worn
        .validate("lgres-elastic")
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(refused.contains("round surfaces only"), "{refused}");
    let absurd = with(ContactSpec {
        model: ContactModelName::LinearSpring,
        stiffness: Some(1e20),
        ..ContactSpec::default()
    });
    assert!(
        absurd.contains("contact.stiffness") && absurd.contains("N/m"),
        "{absurd}"
    );
}
