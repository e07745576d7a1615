//! What the commands print: the scene `check` found, and the one-screen summary of a run.

use std::path::Path;

use scene::ValidScene;
use sim::{AssemblyCheck, RunOutcome};

/// What `check` found: the scene's contents, its solver settings and its assembly at t = 0.
pub fn scene_check(name: &str, s: &ValidScene, check: &AssemblyCheck) {
    outln!("scene {name}: valid");
    outln!("  {}", s.description);
    outln!("  inertia: {}", s.inertia_convention);
    outln!("  bodies ({}):", s.bodies.len());
    for b in &s.bodies {
        outln!(
            "    {:<12} m = {} kg, I = {} kg·m², at ({}, {}) m, {:.4}°",
            b.name,
            b.mass,
            b.inertia,
            b.x,
            b.y,
            b.theta.deg()
        );
    }
    let names = |v: Vec<&str>| {
        if v.is_empty() {
            "-".into()
        } else {
            v.join(", ")
        }
    };
    outln!(
        "  revolute joints: {}",
        names(s.revolute_joints.iter().map(|j| j.name.as_str()).collect())
    );
    outln!(
        "  prismatic joints: {}",
        names(s.prismatic_joints.iter().map(|j| j.name.as_str()).collect())
    );
    outln!(
        "  drivers: {}",
        names(s.drivers.iter().map(|d| d.name.as_str()).collect())
    );
    outln!("  clearance joints ({}):", s.clearance_joints.len());
    for c in &s.clearance_joints {
        let role = if c.ideal {
            "ideal revolute (2 equations)".to_string()
        } else {
            format!(
                "clearance {} mm, bearing R = {} mm, wear {}",
                millimetres(c.clearance, 0),
                millimetres(c.bearing_radius, 0),
                match &c.wear {
                    Some(w) if w.k_d_scatter > 0.0 => {
                        format!("on (k_d {:e}, scatter {} in ln k_d)", w.k_d, w.k_d_scatter)
                    }
                    Some(_) => "on".to_string(),
                    None => "off".to_string(),
                }
            )
        };
        outln!(
            "    {:<12} bearing on {}, pin on {}: {role}",
            c.name,
            c.bearing_body,
            c.pin_body
        );
        if !c.ideal {
            outln!("    {:<12} {}", "", c.contact_description());
        }
    }
    outln!(
        "  constraint equations: {}; degrees of freedom (3·{} − {}, clearance joints as 0): {}",
        s.constraint_count(),
        s.bodies.len(),
        s.constraint_count(),
        s.degrees_of_freedom()
    );
    if let (true, Some(limit), Some(max)) =
        (s.run.until_limit, s.run.clearance_limit, s.run.max_cycles)
    {
        let correlation = s.run.k_d_correlation.name();
        outln!(
            "  run: wear stages until every wearing joint reaches {} mm clearance, at most \
             {max:.3e} cycles; k_d scatter {correlation} between the joints",
            millimetres(limit, 2)
        );
    }
    let t = s.tolerances();
    outln!(
        "  solver: {:?}, rtol {:e}, atol {:.3e} m / {:.3e} rad / {:.3e} (m|rad)/s; cycle {} s",
        s.solver.integrator,
        s.solver.rtol,
        t.position,
        t.angle,
        t.velocity,
        s.cycle_period().map_or("-".into(), |p| format!("{p:.6}"))
    );
    outln!(
        "  assembly at t = 0: ok, {} coordinates, {} constraint equations, {} degrees of freedom \
         (clearance joints as force elements); largest joint-centre move from the file's poses \
         {:.3e} m",
        check.coordinates,
        check.constraints,
        check.degrees_of_freedom,
        check.largest_move
    );
}

/// Peak statistics after the start-up window, or "n/a" when the window covers the run (no
/// cycle has a sample after it, so there is no peak to report).
fn peak_after(b: Option<&sim::PeakStats>, window: f64) -> String {
    let Some(b) = b else {
        return format!("n/a after {window} s (the start-up window covers the whole run)");
    };
    format!(
        "{:.2} kN after {window} s (median of {} cycle peaks {:.2} ± {:.2} kN, range {:.2}–{:.2} \
         kN; elastic share at the peaks {})",
        b.max * 1e-3,
        b.cycles,
        b.cycle_median * 1e-3,
        b.cycle_median_noise * 1e-3,
        b.cycle_min * 1e-3,
        b.cycle_max * 1e-3,
        elastic_share(b)
    )
}

