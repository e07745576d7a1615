//! The paper's studies (Sec. 4.2) as values: the shipped scenes each runs ([`crate::scenes`]),
//! the trend the paper claims for them ([`Claim`]) and, for a study in the paper's wear
//! formulation, the physical-formulation study it mirrors ([`Mirror`]), under whose study and
//! scene names the paper's numbers are filed ([`crate::paper`]); and the study of the paper's
//! wear extrapolation ([`EXTRAPOLATION`]).

use crate::claim::{Cases, Claim, Direction, ResponseMeasure, WearMeasure};

/// One of the paper's studies (Sec. 4.2): the scenes it runs, each compared with its
/// `Scene::idealized` reference, and the trend judged on them.
#[derive(Debug, Clone, Copy)]
pub struct Study {
    /// Name used on the command line.
    pub name: &'static str,
    /// What it shows.
    pub summary: &'static str,
    /// Built-in scene names, in the order the paper presents them.
    pub scenes: &'static [&'static str],
    /// The trend the paper states, judged on these scenes.
    pub claim: Claim,
    /// The physical-formulation study this one mirrors (`None`: a physical study).
    pub mirror: Option<Mirror>,
}

/// The physical-formulation study a paper-formulation study mirrors: the paper's numbers are
/// filed under its study and scene names.
#[derive(Debug, Clone, Copy)]
pub struct Mirror {
    /// The mirrored study.
    pub study: &'static Study,
    /// Each scene of the mirroring study with the scene of `study` it stands for.
    pub scenes: &'static [(&'static str, &'static str)],
}

impl Study {
    /// The name the paper files this study's numbers under: its mirror's, or its own.
    pub fn paper_name(&self) -> &'static str {
        self.mirror.map_or(self.name, |m| m.study.name)
    }

    /// The scene of this study standing for `paper_scene`, a scene the paper's numbers are
    /// filed under (see [`Study::paper_name`]).
    pub fn scene_for(&self, paper_scene: &str) -> Option<&'static str> {
        match self.mirror {
            Some(mirror) => mirror
                .scenes
                .iter()
                .find(|(_, theirs)| *theirs == paper_scene)
                .map(|(ours, _)| *ours),
            None => self.scenes.iter().find(|s| **s == paper_scene).copied(),
        }
    }
}

/// What the scene-against-scene claims compare of the responses.
const RESPONSE: &[ResponseMeasure] = &[
    ResponseMeasure::PeakForce,
    ResponseMeasure::Deviation,
    ResponseMeasure::Dissipation,
];
/// What the scene-against-scene claims compare of the wear.
const SPREAD_WEAR: &[WearMeasure] = &[WearMeasure::Volume, WearMeasure::Arc];

/// One and two wear stages (Sec. 4.2.1).
pub const WEAR_STAGES: Study = Study {
    name: "wear-stages",
    summary: "0.5 mm, 60 rpm, one and two wear stages (Sec. 4.2.1)",
    scenes: &["lgres", "lgres-2stages"],
    claim: Claim {
        trend: "second wear stage → deeper and more irregular wear than the first",
        cases: Cases::Stages {
            scene: "lgres-2stages",
            first: 1,
            second: 2,
        },
        wear: &[
            WearMeasure::PeakDepth,
            WearMeasure::DepthVariation,
            WearMeasure::ConcentratedRanges,
        ],
        direction: Direction::Grows,
    },
    mirror: None,
};

/// Two initial clearances (Sec. 4.2.2).
pub const CLEARANCE: Study = Study {
    name: "clearance",
    summary: "0.2 and 0.5 mm initial clearance, 60 rpm, one stage (Sec. 4.2.2)",
    scenes: &["lgres-c02", "lgres"],
    claim: Claim {
        trend: "larger clearance → larger forces, deviations, dissipation and wear over a wider arc",
        cases: Cases::Scenes {
            first: "lgres-c02",
            second: "lgres",
            response: RESPONSE,
        },
        wear: SPREAD_WEAR,
        direction: Direction::Grows,
    },
    mirror: None,
};

