//! The files of one run, written atomically with [`crate::files`] and drawn with
//! [`crate::plot`]: CSV time series, per-stage wear grids, the joints' life curves
//! (`wear_life.csv`), `summary.json`, the resolved `scene.toml`, PNG figures, the mechanism's
//! animations (`mechanism[_worn].gif`) and the page that shows them all, `report.html`.

use std::path::{Path, PathBuf};

use crate::animation;
use crate::files::{Cell, Column, CsvWriter, OutputError, write_atomic, write_csv, write_json};
use crate::life_plot::{LifeCurve, life_curve, life_distribution};
use crate::plot::{self, DEFAULT_SIZE, Figure, Series};
use crate::report::{Captioned, FILES_MARK, REPORT_FILE, RunFigure};
use scene::file_names::{JointFile, is_file_name_safe};
use sim::{LifePoint, Response, RunOutcome, Summary};

const QUANTITIES: [(&str, &str, &str); 6] = [
    ("x", "m", "x displacement"),
    ("y", "m", "y displacement"),
    ("vx", "m/s", "x velocity"),
    ("vy", "m/s", "y velocity"),
    ("ax", "m/s^2", "x acceleration"),
    ("ay", "m/s^2", "y acceleration"),
];

/// Writes every output of `outcome` into `dir`; returns the files written, in order.
pub fn write_run(outcome: &RunOutcome, dir: &Path) -> Result<Vec<PathBuf>, OutputError> {
    // Names become file names: refuse before writing anything (validation rejects them first).
    let names = outcome.response.contact.iter().map(|c| &c.name);
    if let Some(name) = names
        .chain(outcome.wear.iter().map(|w| &w.name))
        .find(|n| !is_file_name_safe(n))
    {
        return Err(OutputError::UnsafeName { name: name.clone() });
    }
    // The animations (most of the writing's cost) are drawn on their own threads while the
    // CSVs and figures are written; the files and their order stay the same, and an
    // error of the files before the animations is reported first, as when written in turn.
    let (written, animations) = std::thread::scope(|s| {
        let animations = s.spawn(|| animation_files(outcome, dir));
        let written = data_files(outcome, dir);
        let animations = animations
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        written.and_then(|written| Ok((written, animations?)))
    })?;
    let Written {
        mut files, figures, ..
    } = written;
    files.extend(animations.iter().map(|a| a.path.clone()));
    let figures: Vec<Captioned> = animations.into_iter().chain(figures).collect();
    let report = crate::report::write_run_report(outcome, dir, &files, &figures)?;
    files.push(report);
    Ok(files)
}

/// What the writers wrote, in order, and the figures among it, captioned as they are drawn.
struct Written<'a> {
    /// The run's summary, which the captions quote.
    summary: &'a Summary,
    files: Vec<PathBuf>,
    figures: Vec<Captioned>,
}

impl<'a> Written<'a> {
    fn new(summary: &'a Summary) -> Self {
        Self {
            summary,
            files: Vec::new(),
            figures: Vec::new(),
        }
    }

    fn file(&mut self, path: PathBuf) {
        self.files.push(path);
    }

    /// The figure drawn at `path`.
    fn figure(&mut self, path: PathBuf, figure: RunFigure) {
        self.figures
            .push(figure.captioned(path.clone(), self.summary));
        self.files.push(path);
    }
}

/// The report of `outcome` as an HTML fragment for a notebook (`_repr_html_`): the page
/// without the files list, figures embedded. The run's files are drawn in a temporary folder,
/// removed before returning.
pub fn notebook_html(outcome: &RunOutcome) -> Result<String, OutputError> {
    static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!(".wearsim-notebook-{}-{n}", std::process::id()));
    let page = write_run(outcome, &dir).and_then(|_| {
        let path = dir.join(REPORT_FILE);
        std::fs::read_to_string(&path).map_err(crate::files::io_err(&path))
    });
    // Best effort: the report (or its error) matters more than a leftover temporary folder.
    let _ = std::fs::remove_dir_all(&dir);
    let page = page?;
    let start = page.find("<div class=\"wj-report\">").unwrap_or(0);
    let end = page.find(FILES_MARK).unwrap_or(page.len());
    Ok(format!("{}</div>\n", &page[start..end]))
}

