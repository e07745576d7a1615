//! One integration of a scene (`sim::integrate`): the surfaces, tolerances and step budget it is
//! asked for are the ones it runs with, and its failures carry their kind.

use multibody::{OutputTimes, SimulationErrorKind};
use scene::ValidScene;
use sim::integrate::{ScaledTolerances, StartSurfaces, StepBudget, ideal_motion};
use sim::{Integration, IntegrationErrorKind, integrate};

fn lgres() -> ValidScene {
    lgres::scenes::builtin("lgres").expect("built-in scene")
}

/// 20 ms of the default scene on `surfaces`: the pins drop into their clearances and strike.
fn short(surfaces: StartSurfaces) -> Integration {
    Integration {
        t_end: 0.02,
        output: OutputTimes::At(vec![0.02]),
        energy_audit: false,
        max_steps: StepBudget::Scene,
        tolerances: None,
        surfaces,
    }
}

#[test]
fn wear_is_gathered_only_on_wearing_surfaces() {
    let scene = lgres();
    let wearing = integrate(
        &scene,
        &short(StartSurfaces::Wearing {
            accumulate_from: 0.0,
        }),
        &mut (),
    )
    .expect("integrates");
    let names: Vec<&str> = wearing.joints.iter().map(|j| j.name.as_str()).collect();
    let expected: Vec<&str> = scene
        .active_clearance_joints()
        .map(|c| c.name.as_str())
        .collect();
    assert_eq!(names, expected);
    for joint in &wearing.joints {
        let wear = joint.stage_wear.as_ref().expect("a wearing joint's record");
        assert!(wear.archard_volume() > 0.0, "{}: no wear", joint.name);
        assert!(joint.peak_normal_force.is_some_and(|f| f > 0.0));
    }
    let round = integrate(&scene, &short(StartSurfaces::Round), &mut ()).expect("integrates");
    assert!(round.joints.iter().all(|j| j.stage_wear.is_none()));
    // Frozen worn surfaces gather nothing either, and a wider clearance changes the run.
    let worn = integrate(
        &scene,
        &short(StartSurfaces::UniformlyWorn { factor: 2.0 }),
        &mut (),
    )
    .expect("integrates");
    assert!(worn.joints.iter().all(|j| j.stage_wear.is_none()));
    assert_ne!(worn.result.final_state.q, round.result.final_state.q);
}

#[test]
fn a_step_budget_ends_the_run_with_its_kind() {
    let mut integration = short(StartSurfaces::Round);
    integration.max_steps = StepBudget::Steps(3);
    let e = integrate(&lgres(), &integration, &mut ()).expect_err("three steps are too few");
    let kind = IntegrationErrorKind::Simulation(SimulationErrorKind::StepLimit);
    assert_eq!(e.kind(), kind);
    assert_eq!(kind.name(), "SimulationError::StepLimit");
}

#[test]
fn scaled_tolerances_at_the_scene_rtol_are_the_scene_tolerances() {
    let scene = lgres();
    let own = short(StartSurfaces::Round).simulation_options(&scene);
    let mut scaled = short(StartSurfaces::Round);
    scaled.tolerances = Some(ScaledTolerances {
        integrator: scene.solver.integrator,
        rtol: scene.solver.rtol,
    });
    assert_eq!(scaled.simulation_options(&scene).atol, own.atol);
    scaled.tolerances = Some(ScaledTolerances {
        integrator: scene.solver.integrator,
        rtol: scene.solver.rtol * 10.0,
    });
    let loose = scaled.simulation_options(&scene);
    assert!((loose.atol.position / own.atol.position - 10.0).abs() < 1e-12);
    assert!((loose.atol.velocity / own.atol.velocity - 10.0).abs() < 1e-12);
}

#[test]
fn the_ideal_motion_starts_at_the_scenes_pose() {
    let scene = lgres();
    let body = scene.response_body().expect("a response body");
    let motion = ideal_motion(&scene, &[0.0, 0.01], body).expect("moves");
    assert_eq!(motion.x.len(), 2);
    assert!((motion.x[0] - scene.bodies[body].x).abs() < 1e-3);
    assert!(motion.x[1] != motion.x[0] || motion.y[1] != motion.y[0]);
}

#[test]
fn an_idealized_valid_scene_passes_validation() {
    for builtin in lgres::scenes::BUILTINS {
        let ideal = lgres::scenes::builtin(builtin.name)
            .expect("built-in scene")
            .idealized();
        assert_eq!(ideal.active_clearance_joints().count(), 0);
        ValidScene::new(ideal.into_scene(), builtin.name).expect("still valid");
    }
}