/// The elastic share of the per-cycle peaks in words: median and smallest, and a warning when
/// the median peak is mostly damping.
fn elastic_share(b: &sim::PeakStats) -> String {
    if !b.elastic_share_median.is_finite() {
        return "n/a".to_string();
    }
    let warning = if b.elastic_share_median < sim::MIN_ELASTIC_SHARE {
        " — MOSTLY DAMPING: not a load the surfaces carry"
    } else {
        ""
    };
    format!(
        "median {:.0} %, min {:.0} %{warning}",
        100.0 * b.elastic_share_median,
        100.0 * b.elastic_share_min
    )
}

/// The one-screen summary at the end of a run.
pub fn run_summary(outcome: &RunOutcome, out: &Path, files: usize) {
    let s = &outcome.summary;
    outln!("scene {}: {}", s.scene, s.description);
    for contact in &s.contacts {
        outln!("  contact {contact}");
    }
    response(s);
    if let Some(w) = &s.wear {
        wear(w);
    }
    if let Some(r) = &s.worn_response {
        outln!("worn response (on the surfaces after the last stage):");
        print_joints(r, s.transient_window_s);
    }
    outln!(
        "wrote {files} files to {} in {:.1} s total",
        out.display(),
        s.wall_time_s
    );
}

/// The response on the surfaces the run started from: the joints, the response body against
/// the ideal mechanism, the integrator's numbers.
fn response(s: &sim::Summary) {
    let r = &s.response;
    outln!(
        "response: {} cycle(s) of {:.3} s; peaks are statistics of per-cycle maxima",
        r.cycles,
        s.period_s
    );
    print_joints(r, s.transient_window_s);
    match &r.deviation_after_transient {
        Some(d) => outln!(
            "  {} vs ideal after {} s: |Δx| {:.1} µm, |Δy| {:.1} µm, |Δv| {:.4}/{:.4} m/s, |Δa| \
             {:.1}/{:.1} m/s²",
            s.response_body,
            s.transient_window_s,
            d.x_m * 1e6,
            d.y_m * 1e6,
            d.vx_m_s,
            d.vy_m_s,
            d.ax_m_s2,
            d.ay_m_s2
        ),
        None => outln!(
            "  {} vs ideal after {} s: n/a (the start-up window covers the whole run)",
            s.response_body,
            s.transient_window_s
        ),
    }
    if let Some(n) = &r.numerics {
        outln!(
            "  integrator: {} steps ({} rejected), {} events, drift {:.1e} m, energy residual \
             {:.2e} J ({:.1e} relative), {:.1} s",
            n.steps,
            n.rejected_steps,
            n.events,
            n.drift_position,
            n.energy_residual_j,
            n.energy_relative_residual,
            n.wall_time_s
        );
    }
}

/// What the wear stages did, and when each joint reaches its clearance limit.
fn wear(w: &sim::WearSummary) {
    outln!(
        "wear: {} stage(s), K = {} cycles per stage (scene: {}) on {} trajector{}, ×{:.0} so \
             a stage stands for {:.3e} cycles; {}; sub-steps {:?}{}; {:.1} s",
        w.stages,
        w.cycles_per_stage,
        w.scene_cycles_per_stage,
        w.trajectories,
        if w.trajectories == 1 { "y" } else { "ies" },
        w.amplification,
        w.cycles_represented_per_stage,
        w.extrapolation,
        w.substeps_per_stage,
        // Controlled sub-steps need one more run per stage, and rejected predictions.
        if w.runs_per_stage == w.substeps_per_stage {
            String::new()
        } else {
            format!(
                " (runs {:?}, of which rejected {:?})",
                w.runs_per_stage, w.rejected_runs_per_stage
            )
        },
        w.wall_time_s
    );
    for j in &w.joints {
        outln!(
            "  joint {}: bearing peak {} at {:.0}°, pin peak {} at {:.0}°, worn volume {}",
            j.name,
            micrometres(j.bearing_peak_depth_m, j.bearing_peak_depth_noise_m),
            j.bearing_peak_angle_deg,
            micrometres(j.pin_peak_depth_m, j.pin_peak_depth_noise_m),
            j.pin_peak_angle_deg,
            match j.worn_volume_noise_m3 {
                Some(n) => format!("{:.3e} ± {:.1e} m³", j.worn_volume_m3, n),
                None => format!("{:.3e} m³", j.worn_volume_m3),
            }
        );
    }
    if w.joints
        .iter()
        .any(|j| j.bearing_peak_depth_noise_m.is_some())
    {
        outln!(
            "  (±: one standard error of the stage's sampling; not in it: the discretisation's \
             bias, which on the built-in lgres reaches about 1.6 ± at joint B's peaks and 1.0 ± \
             at its volume against 20× finer sub-steps and stays within 0.7 ± at A, \
             docs/convergence.md)"
        );
    }
    for j in &w.joints {
        if let Some(limit) = &j.clearance_limit {
            outln!(
                "  {}",
                clearance_limit_line(&j.name, limit, w.cycles_applied)
            );
            if let (Some(b10), Some(b50)) = (limit.b10_cycles, limit.b50_cycles) {
                outln!(
                    "    under a k_d scatter of {} (sd of ln k_d): B10 {}, B50 {} cycles",
                    limit.k_d_scatter,
                    sim::life_distribution::cycles_with_noise(b10, limit.b10_noise),
                    sim::life_distribution::cycles_with_noise(b50, limit.b50_noise)
                );
            }
        }
    }
    if let Some(life) = &w.life {
        outln!("  life: {}", life.ended);
        if w.joints.len() > 1 {
            outln!("  mechanism: {}", life.mechanism_message);
            outln!("    assumed: {}", life.assumption);
        }
    }
    for text in &w.warnings {
        outln!("  {text}");
    }
}