/// Every file of [`write_run`] but the animations and the report, in order.
fn data_files<'a>(outcome: &'a RunOutcome, dir: &Path) -> Result<Written<'a>, OutputError> {
    let mut files = Written::new(&outcome.summary);
    response_files(&mut files, &outcome.response, dir, ResponseSurfaces::Unworn)?;
    if let Some(worn) = &outcome.worn_response {
        response_files(&mut files, worn, dir, ResponseSurfaces::Worn)?;
    }
    for joint in &outcome.wear {
        for (k, stage) in joint.stages.iter().enumerate() {
            files.file(crate::surfaces::write_stage(
                dir,
                &joint.name,
                k + 1,
                stage,
            )?);
        }
        if joint.stages.is_empty() {
            continue;
        }
        let labels: Vec<(String, &[f64])> = joint
            .stages
            .iter()
            .enumerate()
            .flat_map(|(k, s)| {
                [
                    (format!("bearing, stage {}", k + 1), s.bearing().depth()),
                    (format!("pin, stage {}", k + 1), s.pin().depth()),
                ]
            })
            .collect();
        let surfaces: Vec<(&str, &[f64])> = labels.iter().map(|(l, d)| (l.as_str(), *d)).collect();
        let path = dir.join(JointFile::Wear.name(&joint.name));
        plot::wear_depth(
            &path,
            &format!("Wear depth at joint {} (body frames)", joint.name),
            DEFAULT_SIZE,
            &surfaces,
        )?;
        files.figure(path, RunFigure::Wear { joint: &joint.name });
        if let Some(last) = joint.stages.last() {
            let peak = last.bearing().peak().depth.max(last.pin().peak().depth);
            let clearance = joint.bearing_radius - joint.pin_radius;
            // Draw the deepest wear at about the clearance's width, at least true to scale.
            let exaggeration = if peak > 0.0 {
                (clearance / peak).max(1.0).round()
            } else {
                1.0
            };
            let path = dir.join(JointFile::Outline.name(&joint.name));
            plot::worn_outline(
                &path,
                &format!("Worn surfaces at joint {} after the last stage", joint.name),
                (900, 650),
                &plot::WornOutlines {
                    bearing_radius: joint.bearing_radius,
                    pin_radius: joint.pin_radius,
                    bearing_wear: last.bearing().depth(),
                    pin_wear: last.pin().depth(),
                    exaggeration,
                },
            )?;
            files.figure(path, RunFigure::WornOutline { joint: &joint.name });
        }
    }
    if !outcome.wear.is_empty() {
        life_files(&mut files, outcome, dir)?;
    }
    let path = dir.join("summary.json");
    write_json(&path, &outcome.summary)?;
    files.file(path);
    let path = dir.join("scene.toml");
    write_atomic(&path, outcome.scene.to_toml().as_bytes())?;
    files.file(path);
    Ok(files)
}

/// `mechanism.gif` and, after wear, `mechanism_worn.gif` (where the run recorded the frames:
/// `run.animation`), captioned for the report.
fn animation_files(outcome: &RunOutcome, dir: &Path) -> Result<Vec<Captioned>, OutputError> {
    let worn = outcome
        .worn_response
        .as_ref()
        .map(|r| (r, ResponseSurfaces::Worn, &outcome.wear[..]));
    let unworn = (&outcome.response, ResponseSurfaces::Unworn, &[][..]);
    let mut out = Vec::new();
    for (response, surfaces, wear) in std::iter::once(unworn).chain(worn) {
        if response.frames.is_none() {
            continue;
        }
        let suffix = surfaces.suffix();
        let path = dir.join(format!("mechanism{suffix}.gif"));
        let on = surfaces.phrase();
        let title = format!("{}: one drive cycle {on}", outcome.summary.scene);
        let info = animation::write_animation(&path, &outcome.scene, response, wear, &title)?;
        let magnified: Vec<String> = info
            .magnification
            .iter()
            .map(|(joint, m)| format!("joint {joint} ×{m:.0}"))
            .collect();
        let magnified = if magnified.is_empty() {
            String::new()
        } else {
            format!(
                " Each clearance joint's inset shows the journal centre in its bearing, the \
                 clearance magnified ({}), its orbit as a trail and the largest contact force \
                 since the previous frame as an arrow scaled to the cycle's peak.",
                magnified.join(", ")
            )
        };
        out.push(Captioned {
            path,
            rank: 0,
            caption: format!(
                "mechanism{suffix}.gif: the mechanism over one drive cycle after the {} s \
                 start-up window {on} ({} frames), the ideal mechanism in grey behind.\
                 {magnified}",
                crate::report::sig(outcome.summary.transient_window_s, 3),
                info.frames
            ),
        });
    }
    Ok(out)
}

