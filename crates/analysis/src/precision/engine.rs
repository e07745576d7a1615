//! The sweep itself: every (method, rtol) run measured against the references, then timed.
//! Every run is one [`sim::integrate`] of the scene.

use std::time::Instant;

use multibody::{Frame, OutputTimes, SimulationErrorKind, State};

use super::{
    CycleQuantities, Errors, Measured, Paths, PrecisionError, PrecisionOptions, PrecisionReport,
    ReferenceRun, Row, RowOutcome, method_name,
};
use scene::{Integrator, ValidScene};
use sim::build::JointHandle;
use sim::integrate::{FrameObserver, ScaledTolerances, StartSurfaces, StepBudget};
use sim::{Integration, IntegrationError, IntegrationErrorKind, RunError};

/// Records the rod position and journal-centre paths at output frames.
struct PathRecorder {
    body: usize,
    paths: Paths,
}

impl FrameObserver for PathRecorder {
    fn frame(&mut self, frame: &Frame<'_>, joints: &[JointHandle]) {
        self.paths.times.push(frame.t);
        let i = 3 * self.body;
        self.paths.rod.push([frame.q[i], frame.q[i + 1]]);
        for (path, handle) in self.paths.journals.iter_mut().zip(joints) {
            let e = handle.probe(frame.elements).map_or([f64::NAN; 2], |p| {
                let d = p.contact(frame.q, frame.qd).diagnostics;
                let (s, c) = d.contact_angle.sin_cos();
                [d.eccentricity * c, d.eccentricity * s]
            });
            path.push(e);
        }
    }
}

/// Everything fixed across the runs of a sweep.
struct Setup<'a> {
    scene: &'a ValidScene,
    options: &'a PrecisionOptions,
    body: usize,
    t_end: f64,
    /// Ideal response body positions at the output times.
    ideal: Vec<[f64; 2]>,
    joint_names: Vec<String>,
}

impl Setup<'_> {
    /// One run of the sweep: `method` at `rtol` (absolute tolerances scaled with it), on
    /// unworn wear grids gathering wear after the transient window or on round surfaces.
    fn integration(
        &self,
        method: Integrator,
        rtol: f64,
        wear: bool,
        output: OutputTimes,
    ) -> Integration {
        Integration {
            t_end: self.t_end,
            output,
            energy_audit: false,
            max_steps: StepBudget::Scene,
            tolerances: Some(ScaledTolerances {
                integrator: method,
                rtol,
            }),
            surfaces: if wear {
                StartSurfaces::Wearing {
                    accumulate_from: self.scene.run.transient_window,
                }
            } else {
                StartSurfaces::Round
            },
        }
    }

    /// The measured run: dense output, energy audit, wear accumulation; `budget` caps its
    /// accepted steps (none for the references: without them nothing can be measured).
    fn measure(
        &self,
        method: Integrator,
        rtol: f64,
        budget: Option<usize>,
    ) -> Result<Measured, Failure> {
        let mut integration = self.integration(
            method,
            rtol,
            true,
            OutputTimes::Every(self.options.output_interval),
        );
        integration.energy_audit = true;
        integration.max_steps = budget.map_or(StepBudget::Unlimited, StepBudget::Steps);
        let mut recorder = PathRecorder {
            body: self.body,
            paths: Paths {
                journals: vec![Vec::new(); self.joint_names.len()],
                ..Paths::default()
            },
        };
        let run = sim::integrate(self.scene, &integration, &mut recorder)?;
        let paths = recorder.paths;
        if let Some(k) = (0..paths.times.len()).find(|&k| {
            !(paths.rod[k].iter().all(|v| v.is_finite())
                && paths
                    .journals
                    .iter()
                    .all(|j| j[k].iter().all(|v| v.is_finite())))
        }) {
            return Err(format!("non-finite state at t = {}", paths.times[k]).into());
        }
        let mut friction = 0.0;
        let mut contact_work = 0.0;
        let mut wear_volume = Vec::new();
        for joint in &run.joints {
            if let Some(f) = joint.friction_dissipation {
                friction += f;
            }
            contact_work -= run
                .result
                .energy
                .as_ref()
                .and_then(|e| e.element_work.iter().find(|(n, _)| n == &joint.name))
                .map_or(0.0, |(_, w)| *w);
            wear_volume.push(
                joint
                    .stage_wear
                    .as_ref()
                    .map_or(0.0, wear::StageWear::archard_volume),
            );
        }
        let squares: f64 = paths
            .rod
            .iter()
            .zip(&self.ideal)
            .map(|(r, i)| (r[0] - i[0]).powi(2) + (r[1] - i[1]).powi(2))
            .sum();
        let s = &run.result.statistics;
        Ok(Measured {
            quantities: CycleQuantities {
                deviation_rms_m: (squares / paths.rod.len().max(1) as f64).sqrt(),
                damping_j: contact_work - friction,
                friction_j: friction,
                wear_volume_m3: wear_volume,
            },
            paths,
            steps: s.steps,
            rejected: s.rejected_steps,
            rhs: s.rhs_evaluations,
            factorizations: s.factorizations,
            final_state: run.result.final_state,
            wall_s: run.wall_s,
        })
    }

    /// One timed run (sparse output, no audit); its wall time and final state.
    fn time_once(
        &self,
        method: Integrator,
        rtol: f64,
        wear: bool,
    ) -> Result<(f64, State), Failure> {
        let mut integration =
            self.integration(method, rtol, wear, OutputTimes::At(vec![self.t_end]));
        integration.max_steps = StepBudget::Steps(self.options.max_steps);
        let run = sim::integrate(self.scene, &integration, &mut ())?;
        Ok((run.wall_s, run.result.final_state))
    }

    /// Errors of `run` against `reference`.
    fn errors(&self, run: &Measured, reference: &Measured) -> Errors {
        let (a, b) = (&run.paths, &reference.paths);
        let frames = a.times.len().min(b.times.len());
        let distance = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).hypot(p[1] - q[1]);
        let mut rod = 0.0_f64;
        let mut journal = 0.0_f64;
        let mut separation = None;
        for k in 0..frames {
            let t = a.times[k];
            let apart: Vec<f64> = a
                .journals
                .iter()
                .zip(&b.journals)
                .map(|(x, y)| distance(x[k], y[k]))
                .collect();
            if t <= self.options.start_up * (1.0 + 1e-12) {
                rod = rod.max(distance(a.rod[k], b.rod[k]));
                journal = apart.iter().copied().fold(journal, f64::max);
            }
            let clearances = self.scene.active_clearance_joints().map(|c| c.clearance);
            if separation.is_none()
                && apart
                    .iter()
                    .zip(clearances)
                    .any(|(d, c)| *d > self.options.separation_fraction * c)
            {
                separation = Some(t);
            }
        }
        // A quantity the reference has none of (no wear gathered in a short run) is exact
        // when the run has none either, and unboundedly wrong otherwise.
        let relative = |x: f64, r: f64| match (r != 0.0, x == r) {
            (true, _) => ((x - r) / r).abs(),
            (false, true) => 0.0,
            (false, false) => f64::INFINITY,
        };
        let ours = run.quantities.named(&self.joint_names);
        let theirs = reference.quantities.named(&self.joint_names);
        Errors {
            start_up_rod_m: rod,
            start_up_journal_m: journal,
            cycle_relative: ours
                .into_iter()
                .zip(theirs)
                .map(|((name, x), (_, r))| (name, relative(x, r)))
                .collect(),
            separation_s: separation,
        }
    }
}