/// Two drive speeds (Sec. 4.2.3).
pub const SPEED: Study = Study {
    name: "speed",
    summary: "45 and 105 rpm, 0.5 mm, one stage (Sec. 4.2.3)",
    scenes: &["lgres-45rpm", "lgres-105rpm"],
    claim: Claim {
        trend: "faster drive → larger forces, deviations, dissipation and wear over a wider arc",
        cases: Cases::Scenes {
            first: "lgres-45rpm",
            second: "lgres-105rpm",
            response: RESPONSE,
        },
        wear: SPREAD_WEAR,
        direction: Direction::Grows,
    },
    mirror: None,
};

/// [`WEAR_STAGES`] in the paper's wear formulation.
pub const WEAR_STAGES_PAPER: Study = Study {
    name: "wear-stages-paper",
    summary: "the paper's wear formulation (wear on δφ̇, K = 100, one jump ×20 000): one \
              and two wear stages",
    scenes: &["lgres-paper", "lgres-paper-2stages"],
    claim: Claim {
        cases: Cases::Stages {
            scene: "lgres-paper-2stages",
            first: 1,
            second: 2,
        },
        ..WEAR_STAGES.claim
    },
    mirror: Some(Mirror {
        study: &WEAR_STAGES,
        scenes: &[
            ("lgres-paper", "lgres"),
            ("lgres-paper-2stages", "lgres-2stages"),
        ],
    }),
};

/// [`CLEARANCE`] in the paper's wear formulation.
pub const CLEARANCE_PAPER: Study = Study {
    name: "clearance-paper",
    summary: "the paper's wear formulation: 0.2 and 0.5 mm initial clearance",
    scenes: &["lgres-paper-c02", "lgres-paper"],
    claim: Claim {
        cases: Cases::Scenes {
            first: "lgres-paper-c02",
            second: "lgres-paper",
            response: RESPONSE,
        },
        ..CLEARANCE.claim
    },
    mirror: Some(Mirror {
        study: &CLEARANCE,
        scenes: &[("lgres-paper-c02", "lgres-c02"), ("lgres-paper", "lgres")],
    }),
};

/// [`SPEED`] in the paper's wear formulation.
pub const SPEED_PAPER: Study = Study {
    name: "speed-paper",
    summary: "the paper's wear formulation: 45 and 105 rpm",
    scenes: &["lgres-paper-45rpm", "lgres-paper-105rpm"],
    claim: Claim {
        cases: Cases::Scenes {
            first: "lgres-paper-45rpm",
            second: "lgres-paper-105rpm",
            response: RESPONSE,
        },
        ..SPEED.claim
    },
    mirror: Some(Mirror {
        study: &SPEED,
        scenes: &[
            ("lgres-paper-45rpm", "lgres-45rpm"),
            ("lgres-paper-105rpm", "lgres-105rpm"),
        ],
    }),
};

/// The paper's studies, in the order they run and are reported.
pub const STUDIES: &[Study] = &[
    WEAR_STAGES,
    CLEARANCE,
    SPEED,
    WEAR_STAGES_PAPER,
    CLEARANCE_PAPER,
    SPEED_PAPER,
];

/// The study of the paper's wear extrapolation: one wear stage of a scene extrapolated in
/// adaptive sub-steps against the same stage in the paper's single jump. It states no trend of
/// the paper's: it shows what the single jump does to the worn profile.
#[derive(Debug, Clone, Copy)]
pub struct ExtrapolationStudy {
    /// Name used on the command line.
    pub name: &'static str,
    /// What it shows.
    pub summary: &'static str,
    /// The scene (built-in name), run as it is: adaptive sub-steps.
    pub scene: &'static str,
    /// Key of the run of `scene` with the paper's single jump (`run.adaptive_extrapolation =
    /// false`), under which its files are written; no built-in scene has this name.
    pub single_jump_run: &'static str,
}

/// The default LGRES after one stage, adaptive sub-steps against the paper's single jump.
pub const EXTRAPOLATION: ExtrapolationStudy = ExtrapolationStudy {
    name: "extrapolation",
    summary: "one wear stage, adaptive sub-steps vs the paper's single jump",
    scene: crate::scenes::DEFAULT,
    single_jump_run: "lgres-single-jump",
};

/// A study by name.
pub fn study(name: &str) -> Option<&'static Study> {
    STUDIES.iter().find(|s| s.name == name)
}