fn col<'a>(name: &'a str, unit: &'a str) -> Column<'a> {
    Column { name, unit }
}

/// `wear_life.csv` (every wearing joint's life curve, one row per sub-step after a row at 0
/// cycles) and one `wear_life_<joint>.png` per joint.
fn life_files(files: &mut Written, outcome: &RunOutcome, dir: &Path) -> Result<(), OutputError> {
    let path = dir.join("wear_life.csv");
    let mut csv = CsvWriter::create(
        &path,
        &[
            col("joint", "-"),
            col("stage", "1"),
            col("substep", "1"),
            col("cycles", "1"),
            col("bearing_peak_depth", "m"),
            col("pin_peak_depth", "m"),
            col("worn_volume", "m^3"),
            col("max_local_clearance", "m"),
            col("wear_stiffness", "1"),
        ],
    )?;
    for joint in &outcome.wear {
        for p in &joint.life {
            csv.record(&[
                Cell::Text(&joint.name),
                Cell::Count(p.stage),
                Cell::Count(p.substep),
                Cell::Number(p.cycles),
                Cell::Number(p.bearing_peak_depth_m),
                Cell::Number(p.pin_peak_depth_m),
                Cell::Number(p.worn_volume_m3),
                Cell::Number(p.max_local_clearance_m),
                Cell::Number(p.wear_stiffness),
            ])?;
        }
    }
    files.file(csv.finish()?);
    let limits = outcome.summary.wear.as_ref().map(|w| &w.joints);
    for joint in &outcome.wear {
        let column = |f: fn(&LifePoint) -> f64| joint.life.iter().map(f).collect::<Vec<f64>>();
        let cycles = column(|p| p.cycles);
        // Each point's noise (0 where not measured); none at all: no band.
        let measured = joint.life_noise.iter().any(Option::is_some);
        let noise = |f: fn(&wear::JointNoise) -> f64| -> Vec<f64> {
            if measured {
                joint
                    .life_noise
                    .iter()
                    .map(|n| n.as_ref().map_or(0.0, f))
                    .collect()
            } else {
                Vec::new()
            }
        };
        // A stage's last point is where the next begins (not after the last stage).
        let boundaries: Vec<f64> = joint
            .life
            .windows(2)
            .filter(|w| w[1].stage > w[0].stage && w[0].stage > 0)
            .map(|w| w[0].cycles)
            .collect();
        let limit = limits
            .and_then(|js| js.iter().find(|j| j.name == joint.name))
            .and_then(|j| j.clearance_limit.as_ref())
            .map(|l| (l.limit_m, l.cycles));
        let path = dir.join(JointFile::Life.name(&joint.name));
        life_curve(
            &path,
            &format!("Wear of joint {} over its life", joint.name),
            DEFAULT_SIZE,
            &LifeCurve {
                cycles: &cycles,
                bearing_depth: &column(|p| p.bearing_peak_depth_m),
                pin_depth: &column(|p| p.pin_peak_depth_m),
                max_clearance: &column(|p| p.max_local_clearance_m),
                noise: [
                    &noise(|n| n.bearing_peak_depth),
                    &noise(|n| n.pin_peak_depth),
                    &noise(|n| n.max_local_clearance),
                ],
                stage_boundaries: &boundaries,
                limit,
            },
        )?;
        files.figure(path, RunFigure::WearLife { joint: &joint.name });
    }
    if let Some(lives) = outcome
        .summary
        .wear
        .as_ref()
        .and_then(sim::life_distributions)
    {
        life_distribution_files(files, &lives, dir)?;
    }
    Ok(())
}

