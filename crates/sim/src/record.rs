//! The response run: assembly, and the observer that records the response body and the
//! contact state at the output frames, and every body's pose at the animation's frames (its
//! energy books are in `summary`).

use multibody::{Frame, Observer, OutputTimes};
use wear::WornJoint;

use super::summary::{Audit, summarize};
use super::{
    ContactSeries, MechanismFrames, Motion, Progress, Response, ResponseSummary, RunError,
    simulation_options,
};
use crate::build::{BuiltScene, JointHandle, Surfaces, build};
use crate::validity::{ValidityLimits, ValidityTally};
use scene::{Scene, ValidScene};

/// The ideal mechanism at the output times: the recorded body's motion, and every body's pose
/// at the animation's frames (`None`: no animation).
pub(super) struct Ideal {
    pub(super) motion: Motion,
    pub(super) frames: Option<MechanismFrames>,
}

/// Records the response body and the contact state at output frames; forwards progress.
pub(super) struct Recorder<'a> {
    pub(super) body: usize,
    pub(super) joints: &'a [JointHandle],
    pub(super) period: f64,
    pub(super) times: Vec<f64>,
    pub(super) motion: Motion,
    pub(super) contact: Vec<ContactSeries>,
    /// Validity measures per joint (same order as `contact`).
    pub(super) validity: Vec<ValidityTally>,
    pub(super) progress: &'a mut dyn Progress,
    pub(super) record: bool,
    /// Output-frame indices at which every body's pose is recorded (increasing).
    pub(super) frames: &'a [usize],
    /// The poses recorded so far, one per entry of `frames` reached.
    pub(super) poses: Vec<Vec<[f64; 3]>>,
}

/// Points on the pin outline for the true-overlap check (0.5° apart).
const OVERLAP_SAMPLES: usize = 720;
/// The overlap is measured at every this-many-th output frame near contact.
const OVERLAP_EVERY: usize = 4;

impl Observer for Recorder<'_> {
    fn output(&mut self, frame: &Frame<'_>) {
        if !self.record {
            return;
        }
        if self.frames.get(self.poses.len()) == Some(&self.times.len()) {
            self.poses.push(MechanismFrames::poses_of(frame.q));
        }
        self.times.push(frame.t);
        self.motion.push(self.body, frame.q, frame.qd, frame.qdd);
        let frame_index = self.times.len();
        for ((series, handle), tally) in self
            .contact
            .iter_mut()
            .zip(self.joints)
            .zip(&mut self.validity)
        {
            let probe = handle.probe(frame.elements);
            let d = probe
                .map(|p| p.contact(frame.q, frame.qd).diagnostics)
                .unwrap_or_default();
            // On round surfaces the overlap is δ itself, and a model whose δ is the true overlap
            // (the foundation's) does not judge it: measure it on worn joints whose model does.
            let overlap = probe
                .filter(|_| {
                    handle.worn
                        && handle.measures_outline_overlap()
                        && frame_index.is_multiple_of(OVERLAP_EVERY)
                        && d.penetration > -0.25 * handle.clearance
                })
                .map(|p| p.outline_overlap(frame.q, OVERLAP_SAMPLES).depth);
            tally.frame(&d, overlap);
            series.normal_force.push(d.normal_force);
            series.elastic_force.push(d.elastic_force);
            series.friction_force.push(d.friction_force);
            series
                .dissipated
                .push(probe.map_or(0.0, |p| p.damping_dissipation() + p.friction_dissipation()));
            series.penetration.push(d.penetration);
            series.eccentricity.push(d.eccentricity);
            let (s, c) = d.contact_angle.sin_cos();
            series.ex.push(d.eccentricity * c);
            series.ey.push(d.eccentricity * s);
            let (s, c) = d.bearing_angle.sin_cos();
            series.ex_bearing.push(d.eccentricity * c);
            series.ey_bearing.push(d.eccentricity * s);
        }
    }

    fn progress(&mut self, t: f64, _t_end: f64) {
        self.progress.advance(t / self.period);
    }
}

/// Assemble `built` from the scene's initial poses at t = 0.
pub(super) fn assemble(built: &BuiltScene, what: &str) -> Result<multibody::State, RunError> {
    let (q0, qd0) = built.system.initial_guess();
    let state = built
        .system
        .assemble(0.0, &q0, &qd0)
        .map_err(|source| RunError::Assembly {
            what: what.to_string(),
            source,
        })?;
    crate::validity::check_initial_penetration(built, &state, what)?;
    Ok(state)
}

