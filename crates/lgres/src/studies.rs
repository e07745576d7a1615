//! The paper's studies (Sec. 4.2) as lists of shipped scenes ([`crate::scenes`]), and the
//! names under which the paper files its numbers ([`physical_counterpart`]).

/// One of the paper's studies (Sec. 4.2): the scenes it runs, each compared with its
/// `Scene::idealized` reference.
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