/// With a clearance limit reached: `life_distribution.csv` (the cycles, then per joint and for
/// the mechanism the fraction that has reached the limit by them) and its figure,
/// `life_distribution.png`.
fn life_distribution_files(
    files: &mut Written,
    lives: &sim::life_distribution::SampledLives,
    dir: &Path,
) -> Result<(), OutputError> {
    let path = dir.join(LIFE_DISTRIBUTION_CSV);
    let names: Vec<String> = lives.curves.iter().map(|c| c.of.column()).collect();
    let columns: Vec<Column> = std::iter::once(col("cycles", "1"))
        .chain(names.iter().map(|n| col(n, "1")))
        .collect();
    let mut csv = CsvWriter::create(&path, &columns)?;
    for (k, cycles) in lives.cycles.iter().enumerate() {
        let row: Vec<f64> = std::iter::once(*cycles)
            .chain(lives.curves.iter().map(|c| c.failed[k]))
            .collect();
        csv.row(&row)?;
    }
    files.file(csv.finish()?);
    let path = dir.join(LIFE_DISTRIBUTION_PNG);
    life_distribution(
        &path,
        "Life to the clearance limit under the wear coefficients' scatter",
        DEFAULT_SIZE,
        lives,
    )?;
    files.figure(path, RunFigure::LifeDistribution);
    Ok(())
}

/// The life distribution's table: the cycles, then per joint (`failed_<joint>`) and for the
/// mechanism (`failed_mechanism`) the fraction that reached the clearance limit by them.
pub const LIFE_DISTRIBUTION_CSV: &str = "life_distribution.csv";
/// The life distribution's figure.
pub const LIFE_DISTRIBUTION_PNG: &str = "life_distribution.png";

/// The surfaces a response ran on, which its files are named and titled after.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum ResponseSurfaces {
    /// The run's response, on the surfaces it started from.
    Unworn,
    /// The response after the wear stages, on the surfaces the last stage left.
    Worn,
}

impl ResponseSurfaces {
    fn is_worn(self) -> bool {
        self == Self::Worn
    }

    /// What the file names end with before their extension.
    fn suffix(self) -> &'static str {
        match self {
            Self::Unworn => "",
            Self::Worn => "_worn",
        }
    }

    /// What the figure titles end with.
    fn title_note(self) -> &'static str {
        match self {
            Self::Unworn => "",
            Self::Worn => " (worn joints)",
        }
    }

    /// The surfaces in the animation's words.
    fn phrase(self) -> &'static str {
        match self {
            Self::Unworn => "on the unworn surfaces",
            Self::Worn => "on the worn surfaces after the last stage",
        }
    }
}

/// `response[_worn].csv`, `contact[_worn].csv` and their figures.
fn response_files(
    files: &mut Written,
    r: &Response,
    dir: &Path,
    surfaces: ResponseSurfaces,
) -> Result<(), OutputError> {
    let (sim, ideal) = (r.motion.series(), r.ideal.series());
    files.file(response_csv(r, &sim, &ideal, dir, surfaces)?);
    if !r.contact.is_empty() {
        files.file(contact_csv(r, dir, surfaces)?);
    }
    // The worn response's body figures only when it has no contact to show instead.
    if surfaces == ResponseSurfaces::Unworn || r.contact.is_empty() {
        response_figures(files, r, &sim, &ideal, dir, surfaces)?;
    }
    contact_figures(files, r, dir, surfaces)
}

/// `response[_worn].csv`: the response body against the ideal mechanism, and their difference.
fn response_csv(
    r: &Response,
    sim: &[&[f64]; 6],
    ideal: &[&[f64]; 6],
    dir: &Path,
    surfaces: ResponseSurfaces,
) -> Result<PathBuf, OutputError> {
    let deviation: Vec<Vec<f64>> = sim
        .iter()
        .zip(ideal)
        .map(|(a, b)| a.iter().zip(*b).map(|(x, y)| x - y).collect())
        .collect();
    let names: Vec<[String; 3]> = QUANTITIES
        .iter()
        .map(|(q, _, _)| [q.to_string(), format!("ideal_{q}"), format!("dev_{q}")])
        .collect();
    let mut columns = vec![(col("t", "s"), r.times.as_slice())];
    for (k, (_, unit, _)) in QUANTITIES.iter().enumerate() {
        columns.push((col(&names[k][0], unit), sim[k]));
        columns.push((col(&names[k][1], unit), ideal[k]));
        columns.push((col(&names[k][2], unit), &deviation[k]));
    }
    write_csv(
        dir.join(format!("response{}.csv", surfaces.suffix())),
        &columns,
    )
}

