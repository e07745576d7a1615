//! The LGRES through all four crates: scene → `sim::build` → `multibody` with `contact`
//! clearance elements and `wear` surfaces. Short runs (a fraction of a drive cycle) so the suite
//! stays fast in release.

use multibody::{OutputTimes, SimulationResult};
use scene::{Scene, ValidScene};
use sim::build::{Surfaces, build, unworn_joints};
use sim::{RunOptions, run_scene, simulation_options};

fn scene(name: &str) -> Scene {
    lgres::scenes::builtin(name)
        .expect("built-in scene")
        .into_scene()
}

/// `scene` as the run takes it: checked.
fn checked(scene: &Scene) -> ValidScene {
    ValidScene::new(scene.clone(), "edited scene").expect("valid scene")
}

fn simulate(scene: &Scene, surfaces: Surfaces<'_>, t_end: f64) -> SimulationResult {
    let mut built = build(&checked(scene), surfaces).expect("builds");
    let (q0, qd0) = built.system.initial_guess();
    let state = built.system.assemble(0.0, &q0, &qd0).expect("assembles");
    let options = simulation_options(scene, t_end, OutputTimes::Every(1e-3), true);
    built
        .system
        .simulate(&state, &options, &mut ())
        .expect("integrates")
}

/// The all-ideal LGRES has 15 equations for 15 coordinates, so integrating its equations of
/// motion must reproduce the kinematic analysis. The difference is integration error plus
/// Baumgarte-controlled drift, amplified by the conditioning of the 15×15 Jacobian (smallest
/// singular value 0.031, docs/model.md §6); with a 1e-9 m position tolerance it measured 3.2e-7 m and
/// 8.5e-6 m/s over 0.3 s, so the bounds 1e-6 m and 1e-4 m/s hold with a 3–10× margin, while a
/// wrong driver, anchor or sign would be off by millimetres.
#[test]
fn ideal_dynamics_match_kinematics() {
    let mut s = scene("lgres-ideal");
    s.solver.atol_position = Some(1e-9);
    s.solver.atol_velocity = 1e-7;
    let result = simulate(&s, Surfaces::default(), 0.3);
    let built = build(&checked(&s), Surfaces::default()).unwrap();
    let (q0, _) = built.system.initial_guess();
    let trajectory = &result.trajectory;
    let kin = built.system.kinematics(&trajectory.times, &q0).unwrap();
    let (mut dq, mut dv) = (0.0f64, 0.0f64);
    for f in 0..trajectory.len() {
        for (a, b) in trajectory.q(f).iter().zip(kin.q(f)) {
            dq = dq.max((a - b).abs());
        }
        for (a, b) in trajectory.qd(f).iter().zip(kin.qd(f)) {
            dv = dv.max((a - b).abs());
        }
    }
    eprintln!("ideal LGRES, dynamics vs kinematics: max |Δq| {dq:e}, max |Δq̇| {dv:e}");
    assert!(dq < 1e-6 && dv < 1e-4, "max |Δq| {dq:e}, max |Δq̇| {dv:e}");

    // The kinematic path of `run_scene` (a scene without active clearance joints) records that
    // analysis for rod 3, which is pinned to ground at the origin 0.645 m from its centroid:
    // its centroid stays on that circle, its velocity is tangent to it, and the recorded
    // velocity and acceleration are the derivatives of the recorded position and velocity
    // (central differences over the 1e-4 s output spacing: error ~ h²·x''' ≈ 1e-8 relative).
    let outcome = run_scene("lgres-ideal", &checked(&s), &RunOptions::default(), &mut ()).unwrap();
    assert!(outcome.summary.response.numerics.is_none());
    let (m, t) = (&outcome.response.motion, &outcome.response.times);
    for k in 1..t.len() - 1 {
        let radius = m.x[k].hypot(m.y[k]);
        assert!(
            (radius - 0.645).abs() < 1e-9,
            "t = {}: |r| = {radius}",
            t[k]
        );
        let radial_speed = (m.x[k] * m.vx[k] + m.y[k] * m.vy[k]) / radius;
        assert!(radial_speed.abs() < 1e-9, "t = {}: {radial_speed}", t[k]);
        let h = t[k + 1] - t[k - 1];
        let speed = m.vx[k].hypot(m.vy[k]).max(1e-3);
        assert!(((m.x[k + 1] - m.x[k - 1]) / h - m.vx[k]).abs() < 1e-5 * speed);
        let accel = m.ax[k].hypot(m.ay[k]).max(1e-2);
        assert!(((m.vy[k + 1] - m.vy[k - 1]) / h - m.ay[k]).abs() < 1e-4 * accel);
    }
    let expected = (f64::from(s.run.cycles) / s.solver.output_interval).round() as usize + 1;
    assert_eq!(outcome.response.times.len(), expected); // 1 s cycles every 1e-4 s
}

