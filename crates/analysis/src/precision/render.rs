//! The sweep's report: CSV, markdown tables with the fastest method per accuracy level, and the
//! work–precision diagram.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::{CycleQuantities, Errors, PrecisionReport, Row, RowOutcome};
use output::files::{OutputError, sci, write_atomic};
use output::plot::{self, Panel, Series};

/// Run time a row is plotted and ranked at: the timed median, else the measured run's.
fn run_time(row: &Row) -> f64 {
    if row.wall_s.is_finite() {
        row.wall_s
    } else {
        row.measured_wall_s
    }
}

/// Least-squares slope of log10 y against log10 x (`None` with fewer than two distinct x).
fn log_log_slope(points: &[(f64, f64)]) -> Option<f64> {
    let logs: Vec<(f64, f64)> = points.iter().map(|(x, y)| (x.log10(), y.log10())).collect();
    let n = logs.len() as f64;
    let mean_x = logs.iter().map(|p| p.0).sum::<f64>() / n;
    let mean_y = logs.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = logs.iter().map(|p| (p.0 - mean_x).powi(2)).sum();
    let sxy: f64 = logs.iter().map(|p| (p.0 - mean_x) * (p.1 - mean_y)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

impl PrecisionReport {
    /// Names of the cycle quantities, in the order of [`Errors::cycle_relative`].
    pub fn quantity_names(&self) -> Vec<String> {
        CycleQuantities {
            wear_volume_m3: vec![0.0; self.joints.len()],
            ..CycleQuantities::default()
        }
        .named(&self.joints)
        .into_iter()
        .map(|(n, _)| n)
        .collect()
    }

    /// One row a run, errors and timings in SI units.
    pub fn csv(&self) -> String {
        let names = self.quantity_names();
        let column = |n: &str| n.replace(' ', "_");
        let mut out = String::from(
            "method,rtol,atol_position_m,status,reference,steps,rejected_steps,rhs_evaluations,\
             factorizations,measured_wall_s,wall_s,wall_wear_s,timed_runs_identical,\
             start_up_rod_m,start_up_journal_m,start_up_m,cycle_max_relative",
        );
        for n in &names {
            let _ = write!(out, ",relative_error_{}", column(n));
        }
        out.push_str(",separation_s");
        for n in &names {
            let _ = write!(out, ",value_{}", column(n));
        }
        out.push_str(",detail\n");
        for r in &self.rows {
            let status = match &r.outcome {
                RowOutcome::Completed { .. } => "completed",
                RowOutcome::Failed { .. } => "failed",
                RowOutcome::Skipped { .. } => "skipped",
            };
            let _ = write!(
                out,
                "{},{:e},{:e},{status},{},{},{},{},{},{},{},{},{}",
                r.method,
                r.rtol,
                r.atol_position_m,
                r.reference,
                r.steps,
                r.rejected_steps,
                r.rhs_evaluations,
                r.factorizations,
                available(r.measured_wall_s),
                available(r.wall_s),
                available(r.wall_wear_s),
                r.timed_runs_identical
            );
            match &r.outcome {
                RowOutcome::Completed { errors, quantities } => {
                    let _ = write!(
                        out,
                        ",{:e},{:e},{:e},{:e}",
                        errors.start_up_rod_m,
                        errors.start_up_journal_m,
                        errors.start_up_m(),
                        errors.cycle_max()
                    );
                    for (_, e) in &errors.cycle_relative {
                        let _ = write!(out, ",{e:e}");
                    }
                    let _ = write!(
                        out,
                        ",{}",
                        errors.separation_s.map_or("none".into(), |t| t.to_string())
                    );
                    for (_, v) in quantities.named(&self.joints) {
                        let _ = write!(out, ",{v:e}");
                    }
                    out.push_str(",\n");
                }
                RowOutcome::Failed { reason } | RowOutcome::Skipped { reason } => {
                    out.push_str(&",".repeat(5 + 2 * names.len()));
                    let _ = writeln!(out, ",\"{}\"", reason.replace('"', "\"\""));
                }
            }
        }
        out
    }

    /// The methods of the sweep, in the order they first appear.
    fn methods(&self) -> Vec<&'static str> {
        let mut methods: Vec<&'static str> = Vec::new();
        for r in &self.rows {
            if !methods.contains(&r.method) {
                methods.push(r.method);
            }
        }
        methods
    }

    /// The fastest completed run whose error `metric` is at most `level`.
    fn fastest(&self, level: f64, metric: impl Fn(&Errors) -> f64) -> Option<&Row> {
        self.rows
            .iter()
            .filter(|r| r.errors().is_some_and(|e| metric(e) <= level))
            .min_by(|a, b| run_time(a).total_cmp(&run_time(b)))
    }

    /// The report: settings, references and their agreement, the convergence, every run, the
    /// cycle quantities, the fastest run per accuracy level.
    pub fn markdown(&self, figure: Option<&str>) -> String {
        let mut out = String::new();
        self.intro(&mut out, figure);
        self.references(&mut out);
        self.convergence(&mut out);
        self.runs(&mut out);
        self.cycle_quantities(&mut out);
        self.fastest_runs(&mut out);
        out
    }

    /// The title, how the sweep was run and what the errors are, the diagram.
    fn intro(&self, out: &mut String, figure: Option<&str>) {
        let _ = writeln!(
            out,
            "# Work–precision: scene `{}`, {} formulation\n",
            self.scene,
            self.formulation.name()
        );
        let _ = writeln!(
            out,
            "Generated by `wearsim precision {}` ({:.0} s of wall time for the whole sweep). \
             Every run integrates {:.4} s from the concentric start with both clearance joints; the \
             absolute tolerances are the scene's clearance-scaled ones times `rtol / \
             solver.rtol`. Run time is the median of {} timed runs with sparse output and no \
             energy audit (the configuration of a wear-stage run; build and assembly excluded), \
             without (`wall`) and with (`wall, wear`) wear accumulation. Errors come from one \
             measured run with output every frame, the energy audit and wear accumulation on. \
             Method and error definitions: `analysis::precision` (crate docs).\n",
            self.scene, self.wall_time_s, self.duration_s, self.repeats
        );
        let _ = writeln!(
            out,
            "- (a) start-up error: largest distance from the reference of the rod position and \
             of the journal-centre paths at {} up to t = {} s (the first impacts);\n\
             - (b) cycle error: largest relative error of the RMS deviation from the ideal \
             mechanism, the energy dissipated by contact damping and by friction, and the wear \
             volume per joint (gathered after the transient window);\n\
             - (c) separation: first time a journal-centre path is {}·clearance away from the \
             reference's (`-`: not within the run).\n",
            self.joints.join(" and "),
            self.start_up_s,
            self.separation_fraction
        );
        if let Some(f) = figure {
            let _ = writeln!(out, "![work–precision diagram]({f})\n");
        }
    }

    /// The references' quantities and how far they agree (the floor of the errors).
    fn references(&self, out: &mut String) {
        let names = self.quantity_names();
        out.push_str("## References\n\n| method | rtol | steps | wall (s) |");
        for n in &names {
            let _ = write!(out, " {n} |");
        }
        out.push_str("\n|---|---:|---:|---:|");
        out.push_str(&"---:|".repeat(names.len()));
        out.push('\n');
        for r in &self.references {
            let _ = write!(
                out,
                "| {} | {:.0e} | {} | {:.2} |",
                r.method, r.rtol, r.steps, r.wall_s
            );
            for (_, v) in r.quantities.named(&self.joints) {
                let _ = write!(out, " {} |", sci(v, 5));
            }
            out.push('\n');
        }
        let a = &self.reference_agreement;
        let _ = writeln!(
            out,
            "\nUnits: deviation m, energies J, wear m³. The two references against each other \
             (the floor below which errors are not resolved): start-up {} m (rod {} m, journals \
             {} m); cycle quantities {} relative ({}); separation {}.\n",
            sci(a.start_up_m(), 2),
            sci(a.start_up_rod_m, 2),
            sci(a.start_up_journal_m, 2),
            sci(a.cycle_max(), 2),
            a.cycle_relative
                .iter()
                .map(|(n, e)| format!("{n} {}", sci(*e, 1)))
                .collect::<Vec<_>>()
                .join(", "),
            a.separation_s
                .map_or("none within the run".into(), |t| format!("at t = {t:.4} s"))
        );
    }

    /// Per method, the slope of its start-up error against the tolerance.
    fn convergence(&self, out: &mut String) {
        out.push_str(
            "## Convergence\n\nSlope of log (a) start-up error against log rtol (least squares over \
             the completed runs; 1 means the error falls in proportion to the tolerance asked \
             for):\n\n| method | runs | slope | (a) at the loosest rtol (m) | (a) at the tightest \
             rtol (m) |\n|---|---:|---:|---:|---:|\n",
        );
        for method in self.methods() {
            let points: Vec<(f64, f64)> = self
                .rows
                .iter()
                .filter(|r| r.method == method)
                .filter_map(|r| r.errors().map(|e| (r.rtol, e.start_up_m())))
                .filter(|(rtol, e)| *rtol > 0.0 && *e > 0.0 && e.is_finite())
                .collect();
            let loosest = points.iter().max_by(|a, b| a.0.total_cmp(&b.0));
            let tightest = points.iter().min_by(|a, b| a.0.total_cmp(&b.0));
            let _ = writeln!(
                out,
                "| {method} | {} | {} | {} | {} |",
                points.len(),
                log_log_slope(&points).map_or("-".into(), |p| format!("{p:.2}")),
                loosest.map_or("-".into(), |p| sci(p.1, 1)),
                tightest.map_or("-".into(), |p| sci(p.1, 1)),
            );
        }
        out.push('\n');
    }

    /// Every run: its cost and its errors, or why it failed or was skipped.
    fn runs(&self, out: &mut String) {
        out.push_str(
            "## Runs\n\n| method | rtol | steps | rejected | wall (s) | wall, wear (s) | \
             (a) start-up (m) | (b) cycle (rel.) | worst (b) quantity | (c) separation (s) | \
             vs | note |\n|---|---:|---:|---:|---:|---:|---:|---:|---|---:|---|---|\n",
        );
        for r in &self.rows {
            match &r.outcome {
                RowOutcome::Completed { errors, .. } => {
                    let worst = errors
                        .cycle_relative
                        .iter()
                        .max_by(|a, b| a.1.total_cmp(&b.1))
                        .map_or("-".into(), |(n, _)| n.clone());
                    let _ = writeln!(
                        out,
                        "| {} | {:.0e} | {} | {} | {} | {} | {} | {} | {worst} | {} | {} | {} |",
                        r.method,
                        r.rtol,
                        r.steps,
                        r.rejected_steps,
                        sci(r.wall_s, 2),
                        sci(r.wall_wear_s, 2),
                        sci(errors.start_up_m(), 2),
                        sci(errors.cycle_max(), 2),
                        errors
                            .separation_s
                            .map_or("-".into(), |t| format!("{t:.4}")),
                        r.reference,
                        if r.timed_runs_identical {
                            ""
                        } else {
                            "timed runs differ"
                        }
                    );
                }
                RowOutcome::Failed { reason } | RowOutcome::Skipped { reason } => {
                    let label = if matches!(r.outcome, RowOutcome::Failed { .. }) {
                        "failed"
                    } else {
                        "skipped"
                    };
                    let _ = writeln!(
                        out,
                        "| {} | {:.0e} | - | - | - | - | - | - | - | - | {} | {label}: {} |",
                        r.method,
                        r.rtol,
                        r.reference,
                        reason.replace('|', "/")
                    );
                }
            }
        }
    }

    /// Per run, the relative error of each cycle quantity, after the references' spread.
    fn cycle_quantities(&self, out: &mut String) {
        let names = self.quantity_names();
        let a = &self.reference_agreement;
        let _ = write!(
            out,
            "\n## Cycle quantities, relative error of each\n\nThe first line is the second \
             reference against the first ({}): the floor below which no run can be judged.\n\n\
             | method | rtol |",
            a.separation_s.map_or(
                "their paths do not separate within the run".to_string(),
                |t| format!(
                    "their journal paths separate at t = {t:.3} s, so after that this is the \
                     quantities' spread between two converged but different trajectories: chaos"
                )
            )
        );
        for n in &names {
            let _ = write!(out, " {n} |");
        }
        out.push_str("\n|---|---:|");
        out.push_str(&"---:|".repeat(names.len()));
        out.push('\n');
        let floor_row = self.references.get(1).map(|r| (r.method, r.rtol));
        let quantity_rows = floor_row
            .map(|(m, rtol)| (format!("{m} (reference)"), rtol, &self.reference_agreement))
            .into_iter()
            .chain(
                self.rows
                    .iter()
                    .filter_map(|r| r.errors().map(|e| (r.method.to_string(), r.rtol, e))),
            );
        for (method, rtol, e) in quantity_rows {
            let _ = write!(out, "| {method} | {rtol:.0e} |");
            for (_, v) in &e.cycle_relative {
                let _ = write!(out, " {} |", sci(*v, 1));
            }
            out.push('\n');
        }
    }

    /// Per accuracy level, the fastest run that reached it.
    fn fastest_runs(&self, out: &mut String) {
        out.push_str("\n## Fastest run per accuracy level\n\n");
        let describe = |r: Option<&Row>| {
            r.map_or("none".to_string(), |r| {
                format!("{} rtol {:.0e}, {:.3} s", r.method, r.rtol, run_time(r))
            })
        };
        out.push_str("| (a) start-up error ≤ (m) | fastest run |\n|---:|---|\n");
        for level in [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8] {
            let _ = writeln!(
                out,
                "| {level:.0e} | {} |",
                describe(self.fastest(level, Errors::start_up_m))
            );
        }
        // Cycle quantities cannot be judged below the references' own spread, so their levels
        // are multiples of it.
        let floor = self.reference_agreement.cycle_max();
        out.push_str("\n| (b) cycle error ≤ (relative) | fastest run |\n|---:|---|\n");
        for multiple in [1.0, 2.0, 4.0] {
            let level = multiple * floor;
            let _ = writeln!(
                out,
                "| {} ({multiple}× the references' spread) | {} |",
                sci(level, 1),
                describe(self.fastest(level, Errors::cycle_max))
            );
        }
    }

    /// The work–precision diagram: errors (a), (b), (c) against run time, and error (a)
    /// against the tolerance asked for, one line per method.
    pub fn plot(&self, path: &Path) -> Result<(), OutputError> {
        let methods = self.methods();
        let column = |method: &str, x: &dyn Fn(&Row) -> f64, y: &dyn Fn(&Errors) -> f64| {
            let rows: Vec<&Row> = self
                .rows
                .iter()
                .filter(|r| r.method == method && r.errors().is_some())
                .collect();
            let xs: Vec<f64> = rows.iter().map(|r| x(r)).collect();
            let ys: Vec<f64> = rows.iter().filter_map(|r| r.errors()).map(y).collect();
            (xs, ys)
        };
        let separation = |e: &Errors| e.separation_s.unwrap_or(f64::NAN);
        let data: Vec<[(Vec<f64>, Vec<f64>); 4]> = methods
            .iter()
            .map(|m| {
                [
                    column(m, &run_time, &Errors::start_up_m),
                    column(m, &run_time, &Errors::cycle_max),
                    column(m, &run_time, &separation),
                    column(m, &|r| r.rtol, &Errors::start_up_m),
                ]
            })
            .collect();
        let series = |k: usize| -> Vec<Series<'_>> {
            methods
                .iter()
                .zip(&data)
                .map(|(m, d)| Series {
                    label: m,
                    x: &d[k].0,
                    y: &d[k].1,
                })
                .collect()
        };
        let a = &self.reference_agreement;
        let floor = "references vs each other";
        let panels = [
            Panel {
                title: "(a) start-up paths: error vs run time",
                x_label: "run time per cycle (s)",
                y_label: "max error (m)",
                series: series(0),
                levels: vec![(a.start_up_m(), floor)],
                legend_top: false,
                errors: Vec::new(),
                dashed: Vec::new(),
            },
            Panel {
                title: "(b) cycle quantities: largest relative error",
                x_label: "run time per cycle (s)",
                y_label: "relative error",
                series: series(1),
                levels: vec![(a.cycle_max(), floor)],
                legend_top: false,
                errors: Vec::new(),
                dashed: Vec::new(),
            },
            Panel {
                title: "(c) journal paths separate from the reference at",
                x_label: "run time per cycle (s)",
                y_label: "separation time (s)",
                series: series(2),
                levels: a.separation_s.map(|t| vec![(t, floor)]).unwrap_or_default(),
                legend_top: true,
                errors: Vec::new(),
                dashed: Vec::new(),
            },
            Panel {
                title: "(a) start-up error vs tolerance asked for",
                x_label: "rtol (atol scaled with it)",
                y_label: "max error (m)",
                series: series(3),
                levels: vec![(a.start_up_m(), floor)],
                legend_top: false,
                errors: Vec::new(),
                dashed: Vec::new(),
            },
        ];
        let title = format!(
            "Work–precision, scene {}: {:.3} s from the concentric start",
            self.scene, self.duration_s
        );
        plot::log_panels(path, &title, (1400, 1050), 2, &panels)
    }

    /// Writes `precision.csv`, `precision.md`, `precision.json` and `precision.png` into `dir`.
    pub fn write(&self, dir: &Path) -> Result<Vec<PathBuf>, OutputError> {
        let png = dir.join("precision.png");
        self.plot(&png)?;
        let files = [
            (dir.join("precision.csv"), self.csv()),
            (
                dir.join("precision.md"),
                self.markdown(Some("precision.png")),
            ),
        ];
        let mut paths = vec![png];
        for (path, text) in files {
            write_atomic(&path, text.as_bytes())?;
            paths.push(path);
        }
        let json = dir.join("precision.json");
        output::files::write_json(&json, self)?;
        paths.push(json);
        Ok(paths)
    }
}

/// A value, or `n/a` where it was not measured (a failed run, no timed repeats): never `NaN`.
fn available(value: f64) -> String {
    if value.is_finite() {
        value.to_string()
    } else {
        "n/a".into()
    }
}
