//! The bias of each setting that discretises a wear stage, measured on an ensemble of runs
//! rather than one pair, and whether the noise the runs print is the scatter of independent
//! repeats.
//!
//! ```sh
//! cargo run --release -p analysis --example bias_ensemble -- MANIFEST [--together SETTING,...]
//! ```
//!
//! `MANIFEST` is a CSV file with the header `dir,SETTING,SETTING,...`: one row per
//! `wearsim run` output folder (its `summary.json` is read; a relative folder is taken from
//! the manifest's own folder), then per setting `0` (the default's value) or `1` (refined).
//! Rows whose settings are all `0` are repeats of the default from other trajectory starts
//! (e.g. other `run.transient_window`); the others form a two-level design, best a
//! fractional factorial in which each setting is refined in half the runs.
//!
//! Each wear result `y` (per wearing joint: bearing and pin peak depth, worn volume) is fitted
//! by least squares to `y = μ + Σ_k b_k x_k`, `x_k` the settings' 0/1: a two-level design's main
//! effects. The default's bias from setting `k` is `−b_k` (coarse minus refined), with the
//! standard error the fit's residuals give (`s² (XᵀX)⁻¹`, `s²` the residual variance on its
//! degrees of freedom), and in units of `σ`, the default's printed noise (root mean square over
//! its repeats). The bias of all settings at once is `−Σ b_k`. Printed as markdown:
//! 1. the default's repeats: values, mean ± standard deviation, printed noise, their ratio with
//!    its 95 % interval (the scatter of `n` values is uncertain: χ² on `n − 1` degrees of
//!    freedom, by the Wilson–Hilferty approximation, within 1 % of the exact quantiles here);
//! 2. each setting's bias ± its standard error, in the quantity's unit and in σ; the bias of
//!    the settings refined together (all, or those `--together` names) as the sum of theirs,
//!    and directly, the mean of the runs refined in exactly those settings against the
//!    repeats' (with at least two such runs: Welch's standard error, no additivity assumed);
//! 3. the printed noise against the scatter over all runs: the residuals, each over its run's
//!    printed noise and `√(1 − h_ii)` (the fit's leverage), should have a unit root mean square.

use std::error::Error;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use nalgebra::{DMatrix, DVector};

#[path = "support/wear_runs.rs"]
mod wear_runs;
use wear_runs::{QUANTITIES, Value, read_wear_results};

/// One run: its folder's name, its settings (0/1) and its wear results, flattened per joint
/// and quantity.
struct Run {
    name: String,
    substeps: u64,
    settings: Vec<f64>,
    values: Vec<Value>,
}

/// The χ² distribution's `p` quantile on `k` degrees of freedom for p = 0.025 or 0.975
/// (Wilson–Hilferty).
fn chi2_quantile(p: f64, k: f64) -> f64 {
    const Z975: f64 = 1.959_963_985;
    let z = if p > 0.5 { Z975 } else { -Z975 };
    let a = 2.0 / (9.0 * k);
    k * (1.0 - a + z * a.sqrt()).powi(3)
}

/// The mean of `values` (at least two) and their sample variance (on `n − 1` degrees of freedom).
fn mean_and_variance(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let variance = values.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, variance)
}

/// The bias table's cells so far: how many, how many within half the noise `σ`, how many
/// beyond twice their standard error.
#[derive(Default)]
struct Tally {
    cells: usize,
    within: usize,
    significant: usize,
}

impl Tally {
    /// Writes one cell, `bias ± se` and both in units of `sigma`, and counts it.
    fn cell(&mut self, out: &mut String, bias: f64, se: f64, sigma: f64) -> std::fmt::Result {
        self.cells += 1;
        self.within += usize::from(bias.abs() <= 0.5 * sigma);
        self.significant += usize::from(bias.abs() > 2.0 * se);
        write!(
            out,
            " {bias:+.1} ± {se:.1} ({:+.2} ± {:.2}σ) |",
            bias / sigma,
            se / sigma
        )
    }
}

/// The quantity's unit and its scale from SI.
fn unit(quantity: usize) -> (&'static str, f64) {
    if QUANTITIES[quantity] == "worn volume" {
        ("mm³", 1e9)
    } else {
        ("µm", 1e6)
    }
}

/// The manifest read: the settings' names, the wearing joints' names and the runs.
struct Manifest {
    settings: Vec<String>,
    joints: Vec<String>,
    runs: Vec<Run>,
}

