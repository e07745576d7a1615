//! A sweep's lives to the clearance limit, combined: each sample's life distribution (its
//! joints' cycles to `run.clearance_limit`, each under its `wear.k_d_scatter`, rescaled from
//! the one simulated life; `sim::life_distribution`) weighs equally in one mixture, the
//! life of a joint (or mechanism) whose other inputs scatter as the sweep drew them. Its B10 and
//! B50 carry two noises in quadrature: the bootstrap over the samples (a finite number of
//! draws of the inputs) and each sample's own sampling noise.
//!
//! A sweep whose base scene sets a clearance limit keeps, per wearing joint, the cycles to it
//! and their noise as metrics of its own ([`crate::LifeColumns`]), so any engine's rows hold
//! them.

use rand::Rng;
use rand::SeedableRng;
use rand_chacha::ChaCha20Rng;
use scene::KdCorrelation;
use sim::life_distribution::{
    BLives, JointLife, LifeDistribution, LifeOf, MechanismLife, Mixture, SampledLives,
    mixture_b_lives, sample,
};

use crate::{Row, Status, Sweep};

/// The combined life distribution's figure in a sweep's folder.
pub const LIFE_FILE: &str = "life_distribution.png";

/// Bootstrap resamples of the samples for the B lives' noise: the noise's own relative error
/// is about `1/√(2·1000)`, 2 %.
pub const RESAMPLES: usize = 1000;

/// The seed of the bootstrap's stream: the same rows give the same noise.
const BOOTSTRAP_SEED: u64 = 0x6c69_6665;

/// A sweep's combined life distribution.
#[derive(Debug, Clone)]
pub struct SweepLife {
    /// The clearance limit, m.
    pub limit_m: f64,
    /// How each sample's joints' `k_d` scatter together in its mechanism's life.
    pub correlation: KdCorrelation,
    /// Samples that ran and whose every wearing joint reached the limit.
    pub used: Vec<usize>,
    /// Samples that ran but where a joint did not reach the limit (within `run.max_cycles`,
    /// or the scene's stages): their lives are longer than the run, not known.
    pub not_reached: Vec<usize>,
    /// Per joint (`joint A`) and for the mechanism, the combined distribution sampled, with
    /// its B lives; `None` when a sample did not reach the limit (the mixture would be
    /// biased) or none ran.
    pub distributions: Option<SampledLives>,
}

/// The combined life of `rows` (`None` when the sweep keeps no life metrics).
pub fn combine(sweep: &Sweep, rows: &[Row]) -> Option<SweepLife> {
    let life = sweep.life.as_ref()?;
    let mut members: Vec<MechanismLife> = Vec::new();
    let (mut used, mut not_reached) = (Vec::new(), Vec::new());
    for row in rows.iter().filter(|r| r.written_status() == Status::Ok) {
        let scatters = sweep
            .scene(row.sample)
            .map(|s| {
                life.joints
                    .iter()
                    .map(|(name, _, _)| {
                        s.clearance_joints
                            .iter()
                            .find(|c| &c.name == name)
                            .and_then(|c| c.wear)
                            .map_or(0.0, |w| w.k_d_scatter)
                    })
                    .collect::<Vec<f64>>()
            })
            .ok();
        let joints: Option<Vec<JointLife>> = life
            .joints
            .iter()
            .zip(scatters.iter().flatten())
            .map(|((_, cycles, noise), scatter)| {
                let cycles = row.metrics.get(*cycles).copied().flatten()?;
                (cycles > 0.0).then_some(JointLife {
                    cycles,
                    noise: row.metrics.get(*noise).copied().flatten(),
                    scatter: *scatter,
                })
            })
            .collect();
        match joints.filter(|j| j.len() == life.joints.len()) {
            Some(joints) => {
                used.push(row.sample);
                members.push(MechanismLife {
                    joints,
                    correlation: life.correlation,
                });
            }
            None => not_reached.push(row.sample),
        }
    }
    let distributions = (not_reached.is_empty() && !members.is_empty())
        .then(|| distributions(&members, &life.joints))
        .flatten();
    Some(SweepLife {
        limit_m: life.limit_m,
        correlation: life.correlation,
        used,
        not_reached,
        distributions,
    })
}

/// Per joint and for the mechanism (two joints or more), the mixture of `members` sampled
/// with its B lives.
fn distributions(
    members: &[MechanismLife],
    joints: &[(String, usize, usize)],
) -> Option<SampledLives> {
    let mut rng = ChaCha20Rng::seed_from_u64(BOOTSTRAP_SEED);
    let resamples: Vec<Vec<usize>> = (0..RESAMPLES)
        .map(|_| {
            (0..members.len())
                .map(|_| rng.random_range(0..members.len()))
                .collect()
        })
        .collect();
    // Each joint alone: the members with that joint only.
    let alone: Vec<Vec<MechanismLife>> = (0..joints.len())
        .map(|j| {
            members
                .iter()
                .map(|m| MechanismLife {
                    joints: vec![m.joints[j]],
                    correlation: m.correlation,
                })
                .collect()
        })
        .collect();
    let mut lives: Vec<(LifeOf, Mixture<MechanismLife>, BLives)> = Vec::new();
    for ((name, _, _), members) in joints.iter().zip(alone) {
        let b = mixture_b_lives(&members, &resamples)?;
        lives.push((LifeOf::Joint(name.clone()), Mixture { members }, b));
    }
    if joints.len() > 1 {
        let b = mixture_b_lives(members, &resamples)?;
        lives.push((
            LifeOf::Mechanism,
            Mixture {
                members: members.to_vec(),
            },
            b,
        ));
    }
    let curves: Vec<(LifeOf, &dyn LifeDistribution, BLives)> = lives
        .iter()
        .map(|(of, m, b)| (of.clone(), m as &dyn LifeDistribution, *b))
        .collect();
    sample(&curves, sim::LIFE_DISTRIBUTION_POINTS)
}
