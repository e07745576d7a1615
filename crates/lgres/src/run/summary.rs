//! Summary numbers of a run: peak statistics over cycles, deviations from the ideal
//! mechanism, numerics and energy books.

use multibody::SimulationResult;

use super::{Deviation, JointSummary, Numerics, PeakStats, Response, ResponseSummary};
use crate::build::{Built, JointHandle};
use crate::scene::Scene;

/// What a dynamic run leaves for its energy books.
pub(super) struct Audit<'a> {
    pub(super) built: &'a Built,
    pub(super) result: &'a SimulationResult,
    pub(super) joints: &'a [JointHandle],
    /// Elastic energy stored in each joint at the start (joint order).
    pub(super) initial_energy: &'a [f64],
}

/// Energy books of one joint over a run (J, totals).
#[derive(Default)]
struct JointBooks {
    friction: f64,
    damping: f64,
    stored_start: f64,
    stored_end: f64,
    audited: f64,
}

impl Audit<'_> {
    fn books(&self, k: usize, name: &str) -> JointBooks {
        let probe = self
            .joints
            .get(k)
            .and_then(|h| h.probe(self.built.system.elements()));
        let work = self
            .result
            .energy
            .as_ref()
            .and_then(|e| e.element_work.iter().find(|(n, _)| n == name))
            .map_or(0.0, |(_, w)| *w);
        let stored_start = self.initial_energy.get(k).copied().unwrap_or(0.0);
        let stored_end = probe
            .and_then(|p| p.last_diagnostics())
            .map_or(0.0, |d| d.elastic_energy);
        JointBooks {
            friction: probe.map_or(0.0, |p| p.friction_dissipation()),
            damping: probe.map_or(0.0, |p| p.damping_dissipation()),
            stored_start,
            stored_end,
            audited: -work - (stored_end - stored_start),
        }
    }
}

/// Energy per cycle (J) below which the books count as closed: a dissipation this small counts
/// as round-off, not as energy put in, and a difference between the audited dissipation and
/// damping + friction this small as integration error (the report's verdict).
pub const ENERGY_BOOKS_TOLERANCE_J: f64 = 0.05;

pub(super) fn summarize(
    scene: &Scene,
    response: &Response,
    audit: Option<Audit<'_>>,
    cycles: u32,
    t_end: f64,
) -> ResponseSummary {
    let period = scene.cycle_period().unwrap_or(t_end);
    let window = scene.run.transient_window;
    let per_cycle = 1.0 / f64::from(cycles);
    let mut joint_summaries = Vec::new();
    let (mut dissipated, mut friction, mut damping) = (0.0, 0.0, 0.0);
    let mut energy_warnings = Vec::new();
    for (k, series) in response.contact.iter().enumerate() {
        let books = audit
            .as_ref()
            .map_or_else(JointBooks::default, |a| a.books(k, &series.name));
        dissipated += books.audited;
        friction += books.friction;
        damping += books.damping;
        for (what, value) in [
            ("its contact force", books.audited),
            ("its normal force's damping", books.damping),
            ("its friction", books.friction),
        ] {
            if value * per_cycle < -ENERGY_BOOKS_TOLERANCE_J {
                energy_warnings.push(format!(
                    "joint {}: {what} put {:.3} J per cycle INTO the mechanism (negative \
                     dissipation): the contact is not dissipative on these surfaces, so its \
                     forces are not physical results",
                    series.name,
                    -value * per_cycle
                ));
            }
        }
        joint_summaries.push(JointSummary {
            name: series.name.clone(),
            clearance_m: series.clearance,
            normal_force_all: peak_stats(&response.times, &series.normal_force, period, 0.0),
            normal_force_after_transient: Some(peak_stats(
                &response.times,
                &series.normal_force,
                period,
                window,
            ))
            .filter(|p| p.cycles > 0),
            max_penetration_m: series.penetration.iter().copied().fold(f64::MIN, f64::max),
            max_eccentricity_m: series.eccentricity.iter().copied().fold(0.0, f64::max),
            validity: series.validity.clone(),
            friction_dissipation_per_cycle_j: books.friction * per_cycle,
            damping_dissipation_per_cycle_j: books.damping * per_cycle,
            elastic_energy_start_j: books.stored_start,
            elastic_energy_end_j: books.stored_end,
            contact_dissipation_per_cycle_j: books.audited * per_cycle,
            energy_books_residual_per_cycle_j: (books.audited - books.damping - books.friction)
                * per_cycle,
        });
    }
    ResponseSummary {
        cycles,
        duration_s: t_end,
        joints: joint_summaries,
        deviation: deviation(response, 0.0),
        deviation_after_transient: response
            .times
            .iter()
            .any(|t| *t >= window)
            .then(|| deviation(response, window)),
        dissipated_per_cycle_j: dissipated * per_cycle,
        friction_per_cycle_j: friction * per_cycle,
        damping_per_cycle_j: damping * per_cycle,
        energy_warnings,
        numerics: audit.map(|a| numerics(a.result)),
    }
}

