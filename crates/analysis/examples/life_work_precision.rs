//! A whole life's work against its precision: the stage's peak depths and worn volumes of
//! `wearsim run`s at other settings, against a fine reference run, with the noise each run
//! prints for itself; and the bias of a setting, a coarse run against its refined twin.
//!
//! ```sh
//! cargo run --release -p analysis --example life_work_precision -- MANIFEST OUT [--pair COARSE,FINE]...
//! ```
//!
//! `MANIFEST` is a CSV file with the header `label,family,dir,cpu_s`: one row per run, `dir`
//! its output folder (its `summary.json` is read), `cpu_s` the CPU time it took (user + system,
//! e.g. from `/usr/bin/time -v`), `family` the setting it varies (runs of one family are joined
//! by a line in the figure; `reference` marks the one fine run the others are judged against,
//! `default` the run at the default settings, a point of every family's line).
//! For every run the error of each wearing joint's bearing and pin peak depth (and of its worn
//! volume) is the difference from the reference over the reference's value, with the noise
//! `√(σ² + σ_ref²)` of both runs' printed noises; a panel shows their root-mean-square over the
//! joints' peaks (and volumes) against the CPU time, with that noise as a bar, and the runs' own
//! printed noise (root-mean-square, relative) as a dashed curve. Each `--pair COARSE,FINE`
//! prints the bias of the coarse setting, its values minus the fine run's, with the combined
//! noise and the bias over the coarse run's own noise. Writes `OUT/life-work-precision.png` and
//! `OUT/life-work-precision.csv`, and prints both tables as markdown.

use std::collections::BTreeMap;
use std::error::Error;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use output::plot::{Panel, Series, log_panels};

#[path = "support/wear_runs.rs"]
mod wear_runs;
use wear_runs::{QUANTITIES, Value, WearResults, read_wear_results};

/// What one run gives: per joint, bearing peak, pin peak, worn volume.
#[derive(Debug, Clone)]
struct Run {
    label: String,
    family: String,
    cpu_s: f64,
    substeps: u64,
    joints: Vec<(String, [Value; 3])>,
}

/// One family's line in the figure, its runs by CPU time: per panel, the error (rms), its
/// noise and the runs' printed noise.
struct Curve {
    family: String,
    cpu_s: Vec<f64>,
    peaks: [Vec<f64>; 3],
    volumes: [Vec<f64>; 3],
}

fn read_run(label: &str, family: &str, dir: &Path, cpu_s: f64) -> Result<Run, Box<dyn Error>> {
    let WearResults { joints, substeps } = read_wear_results(dir)?;
    Ok(Run {
        label: label.to_string(),
        family: family.to_string(),
        cpu_s,
        substeps,
        joints,
    })
}

/// Relative differences of `run` from `reference` (value, combined noise) for the quantities
/// `picks` (indices into [`QUANTITIES`]) of every joint.
fn relative_errors(run: &Run, reference: &Run, picks: &[usize]) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for ((_, values), (_, reference)) in run.joints.iter().zip(&reference.joints) {
        for &q in picks {
            let (v, r) = (values[q], reference[q]);
            out.push((
                (v.value - r.value) / r.value,
                v.noise.hypot(r.noise) / r.value,
            ));
        }
    }
    out
}

fn rms(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = values.fold((0.0, 0usize), |(s, n), v| (s + v * v, n + 1));
    if n == 0 {
        f64::NAN
    } else {
        (sum / n as f64).sqrt()
    }
}

