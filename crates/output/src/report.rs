//! `report.html`: one self-contained page per run ([`crate::html`]). First what a reader
//! needs to judge the run (scene, force peaks, deviations, energy books, validity, wear, life,
//! numerics, warnings), then every figure the run drew with what to look at in it, then the
//! scene's parameters and the files beside the page.

use std::path::{Path, PathBuf};

use crate::files::OutputError;
use crate::html::{Html, Td};
use sim::{
    ENERGY_BOOKS_TOLERANCE_J, JointSummary, PeakStats, ResponseSummary, RunOutcome, Summary,
};

/// The report's file name in a run's folder.
pub const REPORT_FILE: &str = "report.html";

/// A figure a run drew: its file and what to look at in it. The writer that draws a figure
/// captions it ([`RunFigure`], or its own words for the animations), so the report never reads
/// a figure's meaning back from its file name.
#[derive(Debug, Clone)]
pub struct Captioned {
    /// The image file, in the run's folder.
    pub path: PathBuf,
    /// What to look at in it.
    pub caption: String,
    /// Where it stands among the figures ([`RunFigure::rank`]; the animations first, 0).
    pub(crate) rank: usize,
}

/// What a figure of a run shows, as the writer that draws it knows it.
#[derive(Debug, Clone, Copy)]
pub(crate) enum RunFigure<'a> {
    /// Normal and friction force at a joint.
    ContactForce { joint: &'a str, worn: bool },
    /// The journal centre's path in the bearing frame.
    Journal { joint: &'a str, worn: bool },
    /// Peak depths and largest local clearance over the stages' cycles.
    WearLife { joint: &'a str },
    /// Wear depth against angle after each stage.
    Wear { joint: &'a str },
    /// The cycles to the clearance limit under the wear coefficients' scatter.
    LifeDistribution,
    /// The worn outlines after the last stage.
    WornOutline { joint: &'a str },
    /// One quantity of the response body's centroid against the ideal mechanism.
    Response { quantity: &'a str, worn: bool },
}

impl RunFigure<'_> {
    /// The report's order: forces and orbits first, then wear and life, then the body
    /// response (after the animations, 0).
    fn rank(self) -> usize {
        match self {
            Self::ContactForce { .. } => 1,
            Self::Journal { .. } => 2,
            Self::WearLife { .. } | Self::LifeDistribution => 3,
            Self::Wear { .. } => 4,
            Self::WornOutline { .. } => 5,
            Self::Response { .. } => 6,
        }
    }

    /// The figure drawn at `path`, captioned with what to look at in it.
    pub(crate) fn captioned(self, path: PathBuf, s: &Summary) -> Captioned {
        let name = file_name(&path);
        let on = |worn: bool| {
            if worn {
                " on the worn surfaces after the last stage"
            } else {
                " on the unworn surfaces"
            }
        };
        let caption = match self {
            Self::ContactForce { joint, worn } => format!(
                "{name}: normal and friction force at joint {joint}{}. Look at the start-up \
                 impacts (before {} s), then the per-cycle peaks the table summarises.",
                on(worn),
                sig(s.transient_window_s, 3)
            ),
            Self::Journal { joint, worn } => format!(
                "{name}: the journal centre's path in the bearing frame at joint {joint}{}; the \
                 circle is the clearance. Contact is on the circle, free flight inside it.",
                on(worn)
            ),
            Self::WearLife { joint } => format!(
                "{name}: peak depths and the largest local clearance of joint {joint} over the \
                 drive cycles of the stages; the slope is the wear rate, and the limit line (if \
                 set) shows when the joint needs maintenance."
            ),
            Self::LifeDistribution => format!(
                "{name}: the fraction of joints (and of mechanisms, the first joint to reach \
                 it) that reach the clearance limit by a number of drive cycles, under the \
                 scatter of the wear coefficient; circles mark B10, squares B50. {}",
                s.wear
                    .as_ref()
                    .and_then(|w| w.life.as_ref())
                    .map_or(String::new(), |l| format!("Assumed: {}.", l.assumption))
            ),
            Self::Wear { joint } => format!(
                "{name}: wear depth against angle on the bearing and the pin of joint {joint}, \
                 after each stage (body frames): where the load concentrates and how irregular \
                 it grew."
            ),
            Self::WornOutline { joint } => format!(
                "{name}: the worn bearing and pin outlines of joint {joint} after the last stage, \
                 wear magnified as the figure says, against the round surfaces."
            ),
            Self::Response { quantity, worn } => format!(
                "{name}: the {} centroid's {quantity}{} against the ideal mechanism; the \
                 difference is the clearance's effect.",
                s.response_body,
                on(worn)
            ),
        };
        Captioned {
            path,
            caption,
            rank: self.rank(),
        }
    }
}

/// Writes `<dir>/report.html` for `outcome`, embedding the `figures` the run drew and listing
/// `files` (every file the run wrote, in `dir`).
pub fn write_run_report(
    outcome: &RunOutcome,
    dir: &Path,
    files: &[PathBuf],
    figures: &[Captioned],
) -> Result<PathBuf, OutputError> {
    let mut html = run_summary(&outcome.summary);
    figures_section(&mut html, figures)?;
    scene_table(&mut html, outcome);
    html.raw(FILES_MARK);
    html.heading(2, "Files");
    html.lede("Every file the run wrote, beside this page.");
    let names: Vec<String> = files
        .iter()
        .filter_map(|f| f.file_name())
        .map(|n| n.to_string_lossy().into_owned())
        .collect();
    html.list(&names);
    let path = dir.join(REPORT_FILE);
    let title = format!("wearsim run: {}", outcome.summary.scene);
    html.write_page(&path, &title)?;
    Ok(path)
}

/// Where the list of files beside the page starts (a notebook's copy ends there).
pub(crate) const FILES_MARK: &str = "<!-- files -->\n";

/// The report's top part, the verdicts and tables without figures (what a notebook shows first).
pub fn run_summary(s: &Summary) -> Html {
    let mut html = Html::new();
    html.heading(1, &format!("Run of scene {}", s.scene));
    html.lede(&scene_line(s));
    for w in warnings(s) {
        html.warning(&w);
    }
    forces(&mut html, s);
    deviations(&mut html, s);
    energy(&mut html, s);
    wear(&mut html, s);
    numerics(&mut html, s);
    html
}

/// The scene in one line.
fn scene_line(s: &Summary) -> String {
    let wear = s.wear.as_ref().map_or_else(
        || "no wear stages".to_string(),
        |w| {
            format!(
                "{} wear stage(s) of {:.3e} cycles each, {} simulated cycles per sub-step on {} \
                 trajector{}",
                w.stages,
                w.cycles_represented_per_stage,
                w.cycles_per_stage,
                w.trajectories,
                if w.trajectories == 1 { "y" } else { "ies" }
            )
        },
    );
    format!(
        "{} — contact {}. {} response cycle(s) of {} s; response body {}; {wear}; {} wall time.",
        s.description,
        s.contacts.join("; "),
        s.response.cycles,
        sig(s.period_s, 4),
        s.response_body,
        seconds(s.wall_time_s)
    )
}

/// Every warning the run raised, and every joint outside the contact model's validity.
fn warnings(s: &Summary) -> Vec<String> {
    let mut out = Vec::new();
    for (label, r) in responses(s) {
        out.extend(r.energy_warnings.iter().map(|w| format!("{label}: {w}")));
        for j in &r.joints {
            if let Some(v) = j.validity.as_ref().filter(|v| !v.inside) {
                out.push(format!(
                    "{label}, joint {}: OUTSIDE the contact model's validity, so its force \
                     peaks are not results: {}",
                    j.name,
                    v.reasons.join("; ")
                ));
            }
        }
    }
    if let Some(w) = &s.wear {
        out.extend(w.warnings.iter().cloned());
    }
    out
}

/// The responses the run made, labelled.
fn responses(s: &Summary) -> Vec<(&'static str, &ResponseSummary)> {
    let mut out = vec![("unworn response", &s.response)];
    if let Some(w) = &s.worn_response {
        out.push(("worn response", w));
    }
    out
}

fn forces(html: &mut Html, s: &Summary) {
    if s.response.joints.is_empty() {
        return;
    }
    html.heading(2, "Contact force peaks");
    html.lede(&format!(
        "Peaks are statistics of per-cycle maxima after the {} s start-up window (the clearance \
         dynamics are chaotic: single peaks do not repeat). Validity: whether the (worn) geometry \
         stayed where the contact model holds; a joint outside it has no result. Noise: the \
         bootstrap standard deviation of the median. Elastic share: the conservative part of the \
         force at each cycle's peak, median (smallest); the rest is the law's damping term, and a \
         median below 50 % is flagged.",
        sig(s.transient_window_s, 3)
    ));
    let mut rows = Vec::new();
    for (label, r) in responses(s) {
        for j in &r.joints {
            rows.push(force_row(label, j));
        }
    }
    html.table(
        &[
            "response",
            "joint",
            "cycles",
            "median peak",
            "± noise",
            "IQR",
            "elastic share",
            "max after window",
            "max incl. start-up",
            "max penetration",
            "validity",
        ],
        &rows,
    );
}

fn force_row(label: &str, j: &JointSummary) -> Vec<Td> {
    let after = j.normal_force_after_transient.as_ref();
    let stat = |f: fn(&PeakStats) -> f64| after.map_or_else(|| "n/a".into(), |p| kn(f(p)));
    let validity = match &j.validity {
        Some(v) if v.inside => Td::Verdict(format!("inside ({})", v.model), true),
        Some(v) => Td::Verdict(format!("OUTSIDE: {}", v.reasons.join("; ")), false),
        None => Td::text("not measured"),
    };
    vec![
        Td::text(label),
        Td::text(&j.name),
        Td::num(after.map_or_else(|| "0".into(), |p| p.cycles.to_string())),
        Td::num(stat(|p| p.cycle_median)),
        Td::num(stat(|p| p.cycle_median_noise)),
        Td::num(stat(|p| p.cycle_iqr)),
        share_cell(after),
        Td::num(stat(|p| p.max)),
        Td::num(kn(j.normal_force_all.max)),
        Td::num(micro(j.max_penetration_m)),
        validity,
    ]
}

/// The elastic share of the peaks (median, smallest), marked when the median is mostly
/// damping.
fn share_cell(after: Option<&PeakStats>) -> Td {
    match after.filter(|p| p.elastic_share_median.is_finite()) {
        None => Td::text("n/a"),
        Some(p) => Td::Verdict(
            format!(
                "{:.0} % (min {:.0} %)",
                100.0 * p.elastic_share_median,
                100.0 * p.elastic_share_min
            ),
            p.elastic_share_median >= sim::MIN_ELASTIC_SHARE,
        ),
    }
}

fn deviations(html: &mut Html, s: &Summary) {
    html.heading(
        2,
        &format!("Deviation of {} from the ideal mechanism", s.response_body),
    );
    html.lede(&format!(
        "Largest |simulated − ideal| of the body's centroid, after the {} s start-up window and \
         over the whole run; the ideal mechanism is {}.",
        sig(s.transient_window_s, 3),
        s.reference
    ));
    let mut rows = Vec::new();
    for (label, r) in responses(s) {
        for (window, d) in [
            ("after window", r.deviation_after_transient.as_ref()),
            ("whole run", Some(&r.deviation)),
        ] {
            let cell = |f: fn(&sim::Deviation) -> f64, unit: &str| {
                Td::num(d.map_or_else(|| "n/a".into(), |d| with_unit(f(d), unit)))
            };
            rows.push(vec![
                Td::text(label),
                Td::text(window),
                cell(|d| d.x_m * 1e6, "µm"),
                cell(|d| d.y_m * 1e6, "µm"),
                cell(|d| d.vx_m_s, "m/s"),
                cell(|d| d.vy_m_s, "m/s"),
                cell(|d| d.ax_m_s2, "m/s²"),
                cell(|d| d.ay_m_s2, "m/s²"),
            ]);
        }
    }
    html.table(
        &[
            "response", "span", "|Δx|", "|Δy|", "|Δvx|", "|Δvy|", "|Δax|", "|Δay|",
        ],
        &rows,
    );
}

fn energy(html: &mut Html, s: &Summary) {
    if s.response.joints.is_empty() {
        return;
    }
    html.heading(2, "Energy books, per cycle");
    html.lede(&format!(
        "What each contact takes out of the mechanism (the energy audit's work, net of stored \
         elastic energy) against what its damping and friction dissipate. The books close when \
         the difference is within {ENERGY_BOOKS_TOLERANCE_J} J per cycle."
    ));
    let mut rows = Vec::new();
    for (label, r) in responses(s) {
        for j in &r.joints {
            let residual = j.energy_books_residual_per_cycle_j;
            let closes = residual.is_finite() && residual.abs() <= ENERGY_BOOKS_TOLERANCE_J;
            rows.push(vec![
                Td::text(label),
                Td::text(&j.name),
                Td::num(joules(j.contact_dissipation_per_cycle_j)),
                Td::num(joules(j.damping_dissipation_per_cycle_j)),
                Td::num(joules(j.friction_dissipation_per_cycle_j)),
                Td::num(joules(residual)),
                Td::Verdict(if closes { "close" } else { "DO NOT close" }.into(), closes),
            ]);
        }
    }
    html.table(
        &[
            "response",
            "joint",
            "dissipated",
            "damping",
            "friction",
            "difference",
            "books",
        ],
        &rows,
    );
}

fn wear(html: &mut Html, s: &Summary) {
    let Some(w) = &s.wear else {
        return;
    };
    html.heading(2, "Wear");
    let batches = w.joints.first().map_or(0, |j| j.noise_batches);
    let noise = if batches > 0 {
        format!(
            "± is the sampling noise of each result (a standard error over {batches} batches of \
             the runs' independent halves, docs/model.md §10.4)"
        )
    } else {
        "no sampling noise was measured (see the warnings and notes)".to_string()
    };
    html.lede(&format!(
        "After {} stage(s): {:.3e} drive cycles applied in sub-steps {:?} ({} extrapolation, {} \
         simulated cycles per sub-step on {} trajector{}). Depths are in the body frames; ranges hold the cells \
         at least half as deep as the peak; {noise}. The stage's two halves {}.",
        w.stages,
        w.cycles_applied,
        w.substeps_per_stage,
        w.extrapolation,
        w.cycles_per_stage,
        w.trajectories,
        if w.trajectories == 1 { "y" } else { "ies" },
        if w.converged {
            "agree: the wear is converged in K"
        } else {
            "were not shown to agree (see the warnings)"
        }
    ));
    let ranges = |r: &[[f64; 2]]| {
        r.iter()
            .map(|[a, b]| format!("[{a:.0}, {b:.0}]°"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let rows: Vec<Vec<Td>> = w
        .joints
        .iter()
        .map(|j| {
            let life = j.clearance_limit.as_ref().map_or_else(
                || "no limit set".to_string(),
                |l| match (l.cycles, l.cycles_noise) {
                    (Some(c), Some(n)) => {
                        format!("{} after {c:.2e} ± {n:.1e} cycles", micro(l.limit_m))
                    }
                    (Some(c), None) => format!("{} after {c:.2e} cycles", micro(l.limit_m)),
                    (None, _) => format!("{} not reached", micro(l.limit_m)),
                },
            );
            vec![
                Td::text(&j.name),
                Td::num(micro_noise(
                    j.bearing_peak_depth_m,
                    j.bearing_peak_depth_noise_m,
                )),
                Td::num(format!("{:.0}°", j.bearing_peak_angle_deg)),
                Td::text(ranges(&j.bearing_ranges_deg)),
                Td::num(micro_noise(j.pin_peak_depth_m, j.pin_peak_depth_noise_m)),
                Td::num(format!("{:.0}°", j.pin_peak_angle_deg)),
                Td::text(ranges(&j.pin_ranges_deg)),
                Td::num(with_noise(
                    j.worn_volume_m3 * 1e9,
                    j.worn_volume_noise_m3.map(|n| n * 1e9),
                    "mm³",
                )),
                Td::num(micro_noise(
                    j.max_local_clearance_m,
                    j.max_local_clearance_noise_m,
                )),
                Td::text(life),
            ]
        })
        .collect();
    html.table(
        &[
            "joint",
            "bearing peak",
            "at",
            "bearing ranges",
            "pin peak",
            "at",
            "pin ranges",
            "worn volume",
            "largest clearance",
            "clearance limit",
        ],
        &rows,
    );
    life(html, w);
}

/// The life to the clearance limit under the wear coefficients' scatter: how the stages ended,
/// each joint's and the mechanism's B10 and B50, and what the mechanism's assumes.
fn life(html: &mut Html, w: &sim::WearSummary) {
    let Some(life) = &w.life else {
        return;
    };
    html.heading(3, "Life to the clearance limit");
    html.lede(&format!(
        "How the stages ended: {}{}. B10 and B50 are the cycles by which 10 % and half of \
         such joints reach {}, with each joint's ln k_d normal about the scene's k_d (its \
         standard deviation: k_d scatter), rescaled from the simulated life (Archard wear is \
         linear in k_d); ± is the sampling noise of the simulated life, scaled. The \
         mechanism's life is its first joint's to reach the limit: {}.",
        life.ended,
        if life.until_limit {
            " (run.until_limit)"
        } else {
            ""
        },
        micro(life.limit_m),
        life.assumption
    ));
    let cycles = |c: Option<f64>, n: Option<f64>| {
        c.map_or_else(
            || "–".to_string(),
            |c| sim::life_distribution::cycles_with_noise(c, n),
        )
    };
    let mut rows: Vec<Vec<Td>> = w
        .joints
        .iter()
        .filter_map(|j| j.clearance_limit.as_ref().map(|l| (j, l)))
        .map(|(j, l)| {
            vec![
                Td::text(format!("joint {}", j.name)),
                Td::num(cycles(l.cycles, l.cycles_noise)),
                Td::num(format!("{}", l.k_d_scatter)),
                Td::num(cycles(l.b10_cycles, l.b10_noise)),
                Td::num(cycles(l.b50_cycles, l.b50_noise)),
            ]
        })
        .collect();
    if w.joints.len() > 1 {
        let m = life.mechanism;
        rows.push(vec![
            Td::text("mechanism"),
            Td::num("–"),
            Td::text(life.k_d_correlation.name()),
            Td::num(cycles(m.map(|m| m.b10_cycles), m.and_then(|m| m.b10_noise))),
            Td::num(cycles(m.map(|m| m.b50_cycles), m.and_then(|m| m.b50_noise))),
        ]);
    }
    html.table(
        &[
            "life of",
            "cycles to the limit (simulated)",
            "k_d scatter",
            "B10 cycles",
            "B50 cycles",
        ],
        &rows,
    );
}

fn numerics(html: &mut Html, s: &Summary) {
    html.heading(2, "Numerics");
    let rows: Vec<Vec<Td>> = responses(s)
        .into_iter()
        .filter_map(|(label, r)| r.numerics.as_ref().map(|n| (label, n)))
        .map(|(label, n)| {
            vec![
                Td::text(label),
                Td::num(n.steps.to_string()),
                Td::num(n.rejected_steps.to_string()),
                Td::num(n.events.to_string()),
                Td::num(format!("{} s", sig(n.smallest_step_s, 3))),
                Td::num(format!("{} m", sig(n.drift_position, 2))),
                Td::num(format!(
                    "{} ({} relative)",
                    joules(n.energy_residual_j),
                    sig(n.energy_relative_residual, 2)
                )),
                Td::num(seconds(n.wall_time_s)),
            ]
        })
        .collect();
    if rows.is_empty() {
        html.lede("Kinematic analysis only: no integration.");
        return;
    }
    html.lede(
        "Accepted and rejected steps, located contact events, the smallest step, the largest \
         position-constraint drift, the energy-balance residual and the solver's wall time.",
    );
    html.table(
        &[
            "response",
            "steps",
            "rejected",
            "events",
            "smallest step",
            "drift",
            "energy residual",
            "wall time",
        ],
        &rows,
    );
}

/// Every figure the run drew, captioned, in the report's order (by rank, then file name).
fn figures_section(html: &mut Html, figures: &[Captioned]) -> Result<(), OutputError> {
    html.heading(2, "Figures");
    let mut figures: Vec<&Captioned> = figures.iter().collect();
    figures.sort_by_key(|f| (f.rank, file_name(&f.path)));
    for f in figures {
        html.figure(&f.path, &file_name(&f.path), &f.caption)?;
    }
    Ok(())
}

fn file_name(p: &Path) -> String {
    p.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// The scene as run, as a table of its fields (flattened TOML paths) with units where known.
fn scene_table(html: &mut Html, outcome: &RunOutcome) {
    html.heading(2, "Scene parameters");
    html.lede("The scene as run (overrides applied); scene.toml beside this page holds the same.");
    let mut rows = Vec::new();
    if let Ok(value) = toml::Value::try_from(&outcome.scene) {
        flatten("", &value, &mut rows);
    }
    html.table(&["field", "value", "unit"], &rows);
}

fn flatten(prefix: &str, value: &toml::Value, rows: &mut Vec<Vec<Td>>) {
    match value {
        toml::Value::Table(t) => {
            for (k, v) in t {
                let path = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                flatten(&path, v, rows);
            }
        }
        toml::Value::Array(a) if a.iter().all(|v| v.is_table()) && !a.is_empty() => {
            for (k, v) in a.iter().enumerate() {
                flatten(&format!("{prefix}[{k}]"), v, rows);
            }
        }
        other => {
            let leaf = prefix.rsplit(['.', ']']).next().unwrap_or(prefix);
            rows.push(vec![
                Td::text(prefix),
                Td::text(other.to_string().trim_matches('"')),
                Td::text(unit_of(leaf)),
            ]);
        }
    }
}

/// The unit of a scene field, by its name (empty where it has none or is not known).
fn unit_of(field: &str) -> &'static str {
    match field {
        "mass" => "kg",
        "inertia" => "kg·m²",
        "x" | "y" | "point" | "other_point" | "bearing_point" | "pin_point" | "bearing_radius"
        | "clearance" | "width" | "clearance_limit" | "atol_position" => "m",
        "theta_deg" | "wear_smoothing_deg" => "deg",
        "gravity" => "m/s²",
        "velocity" => "m/s",
        "omega" => "rad/s",
        "rpm" => "1/min",
        "period" | "transient_window" | "output_interval" | "max_wall_time" => "s",
        "youngs_modulus" | "hardness" => "Pa",
        "k_d" => "m²/N",
        _ => "",
    }
}

/// `x` with `digits` significant digits, in plain notation where it reads well.
pub fn sig(x: f64, digits: usize) -> String {
    if !x.is_finite() {
        return "n/a".into();
    }
    if x == 0.0 {
        return "0".into();
    }
    let magnitude = x.abs().log10().floor();
    if !(-3.0..5.0).contains(&magnitude) {
        return format!("{x:.*e}", digits.saturating_sub(1));
    }
    let decimals = (digits as f64 - 1.0 - magnitude).max(0.0) as usize;
    format!("{x:.decimals$}")
}

fn with_unit(x: f64, unit: &str) -> String {
    if x.is_finite() {
        format!("{} {unit}", sig(x, 3))
    } else {
        "n/a".into()
    }
}

fn kn(newtons: f64) -> String {
    with_unit(newtons * 1e-3, "kN")
}

/// A length given in m, in µm.
fn micro(metres: f64) -> String {
    with_unit(metres * 1e6, "µm")
}

/// `x ± noise unit` (3 and 2 significant digits), or `x unit` without a noise.
fn with_noise(x: f64, noise: Option<f64>, unit: &str) -> String {
    match noise.filter(|n| n.is_finite() && x.is_finite()) {
        Some(n) => format!("{} ± {} {unit}", sig(x, 3), sig(n, 2)),
        None => with_unit(x, unit),
    }
}

/// A length and its noise given in m, in µm.
fn micro_noise(metres: f64, noise: Option<f64>) -> String {
    with_noise(metres * 1e6, noise.map(|n| n * 1e6), "µm")
}

fn joules(j: f64) -> String {
    with_unit(j, "J")
}

fn seconds(s: f64) -> String {
    with_unit(s, "s")
}