/// A depth in µm with its sampling noise when measured: `358.1 ± 6.2 µm`.
fn micrometres(metres: f64, noise: Option<f64>) -> String {
    match noise {
        Some(n) => format!("{:.1} ± {:.1} µm", metres * 1e6, n * 1e6),
        None => format!("{:.1} µm", metres * 1e6),
    }
}

/// `metres` in millimetres as a person reads it: at least `min_decimals` decimals, as many
/// more as the value needs to read back within 1e-9 of itself (up to nine; `0.5000001`), so
/// the round-off of the conversion (`0.5000001000000001`) is never printed.
fn millimetres(metres: f64, min_decimals: usize) -> String {
    let value = metres * 1e3;
    (min_decimals..=9)
        .map(|d| format!("{value:.d$}"))
        .find(|t| {
            t.parse::<f64>()
                .is_ok_and(|v| (v - value).abs() <= 1e-9 * value.abs())
        })
        .unwrap_or_else(|| format!("{value:.4e}"))
}

/// When joint `name`'s largest local clearance reaches the maintenance limit, in a line.
fn clearance_limit_line(
    name: &str,
    limit: &sim::ClearanceLimitReport,
    cycles_applied: f64,
) -> String {
    // Two decimals as in "1.00 mm", more when the limit needs them (0.501 mm).
    let mm = millimetres(limit.limit_m, 2);
    match (limit.cycles, limit.cycles_noise) {
        (Some(c), Some(n)) if c > 0.0 => {
            format!("joint {name} reaches {mm} mm clearance after {c:.1e} ± {n:.1e} cycles")
        }
        (Some(c), None) if c > 0.0 => {
            format!("joint {name} reaches {mm} mm clearance after {c:.1e} cycles")
        }
        (Some(_), _) => format!(
            "joint {name} is at {mm} mm clearance from the start (the surfaces the run started \
             from)"
        ),
        (None, _) => format!(
            "joint {name} does not reach {mm} mm clearance within {cycles_applied:.1e} cycles"
        ),
    }
}

/// Per-joint peaks and energy books of one response, and what the books flag.
fn print_joints(r: &sim::ResponseSummary, window: f64) {
    for j in &r.joints {
        let (a, b) = (&j.normal_force_all, j.normal_force_after_transient.as_ref());
        if let Some(v) = j.validity.as_ref().filter(|v| !v.inside) {
            outln!(
                "  joint {}: OUTSIDE the contact model's validity, so its force peaks are not \
                 results (summary.json has them, and the measures): {}",
                j.name,
                v.reasons.join("; ")
            );
            continue;
        }
        outln!(
            "  joint {}: peak F_n {:.2} kN (all), {}; max penetration {:.2} µm",
            j.name,
            a.max * 1e-3,
            peak_after(b, window),
            j.max_penetration_m * 1e6,
        );
        outln!(
            "    dissipated per cycle: {:.3} J (damping {:.3} J + friction {:.3} J; books close \
             to {:.1e} J)",
            j.contact_dissipation_per_cycle_j,
            j.damping_dissipation_per_cycle_j,
            j.friction_dissipation_per_cycle_j,
            j.energy_books_residual_per_cycle_j
        );
    }
    for w in &r.energy_warnings {
        outln!("  WARNING: {w}");
    }
}
