//! The numbers the paper reports (Ma, Jiang & Yin 2026, §4.2), kept as data in
//! `data/paper.toml` so the report shows them without code standing for a table.

use std::sync::LazyLock;

use serde::Deserialize;

/// The paper's numbers for one study.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PaperStudy {
    /// Study name, e.g. `clearance` (the physical formulation's).
    pub name: String,
    /// The paper's section, e.g. `§4.2.2`.
    pub section: String,
    /// Its numbers, in the paper's order.
    pub values: Vec<PaperValue>,
}

/// A number the paper reports for one scene.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PaperValue {
    /// Our built-in scene standing for the paper's case.
    pub scene: String,
    /// What is reported.
    pub quantity: Quantity,
    /// Joint (0 = A, 1 = B) or deviation component (0–5 = x, y, vx, vy, ax, ay).
    pub index: usize,
    /// The value as the paper gives it.
    pub text: String,
}

/// What a [`PaperValue`] reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Quantity {
    /// Peak normal force at a joint.
    Force,
    /// Rod-3 deviation from the ideal mechanism, one component.
    Deviation,
    /// Peak wear depth at a joint after the last stage.
    Wear,
    /// Peak wear depth at a joint after stage 1.
    WearStage1,
}

/// `data/paper.toml`, the paper's numbers by study.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct PaperFile {
    study: Vec<PaperStudy>,
}

static PAPER: LazyLock<Result<Vec<PaperStudy>, toml::de::Error>> = LazyLock::new(|| {
    toml::from_str::<PaperFile>(include_str!("../data/paper.toml")).map(|f| f.study)
});

/// The paper's numbers by study. The file is compiled in; a test parses it, so an error here
/// means an edit broke it.
pub fn paper() -> Result<&'static [PaperStudy], &'static toml::de::Error> {
    PAPER.as_ref().map(Vec::as_slice)
}

/// The report's closing section: why our numbers differ from the paper's.
pub const WHY_DIFFERENT: &str = "## Why our numbers differ from the paper's\n\n\
- **Geometry is a reconstruction** (docs/model.md §6): link lengths and joint positions are \
inferred from the paper's figures, so forces and deviations are comparable in order of \
magnitude, not digit for digit.\n\
- **Wear magnitude**: with `K_d = 1.8e-13 m²/N` as printed, one cycle wears ~1e-10–1e-9 m, so \
a stage of 2 million cycles is tenths of a millimetre to millimetres (docs/model.md §8), far above the \
paper's figures, which themselves differ 10× between §4.2.1 and §4.2.2 for the same case. Our \
worn response therefore runs in much larger clearances than the paper's.\n\
- **Chaos**: the journal paths separate within a fraction of a cycle; single peak forces move \
by tens of percent with tolerances. We judge on medians over cycles, deviations, dissipation \
and wear integrals, not on single peaks.\n\
- **K reduced**: K simulated cycles per stage instead of 100 gather wear over fewer impacts, \
so the profile is noisier; the adaptive sub-steps re-simulate between extrapolations, which \
the paper's single jump does not.\n\
- **Start-up**: the paper does not say whether its peaks include the concentric start-up \
impact; ours exclude the first window (the run's `summary.json` has both).\n";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_paper_file_parses_with_every_studys_numbers() {
        let studies = paper().expect("data/paper.toml parses");
        let names: Vec<&str> = studies.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, ["wear-stages", "clearance", "speed"]);
        assert_eq!(studies.iter().map(|s| s.values.len()).sum::<usize>(), 40);
        for v in studies.iter().flat_map(|s| &s.values) {
            let most = if v.quantity == Quantity::Deviation {
                6
            } else {
                2
            };
            assert!(v.index < most, "{v:?}");
            assert!(crate::scenes::source(&v.scene).is_some(), "{v:?}");
        }
    }
}
