//! The shipped scenes, embedded in the binary (the paper's studies list them: [`crate::studies`]).
//!
//! Variants are small TOML files that `extends = "lgres"` and override a few values (see
//! the `scene` crate), so the reconstructed geometry lives in `scenes/lgres.toml` only. The
//! scene loaders resolve names against [`BUILTINS`]: `scene::load_path(path, BUILTINS)`.

use scene::{Builtin, SceneError, ValidScene};

macro_rules! builtin {
    ($name:literal, $summary:literal) => {
        Builtin {
            name: $name,
            summary: $summary,
            source: include_str!(concat!("../scenes/", $name, ".toml")),
        }
    };
}

/// Every shipped scene; the first is the default.
pub const BUILTINS: &[Builtin] = &[
    builtin!(
        "lgres",
        "LGRES of the paper: A and B with 0.5 mm clearance, 60 rpm, one wear stage"
    ),
    builtin!("lgres-c02", "LGRES with 0.2 mm initial clearance"),
    builtin!("lgres-45rpm", "LGRES driven at 45 rpm"),
    builtin!("lgres-105rpm", "LGRES driven at 105 rpm"),
    builtin!("lgres-2stages", "LGRES with two wear stages"),
    builtin!(
        "lgres-printed-inertia",
        "LGRES with Table 1's printed inertias (x1e-3 kg m^2)"
    ),
    builtin!(
        "lgres-paper",
        "LGRES with the paper's wear formulation (delta*phi_dot sliding, K = 100, one jump)"
    ),
    builtin!(
        "lgres-paper-2stages",
        "LGRES, paper's wear formulation, two wear stages"
    ),
    builtin!(
        "lgres-paper-c02",
        "LGRES, paper's wear formulation, 0.2 mm initial clearance"
    ),
    builtin!(
        "lgres-paper-45rpm",
        "LGRES, paper's wear formulation, 45 rpm"
    ),
    builtin!(
        "lgres-paper-105rpm",
        "LGRES, paper's wear formulation, 105 rpm"
    ),
    builtin!(
        "lgres-elastic",
        "LGRES with elastic, frictionless contact (energy check on worn surfaces)"
    ),
    builtin!(
        "lgres-ideal",
        "LGRES with ideal joints A and B (reference mechanism)"
    ),
    builtin!(
        "slider-crank",
        "Slider-crank with a rod-slider clearance joint (Flores benchmark)"
    ),
];

/// Name of the default scene.
pub const DEFAULT: &str = "lgres";

/// The TOML text of a built-in scene.
pub fn source(name: &str) -> Option<&'static str> {
    scene::source(BUILTINS, name)
}

/// A built-in scene, parsed and validated.
pub fn builtin(name: &str) -> Result<ValidScene, SceneError> {
    scene::builtin(BUILTINS, name)
}