/// The response run on `worn` surfaces (empty: round) with its summary.
pub(super) fn respond(
    scene: &ValidScene,
    worn: &[Option<WornJoint>],
    times: &[f64],
    ideal: &Ideal,
    body: usize,
    progress: &mut dyn Progress,
    what: &str,
) -> Result<(Response, ResponseSummary), RunError> {
    let frames = ideal.frames.as_ref().map_or(&[][..], |f| &f.frames);
    simulate(scene, worn, times, frames, body, progress, what)?.compare(scene, ideal)
}

/// A response simulated, before it is compared with the ideal mechanism: the simulation
/// needs only the animation's frame indices, so the ideal reference can be computed
/// meanwhile ([`super::run_scene`]).
pub(super) struct Simulated {
    built: BuiltScene,
    joints: Vec<JointHandle>,
    initial_energy: Vec<f64>,
    result: multibody::SimulationResult,
    times: Vec<f64>,
    motion: Motion,
    contact: Vec<ContactSeries>,
    poses: Vec<Vec<[f64; 3]>>,
    t_end: f64,
    cycles: u32,
    what: String,
}

/// Simulates the response on `worn` surfaces (empty: round), recording every body's pose at
/// the output frames `frames` (indices into `times`).
pub(super) fn simulate(
    scene: &ValidScene,
    worn: &[Option<WornJoint>],
    times: &[f64],
    frames: &[usize],
    body: usize,
    progress: &mut dyn Progress,
    what: &str,
) -> Result<Simulated, RunError> {
    let period = scene.cycle_period().ok_or(RunError::NoPeriod)?;
    let t_end = times.last().copied().unwrap_or(period);
    let cycles = scene.run.cycles.max(1);
    let mut built = build(
        scene,
        Surfaces {
            worn,
            accumulate_from: None,
            split_halves_at: None,
        },
    )?;
    let state = assemble(&built, what)?;
    let opts = simulation_options(scene, t_end, OutputTimes::At(times.to_vec()), false);
    progress.phase(what, f64::from(cycles));
    let joints = built.joints.clone();
    let initial_energy: Vec<f64> = joints
        .iter()
        .map(|h| {
            h.probe(built.system.elements()).map_or(0.0, |p| {
                p.contact(&state.q, &state.qd).diagnostics.elastic_energy
            })
        })
        .collect();
    let mut recorder = Recorder {
        body,
        joints: &joints,
        period,
        times: Vec::with_capacity(times.len()),
        motion: Motion::default(),
        contact: joints
            .iter()
            .map(|j| ContactSeries {
                name: j.name.clone(),
                clearance: j.clearance,
                ..Default::default()
            })
            .collect(),
        validity: joints
            .iter()
            .map(|j| ValidityTally::new(j.clearance, ValidityLimits::default(), &j.model))
            .collect(),
        progress,
        record: true,
        frames,
        poses: Vec::with_capacity(frames.len()),
    };
    let result = built
        .system
        .simulate(&state, &opts, &mut recorder)
        .map_err(|source| RunError::Simulation {
            what: what.to_string(),
            source,
        })?;
    let Recorder {
        times: rec_times,
        motion,
        mut contact,
        validity,
        progress,
        poses,
        ..
    } = recorder;
    progress.finish();
    for (series, tally) in contact.iter_mut().zip(validity) {
        series.validity = Some(tally.finish());
    }
    Ok(Simulated {
        built,
        joints,
        initial_energy,
        result,
        times: rec_times,
        motion,
        contact,
        poses,
        t_end,
        cycles,
        what: what.to_string(),
    })
}

impl Simulated {
    /// The response against the `ideal` mechanism, with its summary.
    pub(super) fn compare(
        self,
        scene: &Scene,
        ideal: &Ideal,
    ) -> Result<(Response, ResponseSummary), RunError> {
        let Simulated {
            built,
            joints,
            initial_energy,
            result,
            times,
            motion,
            contact,
            poses,
            t_end,
            cycles,
            what,
        } = self;
        if let Some(k) = (0..times.len()).find(|&k| {
            motion.series().iter().any(|s| !s[k].is_finite())
                || contact.iter().any(|c| !c.normal_force[k].is_finite())
        }) {
            return Err(RunError::NonFinite { what, t: times[k] });
        }
        let response = Response {
            times,
            motion,
            ideal: ideal.motion.clone(),
            contact,
            frames: ideal.frames.as_ref().map(|f| MechanismFrames {
                frames: f.frames.clone(),
                poses,
                ideal_poses: f.ideal_poses.clone(),
            }),
        };
        let audit = Audit {
            built: &built,
            result: &result,
            joints: &joints,
            initial_energy: &initial_energy,
        };
        let summary = summarize(scene, &response, Some(audit), cycles, t_end);
        Ok((response, summary))
    }
}
