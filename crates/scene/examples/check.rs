//! Loads a scene file (no named scenes to extend) and prints what it holds, or every issue
//! that makes it invalid, naming the field, the value and why:
//!
//! ```sh
//! cargo run -p scene --example check -- my_scene.toml
//! ```

fn main() {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: check SCENE.toml");
        std::process::exit(2);
    };
    match scene::load_path(std::path::Path::new(&path), &[]) {
        Ok(s) => println!(
            "{path}: valid; {} bodies, {} clearance joint(s), {} degrees of freedom",
            s.bodies.len(),
            s.clearance_joints.len(),
            s.degrees_of_freedom()
        ),
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    }
}