/// Why a run of the sweep did not complete.
struct Failure {
    reason: String,
    /// It ran out of the step budget (tighter tolerances of the method would too).
    out_of_budget: bool,
}

impl From<String> for Failure {
    fn from(reason: String) -> Self {
        Self {
            reason,
            out_of_budget: false,
        }
    }
}

impl From<IntegrationError> for Failure {
    fn from(e: IntegrationError) -> Self {
        Self {
            out_of_budget: e.kind()
                == IntegrationErrorKind::Simulation(SimulationErrorKind::StepLimit),
            reason: e.to_string(),
        }
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn check_options(o: &PrecisionOptions) -> Result<(), PrecisionError> {
    let bad = |field, reason: String| Err(PrecisionError::Options { field, reason });
    if o.methods.is_empty() {
        return bad("methods", "at least one integrator is needed".into());
    }
    if let Some(r) = o
        .rtols
        .iter()
        .find(|r| !(r.is_finite() && **r > 0.0 && **r < 1.0))
    {
        return bad("rtols", format!("{r} is not in (0, 1)"));
    }
    if o.rtols.is_empty() {
        return bad("rtols", "at least one tolerance is needed".into());
    }
    let [(m0, r0), (m1, r1)] = o.references;
    if m0 == m1 {
        return bad(
            "references",
            format!(
                "the two references must use different methods, both are {}",
                method_name(m0)
            ),
        );
    }
    let loosest_reference = r0.max(r1);
    let tightest = o.rtols.iter().copied().fold(f64::INFINITY, f64::min);
    if !(loosest_reference > 0.0 && loosest_reference < tightest) {
        return bad(
            "references",
            format!(
                "reference tolerances ({r0:e}, {r1:e}) must be positive and tighter than the \
                 tightest swept tolerance {tightest:e}"
            ),
        );
    }
    if let Some(d) = o.duration.filter(|d| !(d.is_finite() && *d > 0.0)) {
        return bad("duration", format!("{d:?} s must be positive"));
    }
    if !(o.start_up.is_finite() && o.start_up > 0.0) {
        return bad("start_up", format!("{:?} s must be positive", o.start_up));
    }
    if !(o.separation_fraction.is_finite() && o.separation_fraction > 0.0) {
        return bad(
            "separation_fraction",
            format!("{:?} must be positive", o.separation_fraction),
        );
    }
    if !(o.output_interval.is_finite() && o.output_interval > 0.0) {
        return bad(
            "output_interval",
            format!("{:?} s must be positive", o.output_interval),
        );
    }
    if o.max_steps == 0 {
        return bad("max_steps", "must be at least 1".into());
    }
    Ok(())
}

/// Output frames a run may keep: each holds every coordinate, so more than this is memory a
/// machine may not have (1e7 frames of the LGRES, 15 coordinates: ~2.4 GB of positions and
/// velocities).
const MAX_OUTPUT_FRAMES: f64 = 1e7;

/// Progress of a sweep, for a caller that shows it.
pub enum Event<'a> {
    /// A run starts: (method, rtol, what: "reference" / "measure" / "time").
    Start(&'static str, f64, &'static str),
    /// A row is done.
    Row(&'a Row),
}

/// Runs the sweep on `scene` (see the module docs): the options checked, the sweep's fixed
/// frame (period, response body, joints, the ideal path), the two references, every method's
/// rows, the report.
pub fn run_sweep(
    name: &str,
    scene: &ValidScene,
    options: &PrecisionOptions,
    on_event: &mut dyn FnMut(Event<'_>),
) -> Result<PrecisionReport, PrecisionError> {
    check_options(options)?;
    let started = Instant::now();
    let setup = Setup::of(scene, options)?;
    let references = run_references(&setup, on_event)?;
    let reference_agreement = setup.errors(&references[1].2, &references[0].2);
    let mut rows = Vec::new();
    for &method in &options.methods {
        let (reference_method, _, reference) = references
            .iter()
            .find(|(m, _, _)| *m != method)
            .unwrap_or(&references[0]);
        let reference = (*reference_method, reference);
        rows.extend(method_rows(&setup, method, reference, on_event));
    }
    Ok(PrecisionReport {
        scene: name.to_string(),
        formulation: scene.solver.formulation,
        duration_s: setup.t_end,
        start_up_s: options.start_up,
        separation_fraction: options.separation_fraction,
        clearances_m: scene
            .active_clearance_joints()
            .map(|c| c.clearance)
            .collect(),
        joints: setup.joint_names,
        repeats: options.repeats,
        references: references
            .into_iter()
            .map(|(method, rtol, m)| ReferenceRun {
                method: method_name(method),
                rtol,
                steps: m.steps,
                wall_s: m.wall_s,
                quantities: m.quantities,
            })
            .collect(),
        reference_agreement,
        rows,
        wall_time_s: started.elapsed().as_secs_f64(),
    })
}

fn unsuitable(reason: impl ToString) -> PrecisionError {
    PrecisionError::Unsuitable(reason.to_string())
}

impl<'a> Setup<'a> {
    /// What every run of a sweep on `scene` shares: its end, response body, clearance joints
    /// and the ideal mechanism's path of the body, refused when the scene or the options
    /// cannot give them.
    fn of(scene: &'a ValidScene, options: &'a PrecisionOptions) -> Result<Self, PrecisionError> {
        let period = scene
            .cycle_period()
            .ok_or_else(|| unsuitable("no drive period (run.period or a periodic driver)"))?;
        let body = scene
            .response_body()
            .ok_or_else(|| unsuitable("no response body"))?;
        let joint_names: Vec<String> = scene
            .active_clearance_joints()
            .map(|c| c.name.clone())
            .collect();
        if joint_names.is_empty() {
            return Err(unsuitable(
                "no active clearance joint: there is nothing to integrate",
            ));
        }
        let t_end = options.duration.unwrap_or(period);
        if t_end / options.output_interval > MAX_OUTPUT_FRAMES {
            return Err(PrecisionError::Options {
                field: "duration",
                reason: format!(
                    "{t_end:e} s at an output interval of {:e} s is more than \
                     {MAX_OUTPUT_FRAMES:e} output frames",
                    options.output_interval
                ),
            });
        }
        if options.start_up > t_end {
            return Err(PrecisionError::Options {
                field: "start_up",
                reason: format!(
                    "{:?} s is longer than the run ({t_end:?} s)",
                    options.start_up
                ),
            });
        }
        let count = (t_end / options.output_interval * (1.0 + 1e-12)).floor() as usize;
        let times: Vec<f64> = (0..=count)
            .map(|i| (i as f64 * options.output_interval).min(t_end))
            .collect();
        let ideal = sim::integrate::ideal_motion(scene, &times, body).map_err(|e| match e {
            RunError::Build(e) => unsuitable(format!("the ideal mechanism does not build: {e}")),
            e => unsuitable(format!("the ideal mechanism does not move: {e}")),
        })?;
        Ok(Self {
            scene,
            options,
            body,
            t_end,
            ideal: ideal
                .x
                .iter()
                .zip(&ideal.y)
                .map(|(x, y)| [*x, *y])
                .collect(),
            joint_names,
        })
    }
}

/// The two reference runs (method, rtol, run); either failing ends the sweep.
fn run_references(
    setup: &Setup<'_>,
    on_event: &mut dyn FnMut(Event<'_>),
) -> Result<Vec<(Integrator, f64, Measured)>, PrecisionError> {
    let mut references = Vec::new();
    for (method, rtol) in setup.options.references {
        on_event(Event::Start(method_name(method), rtol, "reference"));
        let m = setup
            .measure(method, rtol, None)
            .map_err(|f| PrecisionError::Reference {
                method: method_name(method),
                rtol,
                reason: f.reason,
            })?;
        references.push((method, rtol, m));
    }
    Ok(references)
}

/// The rows of `method` over the swept tolerances, loosest first, against `reference` (its
/// method and run); once a tolerance exceeds the step budget the tighter ones are skipped.
fn method_rows(
    setup: &Setup<'_>,
    method: Integrator,
    reference: (Integrator, &Measured),
    on_event: &mut dyn FnMut(Event<'_>),
) -> Vec<Row> {
    let options = setup.options;
    let mut rows = Vec::new();
    let mut exhausted: Option<f64> = None;
    for &rtol in &options.rtols {
        let mut row = blank_row(setup.scene, method, rtol, reference.0);
        if let Some(looser) = exhausted {
            row.outcome = RowOutcome::Skipped {
                reason: format!(
                    "rtol {looser:e} already exceeded the budget of {} steps",
                    options.max_steps
                ),
            };
        } else {
            on_event(Event::Start(method_name(method), rtol, "measure"));
            match setup.measure(method, rtol, Some(options.max_steps)) {
                Err(f) => {
                    if f.out_of_budget {
                        exhausted = Some(rtol);
                    }
                    row.outcome = RowOutcome::Failed { reason: f.reason };
                }
                Ok(m) => measured_row(setup, &mut row, method, m, reference.1, on_event),
            }
        }
        on_event(Event::Row(&row));
        rows.push(row);
    }
    rows
}

/// A row of `method` at `rtol` with nothing measured yet.
fn blank_row(scene: &ValidScene, method: Integrator, rtol: f64, reference: Integrator) -> Row {
    let tolerances = ScaledTolerances {
        integrator: method,
        rtol,
    };
    Row {
        method: method_name(method),
        rtol,
        atol_position_m: tolerances.absolute(scene).position,
        steps: 0,
        rejected_steps: 0,
        rhs_evaluations: 0,
        factorizations: 0,
        measured_wall_s: f64::NAN,
        wall_s: f64::NAN,
        wall_wear_s: f64::NAN,
        timed_runs_identical: true,
        reference: method_name(reference),
        outcome: RowOutcome::Skipped {
            reason: String::new(),
        },
    }
}

/// `row` of `method` filled from its measured run `m`: the solver counts, the timed repeats (each must end
/// in `m`'s final state bit for bit) and the errors against `reference`.
fn measured_row(
    setup: &Setup<'_>,
    row: &mut Row,
    method: Integrator,
    m: Measured,
    reference: &Measured,
    on_event: &mut dyn FnMut(Event<'_>),
) {
    let options = setup.options;
    row.steps = m.steps;
    row.rejected_steps = m.rejected;
    row.rhs_evaluations = m.rhs;
    row.factorizations = m.factorizations;
    row.measured_wall_s = m.wall_s;
    if options.repeats > 0 {
        on_event(Event::Start(row.method, row.rtol, "time"));
    }
    let mut plain = Vec::new();
    let mut worn = Vec::new();
    for _ in 0..options.repeats {
        for (wear, walls) in [(false, &mut plain), (true, &mut worn)] {
            match setup.time_once(method, row.rtol, wear) {
                Ok((wall, state)) => {
                    walls.push(wall);
                    row.timed_runs_identical &=
                        state.q == m.final_state.q && state.qd == m.final_state.qd;
                }
                Err(_) => row.timed_runs_identical = false,
            }
        }
    }
    row.wall_s = median(plain);
    row.wall_wear_s = median(worn);
    row.outcome = RowOutcome::Completed {
        errors: setup.errors(&m, reference),
        quantities: m.quantities,
    };
}
