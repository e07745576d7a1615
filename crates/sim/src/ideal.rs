//! The reference a response is compared with: the scene's mechanism with every clearance joint
//! ideal, built once per run and analysed kinematically at the output times.

use multibody::System;

use super::record::Ideal;
use super::{MechanismFrames, Motion, RunError};
use crate::build::{Surfaces, build};
use scene::ValidScene;

/// The all-ideal mechanism of a scene: built once, then asked for its motion (a run asks
/// twice: at the first output time before any simulation, so a mechanism that is not fully
/// driven is refused at once, then at all of them beside the response).
pub(super) struct IdealMechanism {
    system: System,
    /// The clearance joints made ideal, comma-separated, for the kinematics error.
    joints: String,
    /// The drivers, comma-separated, for the kinematics error.
    drivers: String,
}

impl IdealMechanism {
    pub(super) fn build(scene: &ValidScene) -> Result<Self, RunError> {
        let names = |v: Vec<&str>| {
            if v.is_empty() {
                "(none)".to_string()
            } else {
                v.join(", ")
            }
        };
        Ok(Self {
            system: build(&scene.idealized(), Surfaces::default())?.system,
            joints: names(
                scene
                    .clearance_joints
                    .iter()
                    .map(|c| c.name.as_str())
                    .collect(),
            ),
            drivers: names(scene.drivers.iter().map(|d| d.name.as_str()).collect()),
        })
    }

    /// The motion of `body` at `times` (kinematic analysis from the file's initial poses), with
    /// the poses of every body at `frames` (indices into `times`) when an animation is drawn.
    pub(super) fn motion(
        &self,
        times: &[f64],
        body: usize,
        frames: Option<Vec<usize>>,
    ) -> Result<Ideal, RunError> {
        let (q0, _) = self.system.initial_guess();
        let kin = self
            .system
            .kinematics(times, &q0)
            .map_err(|source| RunError::Kinematics {
                joints: self.joints.clone(),
                drivers: self.drivers.clone(),
                source,
            })?;
        let mut motion = Motion::default();
        for f in 0..kin.times.len() {
            motion.push(body, kin.q(f), kin.qd(f), kin.qdd(f));
        }
        let frames = frames.map(|frames| MechanismFrames {
            ideal_poses: frames
                .iter()
                .map(|&f| MechanismFrames::poses_of(kin.q(f)))
                .collect(),
            frames,
            poses: Vec::new(),
        });
        Ok(Ideal { motion, frames })
    }
}