pub(super) fn numerics(r: &SimulationResult) -> Numerics {
    let s = &r.statistics;
    Numerics {
        steps: s.steps,
        rejected_steps: s.rejected_steps,
        rhs_evaluations: s.rhs_evaluations,
        jacobian_evaluations: s.jacobian_evaluations,
        factorizations: s.factorizations,
        smallest_step_s: s.smallest_step,
        largest_step_s: s.largest_step,
        events: s.events,
        drift_position: r.drift.position,
        drift_velocity: r.drift.velocity,
        energy_residual_j: r.energy.as_ref().map_or(f64::NAN, |e| e.residual),
        energy_relative_residual: r
            .energy
            .as_ref()
            .map_or(f64::NAN, |e| e.relative_residual()),
        wall_time_s: s.wall_time.as_secs_f64(),
    }
}

/// Per-cycle peaks of `values` for samples at `t ≥ from`.
pub fn peak_stats(times: &[f64], values: &[f64], period: f64, from: f64) -> PeakStats {
    let mut peaks: Vec<f64> = Vec::new();
    let mut current: Option<(usize, f64)> = None;
    for (t, v) in times.iter().zip(values) {
        if *t < from {
            continue;
        }
        // A sample exactly at the end of the run belongs to the last cycle.
        let cycle = ((t / period) * (1.0 - 1e-12)).floor().max(0.0) as usize;
        match current {
            Some((c, peak)) if c == cycle => current = Some((c, peak.max(*v))),
            Some((_, peak)) => {
                peaks.push(peak);
                current = Some((cycle, *v));
            }
            None => current = Some((cycle, *v)),
        }
    }
    peaks.extend(current.map(|(_, p)| p));
    if peaks.is_empty() {
        return PeakStats::default();
    }
    peaks.sort_by(f64::total_cmp);
    let quantile = |q: f64| {
        let x = q * (peaks.len() - 1) as f64;
        let (lo, hi) = (x.floor() as usize, x.ceil() as usize);
        peaks[lo] + (x - lo as f64) * (peaks[hi] - peaks[lo])
    };
    PeakStats {
        max: peaks[peaks.len() - 1],
        cycles: peaks.len(),
        cycle_median: quantile(0.5),
        cycle_min: peaks[0],
        cycle_max: peaks[peaks.len() - 1],
        cycle_iqr: quantile(0.75) - quantile(0.25),
    }
}

pub(super) fn deviation(r: &Response, from: f64) -> Deviation {
    let mut d = [0.0f64; 6];
    let (a, b) = (r.motion.series(), r.ideal.series());
    for (k, t) in r.times.iter().enumerate() {
        if *t < from {
            continue;
        }
        for c in 0..6 {
            if let (Some(x), Some(y)) = (a[c].get(k), b[c].get(k)) {
                d[c] = d[c].max((x - y).abs());
            }
        }
    }
    Deviation {
        x_m: d[0],
        y_m: d[1],
        vx_m_s: d[2],
        vy_m_s: d[3],
        ax_m_s2: d[4],
        ay_m_s2: d[5],
    }
}

/// Largest disagreement of the two halves of a stage's simulated cycles, each extrapolated
/// alone (their peak depths and worn volumes, relative to the mean), for which the stage's
/// wear counts as converged in K. The stage's result averages both halves, so its own sampling
/// noise is about `1/√2` of this.
pub const STAGE_HALVES_TOLERANCE: f64 = 0.1;
