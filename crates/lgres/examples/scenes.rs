//! The shipped scenes and the paper's studies, with each scene's mechanism in a line:
//!
//! ```sh
//! cargo run -p lgres --example scenes
//! ```

fn main() -> Result<(), scene::SceneError> {
    for b in lgres::scenes::BUILTINS {
        let scene = lgres::scenes::builtin(b.name)?;
        println!(
            "{:<22} {} bodies, {} clearance joint(s), {} degrees of freedom: {}",
            b.name,
            scene.bodies.len(),
            scene.clearance_joints.len(),
            scene.degrees_of_freedom(),
            b.summary
        );
    }
    println!();
    for study in lgres::studies::STUDIES {
        println!(
            "{:<18} {}: {}",
            study.name,
            study.scenes.join(" vs "),
            study.summary
        );
    }
    Ok(())
}
