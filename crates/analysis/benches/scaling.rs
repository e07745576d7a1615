//! How the cost of a run grows with the size of the mechanism:
//! `cargo bench -p analysis --bench scaling`.
//!
//! The mechanism is [`clearance::family::chain`] with `N` bodies and a clearance joint at every
//! 5th joint, driven from rest. For each `N` and each path — Cartesian coordinates with the
//! dense LU of the reduced iteration matrix (default), the same with faer's sparse LU, and
//! joint coordinates — it times [`multibody::System::simulate`] over a fixed interval from the
//! assembled start (the pins fall into their bearings and the impacts begin after ~5 ms), with
//! output at the end only and no energy audit, and reports medians over the repeats (interleaved across the paths) of the cost
//! per accepted step and per simulated second. One extra run per case with the energy audit on
//! (not timed) reports the physics checks: constraint drift and the energy residual.
//!
//! Prints a markdown table, the fitted slopes `cost ∝ N^p` and the crossovers, writes
//! `docs/figures/scaling.csv` and the log–log figure `docs/figures/scaling.png`.
//! Environment: `SCALING_SIZES` (comma-separated `N`, default 5,10,20,50,100,200),
//! `SCALING_REPEATS` (default 5), `SCALING_INTERVAL` (simulated seconds, default 0.03).

use std::path::PathBuf;
use std::time::{Duration, Instant};

use clearance::family::{ChainParams, chain};
use multibody::{Formulation, LinearSolverKind, OutputTimes, SimulationOptions};
use output::plot::{Panel, Series, log_panels};

/// Clearance at every 5th joint.
const PERIOD: usize = 5;

struct Path {
    label: &'static str,
    formulation: Formulation,
    solver: LinearSolverKind,
}

const PATHS: [Path; 3] = [
    Path {
        label: "Cartesian, dense LU",
        formulation: Formulation::Cartesian,
        solver: LinearSolverKind::Dense,
    },
    Path {
        label: "Cartesian, sparse LU (faer)",
        formulation: Formulation::Cartesian,
        solver: LinearSolverKind::SparseFaer,
    },
    Path {
        label: "joint coordinates, dense LU",
        formulation: Formulation::JointCoordinates,
        solver: LinearSolverKind::Dense,
    },
];

#[derive(Debug, Clone, Default)]
struct Measured {
    steps: usize,
    /// Median wall time of a run (s).
    wall: f64,
    per_step: f64,
    per_simulated_second: f64,
    drift: f64,
    energy: f64,
}

fn env_list(name: &str, default: &[usize]) -> Vec<usize> {
    std::env::var(name)
        .ok()
        .map(|s| s.split(',').filter_map(|v| v.trim().parse().ok()).collect())
        .filter(|v: &Vec<usize>| !v.is_empty())
        .unwrap_or_else(|| default.to_vec())
}

fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    let k = values.len();
    if k == 0 {
        f64::NAN
    } else if k % 2 == 1 {
        values[k / 2]
    } else {
        0.5 * (values[k / 2 - 1] + values[k / 2])
    }
}

/// One run of the `bodies`-body chain on `path`: (wall time, steps, drift, energy residual).
fn run(bodies: usize, path: &Path, interval: f64, audit: bool) -> (f64, usize, f64, f64) {
    let mut built = chain(bodies, PERIOD, &ChainParams::default()).expect("the chain builds");
    let (q, qd) = built.system.initial_guess();
    let start = built
        .system
        .assemble(0.0, &q, &qd)
        .expect("the chain assembles");
    let mut options = SimulationOptions::until(interval);
    options.output = OutputTimes::At(vec![interval]);
    options.record_trajectory = false;
    options.energy_audit = audit;
    options.formulation = path.formulation;
    options.linear_solver = path.solver;
    options.max_wall_time = Some(Duration::from_secs(600));
    let clock = Instant::now();
    let result = built
        .system
        .simulate(&start, &options, &mut ())
        .unwrap_or_else(|e| panic!("{bodies} bodies, {}: {e}", path.label));
    let wall = clock.elapsed().as_secs_f64();
    let energy = result.energy.map_or(f64::NAN, |e| e.relative_residual());
    (wall, result.statistics.steps, result.drift.position, energy)
}

/// Least-squares slope of `ln y` against `ln x`.
fn slope(x: &[f64], y: &[f64]) -> f64 {
    let points: Vec<(f64, f64)> = x.iter().zip(y).map(|(a, b)| (a.ln(), b.ln())).collect();
    let k = points.len() as f64;
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / k, b + y / k));
    let (sxy, sxx) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    sxy / sxx
}

/// Where `a` and `b` trade places, interpolated log-linearly between the measured sizes: which
/// is cheaper at the smallest size, then every size where the order flips.
fn crossover(sizes: &[usize], a: &[f64], b: &[f64]) -> String {
    let ratio: Vec<f64> = a.iter().zip(b).map(|(a, b)| (a / b).ln()).collect();
    let order = |r: f64| if r < 0.0 { "cheaper" } else { "dearer" };
    let mut text = format!("{} at N = {}", order(ratio[0]), sizes[0]);
    for k in 1..sizes.len() {
        if (ratio[k] < 0.0) != (ratio[k - 1] < 0.0) {
            let (x0, x1) = ((sizes[k - 1] as f64).ln(), (sizes[k] as f64).ln());
            let x = x0 + (x1 - x0) * ratio[k - 1] / (ratio[k - 1] - ratio[k]);
            text += &format!(", {} from N ≈ {:.0}", order(ratio[k]), x.exp());
        }
    }
    text
}

