//! Runs a scene and draws its animations, printing their size and encoding time.
//!
//! ```sh
//! cargo run --release -p output --example animation -- lgres /tmp/anim 2 0
//! ```
//!
//! Arguments: a built-in scene name or a scene file, the output folder, the response run's
//! cycles (default 2) and the wear stages (default 0; with stages, also the worn response's
//! animation, on `K = 2` simulated cycles per stage).

use std::path::PathBuf;
use std::time::Instant;

use output::animation::write_animation;
use sim::RunOptions;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let name = args.first().map_or("lgres", String::as_str);
    let out = PathBuf::from(args.get(1).map_or("out/animation", String::as_str));
    let scene = match lgres::scenes::builtin(name) {
        Ok(scene) => scene,
        Err(_) => scene::load_path(name.as_ref(), lgres::scenes::BUILTINS)?,
    };
    let cycles = args.get(2).map_or(Ok(2), |s| s.parse())?;
    let stages = args.get(3).map_or(Ok(0), |s| s.parse())?;
    let scene = scene.edit(&format!("{name}, {cycles} cycles"), |s| {
        s.run.cycles = cycles;
        s.run.wear_stages = stages;
    })?;
    let options = RunOptions {
        cycles_per_stage: Some(2),
        ..RunOptions::default()
    };
    let started = Instant::now();
    let outcome = sim::run_scene(name, &scene, &options, &mut ())?;
    println!("run: {:.1} s", started.elapsed().as_secs_f64());
    let mut responses = vec![("mechanism.gif", &outcome.response, &[][..], "")];
    if let Some(worn) = &outcome.worn_response {
        responses.push(("mechanism_worn.gif", worn, &outcome.wear[..], ", worn"));
    }
    for (file, response, wear, label) in responses {
        let started = Instant::now();
        let title = format!("{name}: one drive cycle after the start-up window{label}");
        let info = write_animation(&out.join(file), &outcome.scene, response, wear, &title)?;
        println!(
            "{file}: {} frames, {:.2} MB, {:.2} s, magnification {:?}",
            info.frames,
            info.bytes as f64 / 1e6,
            started.elapsed().as_secs_f64(),
            info.magnification
        );
    }
    Ok(())
}