/// The run's own printed noise, relative, root-mean-square over `picks` of every joint.
fn printed_noise(run: &Run, picks: &[usize]) -> f64 {
    rms(run
        .joints
        .iter()
        .flat_map(|(_, v)| picks.iter().map(move |&q| v[q].noise / v[q].value)))
}

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: life_work_precision MANIFEST OUT [--pair COARSE,FINE]...";
    let (Some(manifest), Some(out)) = (args.first(), args.get(1)) else {
        return Err(usage.into());
    };
    let mut pairs = Vec::new();
    let mut rest = args[2..].iter();
    while let Some(flag) = rest.next() {
        match (flag.as_str(), rest.next().and_then(|p| p.split_once(','))) {
            ("--pair", Some((a, b))) => pairs.push((a.to_string(), b.to_string())),
            _ => return Err(usage.into()),
        }
    }
    let base = Path::new(manifest).parent().unwrap_or(Path::new("."));
    let text = std::fs::read_to_string(manifest).map_err(|e| format!("{manifest}: {e}"))?;
    let mut runs = Vec::new();
    for (k, line) in text.lines().enumerate().skip(1) {
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        let [label, family, dir, cpu] = fields[..] else {
            return Err(format!("{manifest} line {}: want label,family,dir,cpu_s", k + 1).into());
        };
        let cpu: f64 = cpu
            .parse()
            .map_err(|e| format!("{manifest} line {}: cpu_s: {e}", k + 1))?;
        runs.push(read_run(label, family, &base.join(dir), cpu)?);
    }
    let reference = runs
        .iter()
        .find(|r| r.family == "reference")
        .ok_or("the manifest has no run of family `reference`")?
        .clone();
    let find = |label: &str| {
        runs.iter()
            .find(|r| r.label == label)
            .ok_or_else(|| format!("no run labelled `{label}`"))
    };
    let peaks = [0, 1];
    let volume = [2];

    // The table of every run against the reference.
    let mut md = String::from(
        "| run | setting varied | CPU (s) | sub-steps | peaks: error (rms, %) | noise of it (%) | \
         printed noise (%) | volumes: error (rms, %) | noise of it (%) | printed noise (%) |\n\
         |---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    let mut csv = String::from(
        "label,family,cpu_s,substeps,peak_error,peak_error_noise,peak_printed_noise,\
         volume_error,volume_error_noise,volume_printed_noise\n",
    );
    let summary = |run: &Run, picks: &[usize]| {
        let e = relative_errors(run, &reference, picks);
        (
            rms(e.iter().map(|(v, _)| *v)),
            rms(e.iter().map(|(_, n)| *n)),
            printed_noise(run, picks),
        )
    };
    for run in &runs {
        let (pe, pn, pp) = summary(run, &peaks);
        let (ve, vn, vp) = summary(run, &volume);
        let _ = writeln!(
            md,
            "| {} | {} | {:.0} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} |",
            run.label,
            run.family,
            run.cpu_s,
            run.substeps,
            100.0 * pe,
            100.0 * pn,
            100.0 * pp,
            100.0 * ve,
            100.0 * vn,
            100.0 * vp
        );
        let _ = writeln!(
            csv,
            "{},{},{},{},{pe:e},{pn:e},{pp:e},{ve:e},{vn:e},{vp:e}",
            run.label, run.family, run.cpu_s, run.substeps
        );
    }
    println!("{md}");

    // The bias of each coarse setting against its refined twin.
    if !pairs.is_empty() {
        let mut bias = String::from(
            "| coarse − fine | joint | quantity | coarse | fine | bias ± noise | bias / coarse's noise |\n\
             |---|---|---|---:|---:|---:|---:|\n",
        );
        for (coarse, fine) in &pairs {
            let (c, f) = (find(coarse)?, find(fine)?);
            for ((name, cv), (_, fv)) in c.joints.iter().zip(&f.joints) {
                for (q, what) in QUANTITIES.iter().enumerate() {
                    let (a, b) = (cv[q], fv[q]);
                    let scale = if q == 2 { 1e9 } else { 1e6 };
                    let unit = if q == 2 { "mm³" } else { "µm" };
                    let d = a.value - b.value;
                    let _ = writeln!(
                        bias,
                        "| {coarse} − {fine} | {name} | {what} ({unit}) | {:.2} ± {:.2} | {:.2} ± {:.2} | {:+.2} ± {:.2} | {:+.2} |",
                        a.value * scale,
                        a.noise * scale,
                        b.value * scale,
                        b.noise * scale,
                        d * scale,
                        a.noise.hypot(b.noise) * scale,
                        d / a.noise
                    );
                }
            }
        }
        println!("{bias}");
    }

    // The figure: one line per family through the default, sorted by CPU time.
    let mut families: BTreeMap<&str, Vec<&Run>> = BTreeMap::new();
    for run in runs
        .iter()
        .filter(|r| !matches!(r.family.as_str(), "reference" | "default"))
    {
        families.entry(run.family.as_str()).or_default().push(run);
    }
    // The default setting is a point of every family.
    for default in runs.iter().filter(|r| r.family == "default") {
        for members in families.values_mut() {
            members.push(default);
        }
    }
    for members in families.values_mut() {
        members.sort_by(|a, b| a.cpu_s.total_cmp(&b.cpu_s));
    }
    let mut columns: Vec<Curve> = Vec::new();
    for (family, members) in &families {
        let mut p = [Vec::new(), Vec::new(), Vec::new()];
        let mut v = [Vec::new(), Vec::new(), Vec::new()];
        for run in members {
            let (pe, pn, pp) = summary(run, &peaks);
            let (ve, vn, vp) = summary(run, &volume);
            for (slot, x) in p.iter_mut().zip([pe, pn, pp]) {
                slot.push(x);
            }
            for (slot, x) in v.iter_mut().zip([ve, vn, vp]) {
                slot.push(x);
            }
        }
        columns.push(Curve {
            family: family.to_string(),
            cpu_s: members.iter().map(|r| r.cpu_s).collect(),
            peaks: p,
            volumes: v,
        });
    }
    let labels: Vec<(String, String)> = columns
        .iter()
        .map(|c| {
            let f = &c.family;
            (format!("{f}: error"), format!("{f}: printed noise"))
        })
        .collect();
    let panel = |title: &'static str, pick: fn(&Curve) -> &[Vec<f64>; 3]| {
        let mut series = Vec::new();
        let mut errors = Vec::new();
        let mut dashed = Vec::new();
        for (k, c) in columns.iter().enumerate() {
            let values = pick(c);
            series.push(Series {
                label: &labels[k].0,
                x: &c.cpu_s,
                y: &values[0],
            });
            errors.push(&values[1][..]);
            dashed.push(Series {
                label: &labels[k].1,
                x: &c.cpu_s,
                y: &values[2],
            });
        }
        Panel {
            title,
            x_label: "CPU time of the run (s)",
            y_label: "relative error against the reference (rms)",
            series,
            levels: Vec::new(),
            legend_top: false,
            errors,
            dashed,
        }
    };
    let panels = [
        panel("peak depths (bearing and pin of each joint)", |c| &c.peaks),
        panel("worn volumes (each joint)", |c| &c.volumes),
    ];
    let out = PathBuf::from(out);
    std::fs::create_dir_all(&out)?;
    let title = format!(
        "a whole life's work and precision: errors against `{}`, noise bars",
        reference.label
    );
    log_panels(
        out.join("life-work-precision.png"),
        &title,
        (1500, 650),
        2,
        &panels,
    )?;
    std::fs::write(out.join("life-work-precision.csv"), csv)?;
    println!("wrote {}", out.join("life-work-precision.png").display());
    Ok(())
}
