//! One cycle of the bench's sparse configuration (`crates/sim/benches/lgres_cycle.rs`: one 60-rpm cycle of
//! the default scene, rtol 1e-6, both clearance joints, wear accumulation on, output at the end
//! only), once, for an instruction count per step under callgrind:
//!
//! ```sh
//! CARGO_PROFILE_RELEASE_DEBUG=true cargo build --release -p analysis --example cycle_cost
//! valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*measured_cycle*' \
//!     target/release/examples/cycle_cost [surfaces-folder [end-time [scene]]]
//! ```
//!
//! Only `measured_cycle` (the integration, as the bench times it) is counted. With a folder
//! (the `wear_<joint>_stage<k>.csv` files of an earlier run, as `--surfaces` reads them) the
//! cycle runs on those worn surfaces (an empty argument: unworn); a second argument ends the
//! run at that time (s) instead of one period (an empty argument: one period); a third names
//! the scene (a built-in name or a TOML file; default `lgres`). Prints the solver statistics and, for comparing
//! outputs, the final state and worn depths' sums.

use std::path::Path;

use multibody::{Formulation, OutputTimes, SimulationOptions, SimulationResult, State};
use output::surfaces::load_last_stage;
use sim::build::{BuiltScene, Surfaces, build, unworn_joints};
use sim::simulation_options;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let scene = match args.get(2).map(String::as_str) {
        None => lgres::scenes::builtin("lgres")?,
        Some(name) if lgres::scenes::source(name).is_some() => lgres::scenes::builtin(name)?,
        Some(path) => scene::load_path(Path::new(path), lgres::scenes::BUILTINS)?,
    };
    let period = scene.cycle_period().ok_or("the scene is not driven")?;
    let unworn = unworn_joints(&scene)?;
    let worn = match args.first().filter(|dir| !dir.is_empty()) {
        Some(dir) => load_last_stage(Path::new(dir), &scene, &unworn)?,
        None => unworn,
    };
    let end: f64 = match args.get(1).filter(|s| !s.is_empty()) {
        Some(s) => s.parse()?,
        None => period,
    };
    let mut built = build(
        &scene,
        Surfaces {
            worn: &worn,
            split_halves_at: None,
            accumulate_from: Some(0.0),
        },
    )?;
    let (q, qd) = built.system.initial_guess();
    let state = built.system.assemble(0.0, &q, &qd)?;
    let mut options = simulation_options(&scene, end, OutputTimes::At(vec![end]), false);
    options.energy_audit = false;
    options.formulation = Formulation::JointCoordinates;
    let result = measured_cycle(&mut built, &state, &options)?;
    let s = &result.statistics;
    println!(
        "{} steps ({} rejected), {} RHS, {} Jacobians, {} factorizations, {} events",
        s.steps,
        s.rejected_steps,
        s.rhs_evaluations,
        s.jacobian_evaluations,
        s.factorizations,
        s.events
    );
    println!("final q: {:?}", result.final_state.q);
    println!("final qd: {:?}", result.final_state.qd);
    for h in built.joints.iter().filter(|h| h.worn) {
        if let Some(w) = built
            .system
            .element::<clearance::WornClearanceForce>(h.element)
            .and_then(|e| e.stage_wear())
        {
            let sum = |d: &[f64]| d.iter().sum::<f64>();
            println!(
                "wear {}: bearing {:e}, pin {:e}, max {:e}",
                h.name,
                sum(w.bearing()),
                sum(w.pin()),
                w.max_depth()
            );
        }
    }
    Ok(())
}

/// The counted region: the cycle's integration alone.
#[inline(never)]
fn measured_cycle(
    built: &mut BuiltScene,
    state: &State,
    options: &SimulationOptions,
) -> Result<SimulationResult, multibody::SimulationError> {
    built.system.simulate(state, options, &mut ())
}
