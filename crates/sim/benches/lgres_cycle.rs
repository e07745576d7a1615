//! One 60-rpm drive cycle (1 s simulated) of the default LGRES scene with both clearance
//! joints and wear accumulation on (the configuration of a wear-stage run):
//! `cargo bench -p sim --bench lgres_cycle`. Medians are printed after criterion's lines.
//!
//! - `cycle, wear, sparse output`: output at the end only, no energy audit, no trajectory
//!   (exactly what `run::stages` asks for each simulated cycle);
//! - `cycle, wear, scene output`: output every `solver.output_interval` (1e-4 s: 10 001
//!   frames) with the energy audit on, no trajectory recorded, a do-nothing observer.
//!
//! Each runs in both formulations (`solver.formulation`): `cartesian` (the paper's augmented
//! system) and `joint` (relative coordinates of the ideal joints' tree).
//!
//! Building and assembling the system, and dropping it, are outside the timed region.

#[path = "../../multibody/benches/common/mod.rs"]
mod common;

use common::bench_median;
use criterion::{Criterion, criterion_group, criterion_main};
use multibody::{Formulation, OutputTimes, SimulationOptions, SolverStatistics, State};
use sim::build::{BuiltScene, Surfaces, build, unworn_joints};
use sim::simulation_options;

fn cycle(c: &mut Criterion) {
    let scene = lgres::scenes::builtin("lgres").expect("built-in scene");
    let period = scene.cycle_period().expect("driven scene");
    let unworn = unworn_joints(&scene).expect("wear parameters");
    assert!(unworn.iter().all(Option::is_some), "both joints wear");
    let setup = || -> (BuiltScene, State) {
        let built = build(
            &scene,
            Surfaces {
                worn: &unworn,
                split_halves_at: None,
                accumulate_from: Some(0.0),
            },
        )
        .expect("builds");
        let (q, qd) = built.system.initial_guess();
        let state = built.system.assemble(0.0, &q, &qd).expect("assembles");
        (built, state)
    };
    let mut sparse = simulation_options(&scene, period, OutputTimes::At(vec![period]), false);
    sparse.energy_audit = false;
    let mut dense = simulation_options(
        &scene,
        period,
        OutputTimes::Every(scene.solver.output_interval),
        false,
    );
    dense.energy_audit = true;
    let mut group = c.benchmark_group("lgres");
    for (formulation, name) in [
        (Formulation::Cartesian, "cartesian"),
        (Formulation::JointCoordinates, "joint"),
    ] {
        sparse.formulation = formulation;
        dense.formulation = formulation;
        for (label, options) in [("sparse output", &sparse), ("scene output", &dense)] {
            let (statistics, _) = simulate(options, setup());
            println!(
                "{name}, {label}: {} steps ({} rejected), {} RHS, {} Jacobians, {} factorizations, \
                 {} events",
                statistics.steps,
                statistics.rejected_steps,
                statistics.rhs_evaluations,
                statistics.jacobian_evaluations,
                statistics.factorizations,
                statistics.events
            );
            bench_median(
                &mut group,
                "lgres",
                &format!("cycle, wear, {label}, {name}"),
                10,
                setup,
                |input| simulate(options, input),
            );
        }
    }
    group.finish();
}

/// Runs the built system from its assembled state; returns the statistics and the system (the
/// bench helper drops outputs outside the timed region).
fn simulate(
    options: &SimulationOptions,
    (mut built, state): (BuiltScene, State),
) -> (SolverStatistics, BuiltScene) {
    let result = built
        .system
        .simulate(&state, options, &mut ())
        .expect("simulates");
    (result.statistics, built)
}

criterion_group!(benches, cycle);
criterion_main!(benches);
