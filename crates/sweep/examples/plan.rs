//! Plans a random sweep without running it: the inputs each sample would run with, which
//! depend on the seed and the sample's index only (`cargo run -p sweep --example plan`).

fn main() -> Result<(), sweep::SweepError> {
    let text = r#"
        scene = "slider-crank"
        samples = 5
        seed = 7
        metrics = ["response.joints.rod-slider.max_penetration_m"]
        [run]
        cycles = 1
        [[vary]]
        path = "clearance_joints.rod-slider.clearance"
        distribution = "log-normal"
        median = 5e-4
        sigma = 0.3
    "#;
    let sweep = sweep::Sweep::from_str(text, "example")?;
    for sample in 0..sweep.samples() {
        println!(
            "sample {sample}: clearance {:.3e} m",
            sweep.input_values(sample)[0]
        );
    }
    Ok(())
}