fn main() {
    // `cargo bench` passes `--bench`; nothing else is expected.
    let sizes = env_list("SCALING_SIZES", &[5, 10, 20, 50, 100, 200]);
    let repeats = env_list("SCALING_REPEATS", &[5])[0].max(1);
    let interval: f64 = std::env::var("SCALING_INTERVAL")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.03);
    let mut table = vec![vec![Measured::default(); sizes.len()]; PATHS.len()];
    println!(
        "chain of N bodies, clearance at every {PERIOD}th joint, {interval} s from rest, medians of {repeats}"
    );
    println!(
        "| N | coordinates | path | steps | run (s) | per step (ms) | per simulated s (s) | drift (m) | energy residual |"
    );
    println!("|---:|---:|---|---:|---:|---:|---:|---:|---:|");
    for (k, &bodies) in sizes.iter().enumerate() {
        let checks: Vec<(f64, f64)> = PATHS
            .iter()
            .map(|path| {
                let (_, _, drift, energy) = run(bodies, path, interval, true);
                (drift, energy)
            })
            .collect();
        // Repeats interleave the paths, so a change in the machine's load affects all alike.
        let mut walls = vec![Vec::new(); PATHS.len()];
        let mut steps = vec![0; PATHS.len()];
        for _ in 0..repeats {
            for (p, path) in PATHS.iter().enumerate() {
                let (wall, s, _, _) = run(bodies, path, interval, false);
                walls[p].push(wall);
                steps[p] = s;
            }
        }
        for (p, path) in PATHS.iter().enumerate() {
            let wall = median(&mut walls[p]);
            let m = Measured {
                steps: steps[p],
                wall,
                per_step: wall / steps[p].max(1) as f64,
                per_simulated_second: wall / interval,
                drift: checks[p].0,
                energy: checks[p].1,
            };
            println!(
                "| {bodies} | {} | {} | {} | {:.3} | {:.3} | {:.2} | {:.1e} | {:.1e} |",
                3 * bodies,
                path.label,
                m.steps,
                m.wall,
                1e3 * m.per_step,
                m.per_simulated_second,
                m.drift,
                m.energy
            );
            table[p][k] = m;
        }
    }
    let x: Vec<f64> = sizes.iter().map(|&n| n as f64).collect();
    let per_step: Vec<Vec<f64>> = table
        .iter()
        .map(|row| row.iter().map(|m| 1e3 * m.per_step).collect())
        .collect();
    let per_second: Vec<Vec<f64>> = table
        .iter()
        .map(|row| row.iter().map(|m| m.per_simulated_second).collect())
        .collect();
    println!();
    let large = sizes.iter().position(|&n| n >= 20).unwrap_or(0);
    for (p, path) in PATHS.iter().enumerate() {
        println!(
            "slope of cost per step, {}: p = {:.2} over all N, {:.2} for N ≥ {}; per simulated second: {:.2}, {:.2}",
            path.label,
            slope(&x, &per_step[p]),
            slope(&x[large..], &per_step[p][large..]),
            sizes[large],
            slope(&x, &per_second[p]),
            slope(&x[large..], &per_second[p][large..]),
        );
    }
    for (a, b) in [(1, 0), (2, 0), (1, 2)] {
        println!(
            "{} against {}: per simulated second {}; per step {}",
            PATHS[a].label,
            PATHS[b].label,
            crossover(&sizes, &per_second[a], &per_second[b]),
            crossover(&sizes, &per_step[a], &per_step[b]),
        );
    }

    let figures = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/figures");
    let mut csv = String::from(
        "bodies,path,steps,run_s,per_step_s,per_simulated_second_s,drift_m,energy_residual\n",
    );
    for (p, path) in PATHS.iter().enumerate() {
        for (k, m) in table[p].iter().enumerate() {
            csv += &format!(
                "{},\"{}\",{},{:e},{:e},{:e},{:e},{:e}\n",
                sizes[k],
                path.label,
                m.steps,
                m.wall,
                m.per_step,
                m.per_simulated_second,
                m.drift,
                m.energy
            );
        }
    }
    if let Err(e) = std::fs::write(figures.join("scaling.csv"), csv) {
        eprintln!("scaling.csv not written: {e}");
    }
    fn series<'a>(x: &'a [f64], values: &'a [Vec<f64>]) -> Vec<Series<'a>> {
        PATHS
            .iter()
            .zip(values)
            .map(|(path, y)| Series {
                label: path.label,
                x,
                y,
            })
            .collect()
    }
    let panels = [
        Panel {
            title: "cost per accepted step",
            x_label: "bodies N",
            y_label: "ms per step",
            series: series(&x, &per_step),
            levels: Vec::new(),
            legend_top: true,
            errors: Vec::new(),
            dashed: Vec::new(),
        },
        Panel {
            title: "cost per simulated second",
            x_label: "bodies N",
            y_label: "s of wall time per s simulated",
            series: series(&x, &per_second),
            levels: Vec::new(),
            legend_top: true,
            errors: Vec::new(),
            dashed: Vec::new(),
        },
    ];
    let title = format!("chain of N bodies, clearance at every {PERIOD}th joint (medians)");
    match log_panels(figures.join("scaling.png"), &title, (1400, 600), 2, &panels) {
        Ok(()) => println!("wrote docs/figures/scaling.png and scaling.csv"),
        Err(e) => eprintln!("scaling.png not written: {e}"),
    }
}