/// A short clearance run: the journal centre stays within a few penetration depths of the
/// clearance circle, penetrations stay small against the clearance, nothing is NaN, the energy
/// balance closes.
#[test]
fn short_clearance_run_is_physical() {
    let mut s = scene("lgres");
    s.run.period = Some(0.15); // one "cycle" of 0.15 s: start-up impact and first contacts
    s.run.cycles = 1;
    s.run.wear_stages = 0;
    let outcome = run_scene("lgres-short", &checked(&s), &RunOptions::default(), &mut ()).unwrap();
    let response = &outcome.response;
    assert!(response.times.len() > 1000);
    for c in &response.contact {
        let max_pen = c.penetration.iter().copied().fold(f64::MIN, f64::max);
        let max_e = c.eccentricity.iter().copied().fold(0.0, f64::max);
        assert!(max_pen > 0.0, "joint {} never touched", c.name);
        assert!(
            max_pen < 0.2 * c.clearance,
            "joint {}: δ {max_pen:e}",
            c.name
        );
        assert!(
            max_e <= c.clearance + 3.0 * max_pen,
            "joint {}: |e| {max_e:e}",
            c.name
        );
        assert!(c.normal_force.iter().all(|f| f.is_finite() && *f >= 0.0));
    }
    for series in response.motion.series() {
        assert!(series.iter().all(|v| v.is_finite()));
    }
    let n = outcome.summary.response.numerics.as_ref().unwrap();
    assert!(n.energy_relative_residual.abs() < 1e-3, "{n:?}");
    assert!(n.drift_position < 1e-5, "{n:?}");
    // Contacts dissipate: friction is part of the total.
    let r = &outcome.summary.response;
    assert!(r.friction_per_cycle_j > 0.0 && r.dissipated_per_cycle_j > r.friction_per_cycle_j);
}

/// Unworn worn-surfaces give exactly the round surfaces' forces (radius `R ± 0/2`, slope 0), and
/// wear accumulation only reads accepted states, so wear on during the first stage must not
/// change a single bit of the trajectory.
#[test]
fn wear_on_first_stage_is_bitwise_wear_off() {
    let s = scene("lgres");
    let t_end = 0.12;
    let off = simulate(&s, Surfaces::default(), t_end);
    let unworn = unworn_joints(&s).unwrap();
    assert!(unworn.iter().all(Option::is_some));
    let on = simulate(
        &s,
        Surfaces {
            worn: &unworn,
            accumulate_from: Some(0.0),
            split_halves_at: None,
        },
        t_end,
    );
    assert_eq!(off.trajectory.times, on.trajectory.times);
    assert!(off.trajectory.q == on.trajectory.q, "positions differ");
    assert!(off.trajectory.qd == on.trajectory.qd, "velocities differ");
    assert_eq!(off.statistics.steps, on.statistics.steps);
}

/// The wear buffer fills on accepted steps of a worn joint, and only after its start time.
#[test]
fn stage_wear_accumulates_after_its_start() {
    let s = scene("lgres");
    let unworn = unworn_joints(&s).unwrap();
    let depth = |from: f64| {
        let mut built = build(
            &checked(&s),
            Surfaces {
                worn: &unworn,
                accumulate_from: Some(from),
                split_halves_at: None,
            },
        )
        .unwrap();
        let (q0, qd0) = built.system.initial_guess();
        let state = built.system.assemble(0.0, &q0, &qd0).unwrap();
        let options = simulation_options(&s, 0.1, OutputTimes::Every(0.01), false);
        built.system.simulate(&state, &options, &mut ()).unwrap();
        let id = built.joints[1].element;
        let force = built
            .system
            .element::<clearance::WornClearanceForce>(id)
            .unwrap();
        force.stage_wear().unwrap().max_depth()
    };
    let all = depth(0.0);
    assert!(all > 0.0);
    assert!(depth(0.05) < all);
    assert_eq!(depth(1.0), 0.0);
}
