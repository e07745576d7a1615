//! What a run may ask for: the ranges that make physical sense, what a run may allocate, the
//! tolerances that still resolve a penetration, and the penetration beyond which a contact
//! result is not trusted (checked on a run's results by `sim::validity`). Names are
//! checked against the file-name rules of [`super::file_names`].
//!
//! [`crate::Scene::validate`] runs these checks, so `check` and `run` reject the same
//! scenes, each problem naming its field. Every bound is far outside the shipped scenes (a
//! landing gear at 60 rpm, a slider-crank at 5000 rpm) and far inside what makes a run hang,
//! panic or exhaust memory. A contact model's own bounds sit beside its fields and are
//! checked with them ([`crate::FoundationSpec::MAX_LAYER_MODULUS`],
//! [`crate::LinearSpringSpec::MAX_STIFFNESS`]).

use contact::FrictionLawParams;

use super::error::Validator;
use super::file_names::{MAX_NAME_CHARS, is_file_name_safe};
use super::{BodyRef, ClearanceJointSpec, RunSettings, Scene, TimeLaw, WearSpec};

/// Most bodies in a scene: the dense `3n × 3n` matrices of 1000 bodies already take ~70 MB.
pub const MAX_BODIES: usize = 1000;
/// Most joints and drivers of each kind (each adds equations or a force element per step).
pub const MAX_JOINTS: usize = 1000;
/// Most response cycles (`run.cycles`): a 1000-cycle run of the default scene takes minutes.
pub const MAX_CYCLES: u32 = 10_000;
/// Most simulated cycles per wear stage and most wear stages.
pub const MAX_STAGE_CYCLES: u32 = 10_000;
/// Most trajectories of a wear sub-step (`run.trajectories`): each holds a system and a thread.
pub const MAX_TRAJECTORIES: u32 = 64;
/// Most wear stages, also those a run to the clearance limit may take
/// (`run.max_cycles / (cycles_per_stage × amplification)`, rounded up).
pub const MAX_WEAR_STAGES: u32 = 1000;
/// Largest scatter of a wear coefficient, the standard deviation of `ln k_d`
/// (`clearance_joints[*].wear.k_d_scatter`): 3 spreads `k_d` by a factor of 20 at one
/// standard deviation; measured scatters are tens of percent.
pub const MAX_K_D_SCATTER: f64 = 3.0;
/// Most extrapolation sub-steps per wear stage (`run.max_substeps`): each re-simulates the
/// stage's `K` cycles (the shipped scenes take a few dozen; the default budget is 400).
pub const MAX_SUBSTEPS: u32 = 10_000;
/// Smallest step bound or tolerance of a wear sub-step, as a fraction
/// (`run.max_clearance_change`, `run.forming_clearance_change`, `run.max_slope_change`,
/// `run.max_curvature_change`,
/// `run.wear_tolerance`): finer, a stage needs more sub-steps than [`MAX_SUBSTEPS`] allows
/// long before it ends (the defaults are 0.1, 0.25 and, for a tolerance, about 0.05).
pub const MIN_SUBSTEP_FRACTION: f64 = 1e-4;
/// Most drive cycles one wear stage may stand for (`run.cycles_per_stage ×
/// run.amplification`; the shipped scenes: 2 million): a landing gear sees about 1e5 cycles in
/// its life, and more than this only multiplies the sub-steps a stage needs.
pub const MAX_CYCLES_PER_STAGE_REPRESENTED: f64 = 1e12;
/// Longest drive period, s (an hour; the shipped scenes: 1 s and 12 ms).
pub const MAX_PERIOD: f64 = 3600.0;
/// Most output samples of one response run (`cycles × period / output_interval`).
pub const MAX_OUTPUT_SAMPLES: f64 = 2_000_000.0;
/// Most numbers one response run records (samples × per-sample values), ~800 MB.
pub const MAX_RECORDED_VALUES: f64 = 100_000_000.0;
/// Most wear-grid values kept over all stages (cells × 2 surfaces × stages, all joints).
pub const MAX_WEAR_VALUES: f64 = 50_000_000.0;
/// Longest start-up window, in drive periods: the start-up impact decays within a period.
pub const MAX_TRANSIENT_PERIODS: f64 = 10.0;
/// Largest coordinate or point, m: a mechanism kilometres wide with µm clearances is a typo.
pub const MAX_LENGTH: f64 = 1000.0;
/// Largest angle, deg (ten turns).
pub const MAX_ANGLE_DEG: f64 = 3600.0;
/// Largest speed, m/s.
pub const MAX_SPEED: f64 = 1000.0;
/// Largest angular speed of a body or a drive law, rad/s (≈ 95 000 rpm).
pub const MAX_ANGULAR_SPEED: f64 = 1.0e4;
/// Body masses, kg.
pub const MASS_RANGE: (f64, f64) = (1e-6, 1e6);
/// Body inertias, kg·m².
pub const INERTIA_RANGE: (f64, f64) = (1e-12, 1e6);
/// Largest |g|, m/s².
pub const MAX_GRAVITY: f64 = 1000.0;
/// Largest Baumgarte gain, 1/s: larger gains add eigenvalues the step size must resolve.
pub const MAX_BAUMGARTE: f64 = 1.0e4;
/// Largest absolute position tolerance as a fraction of the smallest clearance: the local
/// error must stay well below a penetration (the default is 2e-4).
pub const MAX_ATOL_PER_CLEARANCE: f64 = 1e-2;
/// Largest velocity tolerance, m/s, when no contact law sets a smaller speed scale.
pub const MAX_ATOL_VELOCITY: f64 = 1e-3;
/// Smallest output interval, s.
pub const MIN_OUTPUT_INTERVAL: f64 = 1e-9;
/// Peak penetration of the (unworn) response run beyond which it fails, as a fraction of the
/// smaller of clearance and pin radius. Hertz contact assumes deformations small against the
/// contact geometry; steel joints penetrate micrometres (the default scene: tens of µm at
/// 0.5 mm clearance, < 10 %). Half the clearance means the contact law is far outside its
/// validity and the forces it reports are not physical.
pub const MAX_PENETRATION_FRACTION: f64 = 0.5;

