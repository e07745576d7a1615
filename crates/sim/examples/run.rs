//! One short run of the slider-crank with its clearance joint, in memory: the energy it
//! dissipates and how deep its contact goes, and nothing written.
//!
//! ```sh
//! cargo run --release -p sim --example run
//! ```

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // A changed scene is checked again: the run takes only a checked one.
    let scene = lgres::scenes::builtin("slider-crank")?.edit("slider-crank, 2 cycles", |s| {
        s.run.cycles = 2;
        s.run.wear_stages = 0;
        s.run.animation = false;
    })?;
    let outcome = sim::run_scene("slider-crank", &scene, &sim::RunOptions::default(), &mut ())?;
    let response = &outcome.summary.response;
    println!(
        "{}: {} s simulated, {:.3} J dissipated per cycle",
        outcome.summary.scene, response.duration_s, response.dissipated_per_cycle_j
    );
    for joint in &response.joints {
        println!(
            "joint {}: largest penetration {:.3e} m, largest eccentricity {:.3e} m (clearance {:.3e} m)",
            joint.name, joint.max_penetration_m, joint.max_eccentricity_m, joint.clearance_m
        );
    }
    Ok(())
}
