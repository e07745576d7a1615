//! The shipped scenes, embedded in the binary, and the paper's studies as lists of them.
//!
//! Variants are small TOML files that `extends = "lgres"` and override a few values (see
//! the `scene` crate), so the reconstructed geometry lives in `scenes/lgres.toml` only. The
//! scene loaders resolve names against [`BUILTINS`]: `scene::load_path(path, BUILTINS)`.

use scene::{Builtin, Scene, SceneError};

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
pub fn builtin(name: &str) -> Result<Scene, SceneError> {
    scene::builtin(BUILTINS, name)
}

/// One of the paper's studies (Sec. 4.2): the scenes it runs, each compared with its
/// [`Scene::idealized`] reference.
#[derive(Debug, Clone, Copy)]
pub struct Study {
    /// Name used on the command line.
    pub name: &'static str,
    /// What it shows.
    pub summary: &'static str,
    /// Built-in scene names, in the order the paper presents them.
    pub scenes: &'static [&'static str],
}

/// The paper's studies.
pub const STUDIES: &[Study] = &[
    Study {
        name: "wear-stages",
        summary: "0.5 mm, 60 rpm, one and two wear stages (Sec. 4.2.1)",
        scenes: &["lgres", "lgres-2stages"],
    },
    Study {
        name: "clearance",
        summary: "0.2 and 0.5 mm initial clearance, 60 rpm, one stage (Sec. 4.2.2)",
        scenes: &["lgres-c02", "lgres"],
    },
    Study {
        name: "speed",
        summary: "45 and 105 rpm, 0.5 mm, one stage (Sec. 4.2.3)",
        scenes: &["lgres-45rpm", "lgres-105rpm"],
    },
    Study {
        name: "wear-stages-paper",
        summary: "the paper's wear formulation (wear on δφ̇, K = 100, one jump ×20 000): one \
                  and two wear stages",
        scenes: &["lgres-paper", "lgres-paper-2stages"],
    },
    Study {
        name: "clearance-paper",
        summary: "the paper's wear formulation: 0.2 and 0.5 mm initial clearance",
        scenes: &["lgres-paper-c02", "lgres-paper"],
    },
    Study {
        name: "speed-paper",
        summary: "the paper's wear formulation: 45 and 105 rpm",
        scenes: &["lgres-paper-45rpm", "lgres-paper-105rpm"],
    },
];

/// The physical-formulation study a paper-formulation study mirrors (`clearance-paper` →
/// `clearance`), and the scene a paper-formulation scene mirrors (`lgres-paper-c02` →
/// `lgres-c02`): the paper's numbers are filed under those. Other names map to themselves.
pub fn physical_counterpart(name: &str) -> String {
    if let Some(study) = name.strip_suffix("-paper") {
        return study.to_string();
    }
    match name.strip_prefix("lgres-paper") {
        Some(variant) => format!("lgres{variant}"),
        None => name.to_string(),
    }
}

/// A study by name.
pub fn study(name: &str) -> Option<&'static Study> {
    STUDIES.iter().find(|s| s.name == name)
}