/// `contact[_worn].csv`: every clearance joint's contact state.
fn contact_csv(
    r: &Response,
    dir: &Path,
    surfaces: ResponseSurfaces,
) -> Result<PathBuf, OutputError> {
    let names: Vec<[String; 8]> = r
        .contact
        .iter()
        .map(|c| {
            [
                "Fn",
                "Ft",
                "delta",
                "e",
                "ex",
                "ey",
                "ex_bearing",
                "ey_bearing",
            ]
            .map(|q| format!("{}_{q}", c.name))
        })
        .collect();
    let mut columns = vec![(col("t", "s"), r.times.as_slice())];
    for (c, n) in r.contact.iter().zip(&names) {
        let units = ["N", "N", "m", "m", "m", "m", "m", "m"];
        let data: [&[f64]; 8] = [
            &c.normal_force,
            &c.friction_force,
            &c.penetration,
            &c.eccentricity,
            &c.ex,
            &c.ey,
            &c.ex_bearing,
            &c.ey_bearing,
        ];
        for k in 0..8 {
            columns.push((col(&n[k], units[k]), data[k]));
        }
    }
    write_csv(
        dir.join(format!("contact{}.csv", surfaces.suffix())),
        &columns,
    )
}

/// `response_<q>[_worn].png`: each quantity of the response body against the ideal mechanism.
fn response_figures(
    files: &mut Written,
    r: &Response,
    sim: &[&[f64]; 6],
    ideal: &[&[f64]; 6],
    dir: &Path,
    surfaces: ResponseSurfaces,
) -> Result<(), OutputError> {
    let body = &files.summary.response_body;
    for (k, (q, unit, label)) in QUANTITIES.iter().enumerate() {
        let path = dir.join(format!("response_{q}{}.png", surfaces.suffix()));
        let title = format!(
            "{body} centroid {label}: clearance vs ideal{}",
            surfaces.title_note()
        );
        let y_label = format!("{q} ({unit})");
        plot::line_chart(
            &path,
            &Figure {
                title: &title,
                x_label: "t (s)",
                y_label: &y_label,
                size: DEFAULT_SIZE,
            },
            &[
                Series {
                    label: "with clearance",
                    x: &r.times,
                    y: sim[k],
                },
                Series {
                    label: "ideal",
                    x: &r.times,
                    y: ideal[k],
                },
            ],
        )?;
        files.figure(
            path,
            RunFigure::Response {
                quantity: q,
                worn: surfaces.is_worn(),
            },
        );
    }
    Ok(())
}

/// Each clearance joint's contact force and journal-centre path.
fn contact_figures(
    files: &mut Written,
    r: &Response,
    dir: &Path,
    surfaces: ResponseSurfaces,
) -> Result<(), OutputError> {
    let worn = surfaces.is_worn();
    let note = surfaces.title_note();
    for c in &r.contact {
        let path = dir.join(JointFile::Force(worn).name(&c.name));
        let title = format!("Contact force at joint {}{note}", c.name);
        let kn: Vec<f64> = c.normal_force.iter().map(|f| f * 1e-3).collect();
        let kt: Vec<f64> = c.friction_force.iter().map(|f| f * 1e-3).collect();
        plot::line_chart(
            &path,
            &Figure {
                title: &title,
                x_label: "t (s)",
                y_label: "force (kN)",
                size: DEFAULT_SIZE,
            },
            &[
                Series {
                    label: "normal",
                    x: &r.times,
                    y: &kn,
                },
                Series {
                    label: "friction",
                    x: &r.times,
                    y: &kt,
                },
            ],
        )?;
        files.figure(
            path,
            RunFigure::ContactForce {
                joint: &c.name,
                worn,
            },
        );
        let path = dir.join(JointFile::Journal(worn).name(&c.name));
        plot::journal_path(
            &path,
            &format!(
                "Journal centre at joint {} in the bearing frame{note}",
                c.name
            ),
            (900, 650),
            &c.ex_bearing,
            &c.ey_bearing,
            c.clearance,
        )?;
        files.figure(
            path,
            RunFigure::Journal {
                joint: &c.name,
                worn,
            },
        );
    }
    Ok(())
}