fn read_manifest(path: &Path) -> Result<Manifest, Box<dyn Error>> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let base = path.parent().map_or_else(PathBuf::new, Path::to_path_buf);
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let header: Vec<&str> = lines.next().ok_or("empty manifest")?.split(',').collect();
    if header.first().map(|h| h.trim()) != Some("dir") || header.len() < 2 {
        return Err("the manifest's header must be `dir,SETTING,...`".into());
    }
    let settings: Vec<String> = header[1..].iter().map(|s| s.trim().to_string()).collect();
    let mut joints: Option<Vec<String>> = None;
    let mut runs = Vec::new();
    for (row, line) in lines.enumerate() {
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != header.len() {
            return Err(format!(
                "row {}: {} fields, the header has {}",
                row + 1,
                fields.len(),
                header.len()
            )
            .into());
        }
        let x = fields[1..]
            .iter()
            .map(|f| match *f {
                "0" => Ok(0.0),
                "1" => Ok(1.0),
                other => Err(format!("row {}: setting `{other}` is not 0 or 1", row + 1)),
            })
            .collect::<Result<Vec<f64>, _>>()?;
        let results = read_wear_results(&base.join(fields[0]))?;
        let names: Vec<String> = results.joints.iter().map(|(n, _)| n.clone()).collect();
        match &joints {
            None => joints = Some(names),
            Some(j) if *j != names => {
                return Err(
                    format!("{}: other wearing joints than the first run's", fields[0]).into(),
                );
            }
            Some(_) => {}
        }
        runs.push(Run {
            name: fields[0].to_string(),
            substeps: results.substeps,
            settings: x,
            values: results
                .joints
                .iter()
                .flat_map(|(_, v)| v.iter().copied())
                .collect(),
        });
    }
    Ok(Manifest {
        settings,
        joints: joints.unwrap_or_default(),
        runs,
    })
}

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: bias_ensemble MANIFEST [--together SETTING,SETTING,...]";
    let (manifest, together) = match args.as_slice() {
        [manifest] => (manifest, None),
        [manifest, flag, list] if flag == "--together" => (manifest, Some(list)),
        _ => return Err(usage.into()),
    };
    let Manifest {
        settings,
        joints,
        runs,
    } = read_manifest(Path::new(manifest))?;
    // The settings refined together in the reference ensemble (default: all of them).
    let together: Vec<bool> = match together {
        None => vec![true; settings.len()],
        Some(list) => {
            let names: Vec<&str> = list.split(',').map(str::trim).collect();
            if let Some(unknown) = names.iter().find(|n| !settings.iter().any(|s| s == *n)) {
                return Err(
                    format!("--together: `{unknown}` is not a setting of the manifest").into(),
                );
            }
            settings
                .iter()
                .map(|s| names.contains(&s.as_str()))
                .collect()
        }
    };
    let labels: Vec<(String, usize)> = joints
        .iter()
        .flat_map(|j| (0..QUANTITIES.len()).map(move |q| (format!("{j} {}", QUANTITIES[q]), q)))
        .collect();
    let mut out = String::new();

    // 1. The default's repeats.
    let repeats: Vec<&Run> = runs
        .iter()
        .filter(|r| r.settings.iter().all(|&x| x == 0.0))
        .collect();
    let n = repeats.len();
    if n < 3 {
        return Err(format!("{n} repeats of the default: at least 3 are needed").into());
    }
    let dof = (n - 1) as f64;
    let (lo, hi) = (
        (chi2_quantile(0.025, dof) / dof).sqrt(),
        (chi2_quantile(0.975, dof) / dof).sqrt(),
    );
    writeln!(out, "## The default repeated from {n} trajectory starts\n")?;
    writeln!(
        out,
        "| quantity | the repeats | mean ± standard deviation | printed noise (rms) | printed / scatter (95 %) |"
    )?;
    writeln!(out, "|---|---|---|---|---|")?;
    let mut sigma = Vec::new();
    for (k, (label, q)) in labels.iter().enumerate() {
        let (u, scale) = unit(*q);
        let v: Vec<f64> = repeats.iter().map(|r| r.values[k].value * scale).collect();
        let (mean, variance) = mean_and_variance(&v);
        let sd = variance.sqrt();
        let printed = (repeats
            .iter()
            .map(|r| (r.values[k].noise * scale).powi(2))
            .sum::<f64>()
            / n as f64)
            .sqrt();
        sigma.push(printed);
        let list: Vec<String> = v.iter().map(|x| format!("{x:.1}")).collect();
        writeln!(
            out,
            "| {label} | {} | {mean:.1} ± {sd:.2} {u} ({:.2} %) | {printed:.2} {u} | {:.2} ({:.2}–{:.2}) |",
            list.join(" "),
            100.0 * sd / mean,
            printed / sd,
            printed / sd * lo,
            printed / sd * hi
        )?;
    }

    // 2. Least squares over every run.
    let p = settings.len() + 1;
    let m = runs.len();
    if m <= p {
        return Err(format!("{m} runs cannot fit {p} coefficients").into());
    }
    let x = DMatrix::from_fn(
        m,
        p,
        |i, j| if j == 0 { 1.0 } else { runs[i].settings[j - 1] },
    );
    let xtx_inv = (x.transpose() * &x)
        .try_inverse()
        .ok_or("the design does not separate the settings (each must be refined in some run and not in another)")?;
    let hat = &x * &xtx_inv * x.transpose();
    let residual_dof = (m - p) as f64;
    writeln!(
        out,
        "\n## The default's bias from each setting (coarse − refined), {m} runs, {} degrees of freedom\n",
        m - p
    )?;
    write!(out, "| refinement |")?;
    for (label, _) in &labels {
        write!(out, " {label} |")?;
    }
    writeln!(out, "\n|---|{}", "---|".repeat(labels.len()))?;
    let mut rows: Vec<(String, DVector<f64>)> = settings
        .iter()
        .enumerate()
        .map(|(k, s)| {
            (
                s.clone(),
                DVector::from_fn(p, |j, _| if j == k + 1 { 1.0 } else { 0.0 }),
            )
        })
        .collect();
    let together_names: Vec<&str> = settings
        .iter()
        .zip(&together)
        .filter(|(_, t)| **t)
        .map(|(s, _)| s.as_str())
        .collect();
    rows.push((
        format!("{} (sum of the above)", together_names.join(" + ")),
        DVector::from_fn(p, |j, _| if j > 0 && together[j - 1] { 1.0 } else { 0.0 }),
    ));
    let mut fits = Vec::new();
    for (k, (_, q)) in labels.iter().enumerate() {
        let scale = unit(*q).1;
        let y = DVector::from_fn(m, |i, _| runs[i].values[k].value * scale);
        let b = &xtx_inv * x.transpose() * &y;
        let r = &y - &x * &b;
        let s2 = r.norm_squared() / residual_dof;
        fits.push((b, r, s2));
    }
    let mut tally = Tally::default();
    for (name, c) in &rows {
        write!(out, "| {name} |")?;
        for (k, (b, _, s2)) in fits.iter().enumerate() {
            let bias = -c.dot(b);
            let se = (s2 * (c.transpose() * &xtx_inv * c)[(0, 0)]).sqrt();
            tally.cell(&mut out, bias, se, sigma[k])?;
        }
        writeln!(out)?;
    }
    // The same, directly: the runs refined in exactly those settings against the repeats
    // (Welch's standard error from each group's own scatter; no additivity assumed).
    let reference: Vec<&Run> = runs
        .iter()
        .filter(|r| {
            r.settings
                .iter()
                .zip(&together)
                .all(|(x, t)| (*x == 1.0) == *t)
        })
        .collect();
    if reference.len() >= 2 {
        write!(
            out,
            "| {} (directly, {} runs against the {n} repeats) |",
            together_names.join(" + "),
            reference.len()
        )?;
        for (k, (_, q)) in labels.iter().enumerate() {
            let scale = unit(*q).1;
            let stats = |group: &[&Run]| {
                let v: Vec<f64> = group.iter().map(|r| r.values[k].value * scale).collect();
                let (mean, variance) = mean_and_variance(&v);
                (mean, variance / v.len() as f64)
            };
            let ((md, vd), (mf, vf)) = (stats(&repeats), stats(&reference));
            tally.cell(&mut out, md - mf, (vd + vf).sqrt(), sigma[k])?;
        }
        writeln!(out)?;
    }
    writeln!(
        out,
        "\nσ (the default's printed noise): {}. {} of {} biases within σ/2; {} of {} beyond twice their standard error.",
        labels
            .iter()
            .zip(&sigma)
            .map(|((l, q), s)| format!("{l} {s:.2} {}", unit(*q).0))
            .collect::<Vec<_>>()
            .join(", "),
        tally.within,
        tally.cells,
        tally.significant,
        tally.cells
    )?;

    // 3. The printed noise against the residuals of every run.
    let (lo, hi) = (
        (chi2_quantile(0.025, residual_dof) / residual_dof).sqrt(),
        (chi2_quantile(0.975, residual_dof) / residual_dof).sqrt(),
    );
    writeln!(
        out,
        "\nPrinted noise over the scatter, from every run's residual (95 %):"
    )?;
    for (k, (label, q)) in labels.iter().enumerate() {
        let scale = unit(*q).1;
        let r = &fits[k].1;
        // A run the fit passes through (leverage 1, e.g. the only run of a setting) has no
        // residual to tell.
        let z: Vec<f64> = (0..m)
            .filter(|&i| 1.0 - hat[(i, i)] > 1e-9)
            .map(|i| r[i] / (runs[i].values[k].noise * scale * (1.0 - hat[(i, i)]).sqrt()))
            .collect();
        let z2 = z.iter().map(|v| v * v).sum::<f64>() / z.len() as f64;
        let ratio = 1.0 / z2.sqrt();
        writeln!(
            out,
            "- {label}: {ratio:.2} ({:.2}–{:.2})",
            ratio * lo,
            ratio * hi
        )?;
    }
    writeln!(
        out,
        "\nRuns (sub-steps): {}",
        runs.iter()
            .map(|r| format!("{} ({})", r.name, r.substeps))
            .collect::<Vec<_>>()
            .join(", ")
    )?;
    print!("{out}");
    Ok(())
}