/// Adds the problems of `scene` against the limits above to `v`.
pub(crate) fn check(v: &mut Validator, s: &Scene) {
    Limits(v).scene(s);
}

/// The limit checks, reporting through the scene validator.
struct Limits<'a>(&'a mut Validator);

impl Limits<'_> {
    /// `|x| ≤ max`; non-finite values are the validator's to report.
    fn at_most(&mut self, path: &str, x: f64, max: f64, unit: &str) {
        self.0.at_most(path, x, max, unit);
    }

    fn within(&mut self, path: &str, x: f64, (lo, hi): (f64, f64), unit: &str) {
        if x.is_finite() && x > 0.0 && !(lo..=hi).contains(&x) {
            self.0
                .push(path, x, format!("must lie in [{lo:e}, {hi:e}] {unit}"));
        }
    }

    fn point(&mut self, path: &str, p: [f64; 2]) {
        for (k, x) in p.iter().enumerate() {
            self.at_most(&format!("{path}[{k}]"), *x, MAX_LENGTH, "m");
        }
    }

    fn count(&mut self, path: &str, n: usize, max: usize) {
        if n > max {
            self.0.push(path, n, format!("at most {max} entries"));
        }
    }

    /// Names appear in messages and, for clearance joints, in file names.
    fn name(&mut self, path: &str, name: &str, in_file_names: bool) {
        if name.chars().count() > MAX_NAME_CHARS {
            self.0
                .push(path, name, format!("at most {MAX_NAME_CHARS} characters"));
        } else if name.chars().any(char::is_control) {
            self.0
                .push(path, name, "must not contain control characters");
        } else if in_file_names && !is_file_name_safe(name) {
            self.0.push(
                path,
                name,
                "used in output file names: only letters, digits, `-`, `_` and `.`, not \
                 starting with `.`",
            );
        }
    }

    fn scene(&mut self, s: &Scene) {
        // `check` and `run` print the description and the reports embed it: a control
        // character (ESC, BEL) would reach the terminal of whoever runs the scene.
        if s.description
            .chars()
            .any(|c| c.is_control() && !matches!(c, '\n' | '\t'))
        {
            self.0.push(
                "description",
                &s.description,
                "must not contain control characters (line breaks and tabs aside)",
            );
        }
        let g = s.gravity;
        self.at_most("gravity", g[0].hypot(g[1]), MAX_GRAVITY, "m/s²");
        self.count("bodies", s.bodies.len(), MAX_BODIES);
        self.count("revolute_joints", s.revolute_joints.len(), MAX_JOINTS);
        self.count("prismatic_joints", s.prismatic_joints.len(), MAX_JOINTS);
        self.count("drivers", s.drivers.len(), MAX_JOINTS);
        self.count("clearance_joints", s.clearance_joints.len(), MAX_JOINTS);
        for (k, b) in s.bodies.iter().enumerate() {
            let p = format!("bodies[{k}]");
            self.name(&format!("{p}.name"), &b.name, false);
            self.within(&format!("{p}.mass"), b.mass, MASS_RANGE, "kg");
            self.within(&format!("{p}.inertia"), b.inertia, INERTIA_RANGE, "kg·m²");
            self.at_most(&format!("{p}.x"), b.x, MAX_LENGTH, "m");
            self.at_most(&format!("{p}.y"), b.y, MAX_LENGTH, "m");
            self.at_most(
                &format!("{p}.theta_deg"),
                b.theta.deg(),
                MAX_ANGLE_DEG,
                "deg",
            );
            for (c, x) in b.velocity.iter().enumerate() {
                self.at_most(&format!("{p}.velocity[{c}]"), *x, MAX_SPEED, "m/s");
            }
            self.at_most(&format!("{p}.omega"), b.omega, MAX_ANGULAR_SPEED, "rad/s");
        }
        for (k, j) in s.revolute_joints.iter().enumerate() {
            let p = format!("revolute_joints[{k}]");
            self.name(&format!("{p}.name"), &j.name, false);
            self.point(&format!("{p}.point"), j.point);
            self.point(&format!("{p}.other_point"), j.other_point);
        }
        for (k, j) in s.prismatic_joints.iter().enumerate() {
            let p = format!("prismatic_joints[{k}]");
            self.name(&format!("{p}.name"), &j.name, false);
            self.point(&format!("{p}.point"), j.point);
            self.point(&format!("{p}.other_point"), j.other_point);
        }
        for (k, d) in s.drivers.iter().enumerate() {
            let p = format!("drivers[{k}]");
            self.name(&format!("{p}.name"), &d.name, false);
            self.law(&format!("{p}.law"), &d.law);
        }
        for (k, c) in s.clearance_joints.iter().enumerate() {
            self.clearance_joint(&format!("clearance_joints[{k}]"), c);
        }
        self.tolerances(s);
        self.run(s);
    }

    /// A drive's frequency (harmonic ω, ramp rate) and value at t = 0 must be of a mechanism.
    fn law(&mut self, p: &str, law: &TimeLaw) {
        if let Some(speed) = law.period().map(|t| std::f64::consts::TAU / t) {
            self.at_most(
                &format!("{p} (angular frequency or rate)"),
                speed,
                MAX_ANGULAR_SPEED,
                "(rad or m)/s",
            );
        }
        self.at_most(&format!("{p} (value at t = 0)"), law.eval(0.0)[0], 1e6, "");
    }

    fn clearance_joint(&mut self, p: &str, c: &ClearanceJointSpec) {
        self.name(&format!("{p}.name"), &c.name, true);
        self.point(&format!("{p}.bearing_point"), c.bearing_point);
        self.point(&format!("{p}.pin_point"), c.pin_point);
        self.at_most(
            &format!("{p}.bearing_radius"),
            c.bearing_radius,
            MAX_LENGTH,
            "m",
        );
        if let FrictionLawParams::Coulomb(_) = c.friction {
            self.0.push(
                format!("{p}.friction.law"),
                "coulomb",
                "plain Coulomb friction is not supported: its jump at zero sliding speed cannot \
                 be stepped over by the integrator (runs hang); use law = \"ambrosio\" with \
                 small v0, v1 (e.g. 1e-4, 1e-3 m/s)",
            );
        }
        if let Some(w) = &c.wear {
            self.wear(&format!("{p}.wear"), w);
        }
    }

    fn wear(&mut self, p: &str, w: &WearSpec) {
        self.at_most(&format!("{p}.width"), w.width, MAX_LENGTH, "m");
    }

    /// Tolerances must resolve a penetration (positions) and the speeds the contact laws
    /// distinguish (velocities); otherwise a run "succeeds" with wrong forces.
    fn tolerances(&mut self, s: &Scene) {
        let clearance = s
            .active_clearance_joints()
            .map(|c| c.clearance)
            .filter(|c| c.is_finite() && *c > 0.0)
            .reduce(f64::min);
        if let Some(c) = clearance {
            let max = MAX_ATOL_PER_CLEARANCE * c;
            for (path, value) in [
                ("solver.atol_position", s.solver.atol_position),
                ("solver.atol_angle", s.solver.atol_angle),
            ] {
                if let Some(a) = value.filter(|a| a.is_finite() && *a > max) {
                    self.0.push(
                        path,
                        a,
                        format!(
                            "must not exceed {MAX_ATOL_PER_CLEARANCE} × the smallest clearance \
                             ({max:e}, per metre of arm for angles): a larger local error \
                             cannot resolve the penetration"
                        ),
                    );
                }
            }
        }
        let (limit, source) = s
            .active_clearance_joints()
            .enumerate()
            .flat_map(|(k, c)| speed_scales(k, c))
            .filter(|(v, _)| v.is_finite() && *v > 0.0)
            .fold(
                (MAX_ATOL_VELOCITY, String::from("the general bound")),
                |best, (v, path)| if v < best.0 { (v, path) } else { best },
            );
        let a = s.solver.atol_velocity;
        if a.is_finite() && a > limit {
            self.0.push(
                "solver.atol_velocity",
                a,
                format!(
                    "must not exceed {limit:e} m/s ({source}): the velocity error must stay \
                     below the smallest speed the contact laws distinguish"
                ),
            );
        }
        let b = &s.solver;
        for (path, gain) in [
            ("solver.baumgarte_alpha", b.baumgarte_alpha),
            ("solver.baumgarte_beta", b.baumgarte_beta),
        ] {
            if gain.is_finite() && !(0.0..=MAX_BAUMGARTE).contains(&gain) {
                self.0.push(
                    path,
                    gain,
                    format!(
                        "must lie in [0, {MAX_BAUMGARTE:e}] 1/s: a negative gain makes the \
                         constraint drift grow, a huge one makes the system too stiff to step"
                    ),
                );
            }
        }
    }

    /// The run's settings: each value in its range, then what they add up to.
    fn run(&mut self, s: &Scene) {
        self.run_values(&s.run, s.solver.output_interval);
        self.run_sizes(s);
        if let Some(name) = &s.run.response_body
            && matches!(s.resolve(name), Some(BodyRef::Ground))
        {
            self.0
                .push("run.response_body", name, "must be a body, not ground");
        }
    }

    /// Each of the run's counts, fractions and times in its own range.
    fn run_values(&mut self, r: &RunSettings, interval: f64) {
        if r.cycles == 0 {
            self.0.push("run.cycles", 0, "must be at least 1");
        } else if r.cycles > MAX_CYCLES {
            self.0
                .push("run.cycles", r.cycles, format!("at most {MAX_CYCLES}"));
        }
        if r.cycles_per_stage > MAX_STAGE_CYCLES {
            self.0.push(
                "run.cycles_per_stage",
                r.cycles_per_stage,
                format!("at most {MAX_STAGE_CYCLES}"),
            );
        }
        if r.trajectories > MAX_TRAJECTORIES {
            self.0.push(
                "run.trajectories",
                r.trajectories,
                format!("at most {MAX_TRAJECTORIES}"),
            );
        }
        if r.max_substeps > MAX_SUBSTEPS {
            self.0.push(
                "run.max_substeps",
                r.max_substeps,
                format!("at most {MAX_SUBSTEPS} (each sub-step re-simulates the stage's cycles)"),
            );
        }
        for (path, fraction) in [
            ("run.max_clearance_change", Some(r.max_clearance_change)),
            ("run.forming_clearance_change", r.forming_clearance_change),
            ("run.max_slope_change", r.max_slope_change),
            ("run.max_curvature_change", r.max_curvature_change),
            ("run.wear_tolerance", r.wear_tolerance),
        ] {
            if let Some(f) = fraction.filter(|f| f.is_finite() && *f > 0.0)
                && f < MIN_SUBSTEP_FRACTION
            {
                self.0.push(
                    path,
                    f,
                    format!(
                        "at least {MIN_SUBSTEP_FRACTION:e}: a finer bound needs more wear \
                         sub-steps per stage than run.max_substeps allows"
                    ),
                );
            }
        }
        let represented = f64::from(r.cycles_per_stage) * r.amplification;
        if r.amplification.is_finite() && represented > MAX_CYCLES_PER_STAGE_REPRESENTED {
            self.0.push(
                "run.amplification",
                r.amplification,
                format!(
                    "a stage would stand for {represented:.3e} drive cycles (cycles_per_stage × \
                     amplification); at most {MAX_CYCLES_PER_STAGE_REPRESENTED:e}"
                ),
            );
        }
        if let (true, Some(max)) = (r.until_limit, r.max_cycles)
            && max.is_finite()
            && represented.is_finite()
            && represented > 0.0
            && max / represented > f64::from(MAX_WEAR_STAGES)
        {
            self.0.push(
                "run.max_cycles",
                max,
                format!(
                    "would take {:.0} stages of {represented:.3e} cycles (cycles_per_stage × \
                     amplification); at most {MAX_WEAR_STAGES} (raise the amplification)",
                    (max / represented).ceil()
                ),
            );
        }
        if r.wear_stages > MAX_WEAR_STAGES {
            self.0.push(
                "run.wear_stages",
                r.wear_stages,
                format!("at most {MAX_WEAR_STAGES}"),
            );
        }
        if let Some(t) = r.period.filter(|t| t.is_finite() && *t > MAX_PERIOD) {
            self.0
                .push("run.period", t, format!("at most {MAX_PERIOD} s"));
        }
        if interval.is_finite() && interval > 0.0 && interval < MIN_OUTPUT_INTERVAL {
            self.0.push(
                "solver.output_interval",
                interval,
                format!("at least {MIN_OUTPUT_INTERVAL:e} s"),
            );
        }
    }

    /// What the run's values add up to over the drive period: the samples it records, the
    /// start-up window every sub-step simulates again, the wear values the stages keep.
    fn run_sizes(&mut self, s: &Scene) {
        let (r, interval) = (&s.run, s.solver.output_interval);
        let Some(period) = s.cycle_period().filter(|t| t.is_finite() && *t > 0.0) else {
            return;
        };
        if r.period.is_none() && period > MAX_PERIOD {
            self.0.push(
                "run.period",
                "none",
                format!("the drive law's period is {period:e} s, more than {MAX_PERIOD} s"),
            );
        }
        let duration = period * f64::from(r.cycles);
        let samples = duration / interval;
        let per_sample = 13.0 + 9.0 * s.bodies.len() as f64 + 8.0 * s.clearance_joints.len() as f64;
        // Only when each factor is in its own range (else that field is already named).
        let factors_ok = interval >= MIN_OUTPUT_INTERVAL
            && r.cycles <= MAX_CYCLES
            && period <= MAX_PERIOD
            && interval.is_finite();
        if factors_ok {
            if samples > MAX_OUTPUT_SAMPLES {
                self.0.push(
                    "solver.output_interval",
                    interval,
                    format!(
                        "{} cycle(s) of {period:.6} s would record {samples:.3e} samples per run; \
                         at most {MAX_OUTPUT_SAMPLES:e} (raise the interval or lower run.cycles)",
                        r.cycles
                    ),
                );
            } else if samples * per_sample > MAX_RECORDED_VALUES {
                self.0.push(
                    "solver.output_interval",
                    interval,
                    format!(
                        "{samples:.3e} samples of {per_sample} values would exceed \
                         {MAX_RECORDED_VALUES:e} recorded numbers (raise the interval)"
                    ),
                );
            }
        }
        let window = r.transient_window;
        if window.is_finite() && window > MAX_TRANSIENT_PERIODS * period {
            self.0.push(
                "run.transient_window",
                window,
                format!(
                    "at most {MAX_TRANSIENT_PERIODS} drive periods ({:.6} s): every wear \
                     sub-step simulates this window again",
                    MAX_TRANSIENT_PERIODS * period
                ),
            );
        }
        let cells: f64 = s
            .active_clearance_joints()
            .filter_map(|c| c.wear.as_ref())
            .map(|w| 2.0 * w.cells as f64)
            .sum();
        if let Some(stages) = r.most_stages()
            && cells * stages > MAX_WEAR_VALUES
        {
            let (path, value) = match (r.until_limit, r.max_cycles) {
                (true, Some(max)) => ("run.max_cycles", max),
                _ => ("run.wear_stages", f64::from(r.wear_stages)),
            };
            self.0.push(
                path,
                value,
                format!(
                    "{stages} stage(s) of {cells} wear cells would keep more than \
                     {MAX_WEAR_VALUES:e} values (lower the stages or \
                     clearance_joints[*].wear.cells)"
                ),
            );
        }
    }
}

/// The speeds (m/s) below which joint `k`'s laws change behaviour, with their field paths.
fn speed_scales(k: usize, c: &ClearanceJointSpec) -> Vec<(f64, String)> {
    let p = format!("clearance_joints[{k}]");
    let mut v = Vec::new();
    for (law, scale) in [
        ("friction", c.friction.speed_scale()),
        ("normal_law", c.normal_law.speed_scale()),
    ] {
        if let Some(contact::SpeedScale { parameter, value }) = scale {
            v.push((value, format!("{p}.{law}.{parameter} = {value:e}")));
        }
    }
    v
}
