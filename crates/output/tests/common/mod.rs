//! What the output tests share: a fresh folder per test, a scene run from its text, and the
//! short worn slider-crank most of them write.

#![allow(dead_code)]

use std::path::PathBuf;

use sim::RunOutcome;

/// An empty folder `lgres-<test>-<tag>-<pid>` under the system's temporary folder.
pub fn temp_dir(test: &str, tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lgres-{test}-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The scene `text` (built-ins resolvable), run in memory under `name`.
pub fn run(text: &str, name: &str) -> RunOutcome {
    let scene = scene::load_str(text, name, lgres::scenes::BUILTINS).unwrap();
    sim::run_scene(name, &scene, &Default::default(), &mut ()).unwrap()
}

/// The slider-crank with a wearing rod-slider joint: `cycles` response cycles, `stages` wear
/// stages of K = 2 cycles, each standing for 1 500 cycles; `extra` lines go before the joint
/// (top-level fields) and `run_extra` at the end of `[run]`.
pub fn worn_slider_crank(extra: &str, cycles: u32, stages: u32, run_extra: &str) -> String {
    format!(
        "extends = \"slider-crank\"\n{extra}[[clearance_joints]]\nname = \"rod-slider\"\n\
         wear = {{ k_d = 1.8e-13, width = 0.02, cells = 360 }}\n[run]\ncycles = {cycles}\n\
         wear_stages = {stages}\ncycles_per_stage = 2\namplification = 750.0\n{run_extra}"
    )
}
