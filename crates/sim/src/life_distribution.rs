//! The distribution of the cycles to a clearance limit under the scatter of the wear
//! coefficients, and its B lives (the cycles by which a fraction of such joints or mechanisms
//! has reached the limit, as quoted for rolling bearings: B10, B50).
//!
//! Archard wear is linear in `k_d`, and `k_d` enters nothing but the wear: a life simulated at
//! `k_d` is the life with every joint's `k_d` scaled to `f·k_d`, its cycle axis divided by `f`
//! (the same surfaces after the same product `k_d · N`, hence the same dynamics). One joint's
//! `k_d` scaled alone is not that exactly: the joints share the mechanism's dynamics
//! ([`KdCorrelation::Independent`]). A joint whose `ln k_d` is normal
//! with standard deviation `s` about the simulated `ln k_d` therefore reaches the limit after a
//! lognormal number of cycles, with median the simulated cycles `N` and the same `s`:
//! `B_p = N · exp(s · z_p)`, `z_p` the standard normal's `p`-quantile. A mechanism's life is its
//! first joint's to reach the limit; how its joints' `k_d` scatter together
//! ([`KdCorrelation`]) decides its distribution. A sweep's lives over other inputs combine into
//! a [`Mixture`].
//!
//! Every quantile is found by bisection of the distribution function in `ln n`, so the
//! closed forms (`B_p = N exp(s z_p)` for one joint) are checks, not the code's route.

use scene::KdCorrelation;
use serde::{Deserialize, Serialize};

/// One wearing joint's life to the limit: the cycles the simulated life took (the median
/// under the scatter), their sampling noise, and the scatter of `ln k_d`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct JointLife {
    /// Cycles to the limit at the scene's `k_d` (> 0).
    pub cycles: f64,
    /// Their sampling noise (a standard error); `None`: not measured.
    pub noise: Option<f64>,
    /// Standard deviation of `ln k_d` (≥ 0; 0: no scatter, every such joint lasts `cycles`).
    pub scatter: f64,
}

impl JointLife {
    /// Its B lives (those of a mechanism of this one joint, [`b_lives`]).
    pub fn b_lives(self) -> Option<BLives> {
        b_lives(&MechanismLife {
            joints: vec![self],
            // One joint: how joints scatter together does not enter.
            correlation: KdCorrelation::Shared,
        })
    }

    /// The fraction of such joints that have reached the limit by `n` cycles.
    pub fn failed_by(&self, n: f64) -> f64 {
        if self.scatter > 0.0 {
            standard_normal_cdf((n / self.cycles).ln() / self.scatter)
        } else if n >= self.cycles {
            1.0
        } else {
            0.0
        }
    }
}

/// A distribution of the cycles to the limit: a function that rises from 0 to 1.
pub trait LifeDistribution {
    /// The fraction of lives that have ended by `n` cycles (> 0).
    fn failed_by(&self, n: f64) -> f64;
    /// Cycles below which no more than a negligible fraction, and above which all but a
    /// negligible fraction, have ended: the bisection's bracket, `(low, high)`, `0 < low ≤ high`.
    fn bracket(&self) -> (f64, f64);
}

impl LifeDistribution for JointLife {
    fn failed_by(&self, n: f64) -> f64 {
        JointLife::failed_by(self, n)
    }
    fn bracket(&self) -> (f64, f64) {
        bracket(std::slice::from_ref(self))
    }
}

/// The cycles `[low, high]` that hold every joint's life but a fraction of 1e-15 (9 standard
/// deviations either side of each median).
fn bracket(joints: &[JointLife]) -> (f64, f64) {
    let mut low = f64::INFINITY;
    let mut high: f64 = 0.0;
    for j in joints {
        let spread = (9.0 * j.scatter).exp();
        low = low.min(j.cycles / spread);
        high = high.max(j.cycles * spread);
    }
    (low, high)
}

/// A mechanism's life: the first of its wearing joints to reach the limit, their `k_d`
/// scattering together as `correlation` says.
#[derive(Debug, Clone, PartialEq)]
pub struct MechanismLife {
    /// Its joints' lives (at least one).
    pub joints: Vec<JointLife>,
    /// How their wear coefficients scatter together.
    pub correlation: KdCorrelation,
}

impl LifeDistribution for MechanismLife {
    fn failed_by(&self, n: f64) -> f64 {
        match self.correlation {
            // Survives when every joint does.
            KdCorrelation::Independent => {
                1.0 - self
                    .joints
                    .iter()
                    .map(|j| 1.0 - j.failed_by(n))
                    .product::<f64>()
            }
            // One standard normal Z scales every k_d: joint j has failed by n when
            // Z ≥ ln(N_j/n)/s_j, so the mechanism when Z ≥ the smallest such threshold.
            KdCorrelation::Shared => {
                let threshold = self
                    .joints
                    .iter()
                    .map(|j| {
                        if j.scatter > 0.0 {
                            (j.cycles / n).ln() / j.scatter
                        } else if n >= j.cycles {
                            f64::NEG_INFINITY
                        } else {
                            f64::INFINITY
                        }
                    })
                    .fold(f64::INFINITY, f64::min);
                1.0 - standard_normal_cdf(threshold)
            }
        }
    }
    fn bracket(&self) -> (f64, f64) {
        bracket(&self.joints)
    }
}

/// Equal-weight mixture of lives: a sweep's samples, each its own distribution (its inputs
/// drawn from theirs), combine into the life of a joint or mechanism whose inputs scatter too.
#[derive(Debug, Clone, PartialEq)]
pub struct Mixture<L> {
    /// The members (at least one).
    pub members: Vec<L>,
}

impl<L: LifeDistribution> LifeDistribution for Mixture<L> {
    fn failed_by(&self, n: f64) -> f64 {
        let sum: f64 = self.members.iter().map(|m| m.failed_by(n)).sum();
        sum / self.members.len().max(1) as f64
    }
    fn bracket(&self) -> (f64, f64) {
        self.members
            .iter()
            .map(LifeDistribution::bracket)
            .fold((f64::INFINITY, 0.0), |(l, h), (a, b)| (l.min(a), h.max(b)))
    }
}

/// The cycles by which a fraction `p` in `(0, 1)` of `life` has ended: the distribution
/// function bisected in `ln n` to a relative width of 1e-13 (at the smallest such `n` where
/// the function jumps, as for a joint without scatter). `None` for an empty or non-finite
/// bracket.
pub fn quantile<L: LifeDistribution + ?Sized>(life: &L, p: f64) -> Option<f64> {
    let (low, high) = life.bracket();
    if !(low > 0.0 && high.is_finite() && low <= high && p > 0.0 && p < 1.0) {
        return None;
    }
    // A little outside the bracket, so that a step at its edge is straddled.
    let (mut a, mut b) = ((low * 0.5).ln(), (high * 2.0).ln());
    while b - a > 1e-13 {
        let mid = 0.5 * (a + b);
        if life.failed_by(mid.exp()) >= p {
            b = mid;
        } else {
            a = mid;
        }
    }
    Some(b.exp())
}

/// B lives of a distribution: the cycles by which 10 % and 50 % have ended, with their sampling
/// noise.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BLives {
    /// Cycles by which 10 % have reached the limit.
    pub b10_cycles: f64,
    /// Its sampling noise (a standard error; `None`: not measured).
    pub b10_noise: Option<f64>,
    /// Cycles by which half have reached the limit (the median life).
    pub b50_cycles: f64,
    /// Its sampling noise.
    pub b50_noise: Option<f64>,
}

/// The fractions the B lives stand for.
pub const B10: f64 = 0.10;
/// See [`B10`].
pub const B50: f64 = 0.50;

/// A mechanism's B lives with their noise, propagated from its joints' noise (independent
/// between joints) to first order ([`mixture_b_lives`] of the one mechanism).
pub fn b_lives(life: &MechanismLife) -> Option<BLives> {
    mixture_b_lives(std::slice::from_ref(life), &[])
}

/// The B lives of the equal-weight [`Mixture`] of `members` (a sweep's samples), with their
/// noise: the members' own (each joint's cycles moved by a relative 1e-6, the quantile's
/// change scaled by that joint's noise; independent, summed in quadrature) and, with
/// `resamples` (each a list of member indices drawn with replacement; empty: none), the
/// bootstrap variance of the quantile over them, for the finite number of members. A member
/// joint without noise makes the noise unknown, unless the B life does not depend on it.
pub fn mixture_b_lives(members: &[MechanismLife], resamples: &[Vec<usize>]) -> Option<BLives> {
    let of = |members: Vec<MechanismLife>, p: f64| quantile(&Mixture { members }, p);
    let noise = |p: f64, value: f64| -> Option<f64> {
        let mut sum = 0.0;
        for (m, member) in members.iter().enumerate() {
            for (j, joint) in member.joints.iter().enumerate() {
                let mut moved = members.to_vec();
                let h = 1e-6 * joint.cycles;
                moved[m].joints[j].cycles += h;
                let slope = (of(moved, p)? - value) / h;
                // Bisection resolves 1e-13 relative: below 1e-7 a joint does not move the life.
                if slope.abs() * joint.cycles < 1e-7 * value {
                    continue;
                }
                sum += (slope * joint.noise?).powi(2);
            }
        }
        if !resamples.is_empty() {
            let drawn: Vec<f64> = resamples
                .iter()
                .map(|r| of(r.iter().map(|&k| members[k].clone()).collect(), p))
                .collect::<Option<_>>()?;
            let mean = drawn.iter().sum::<f64>() / drawn.len() as f64;
            let var = drawn.iter().map(|d| (d - mean).powi(2)).sum::<f64>()
                / (drawn.len().max(2) - 1) as f64;
            sum += var;
        }
        Some(sum.sqrt())
    };
    let (b10, b50) = (of(members.to_vec(), B10)?, of(members.to_vec(), B50)?);
    Some(BLives {
        b10_cycles: b10,
        b10_noise: noise(B10, b10),
        b50_cycles: b50,
        b50_noise: noise(B50, b50),
    })
}

/// Distributions sampled on one grid of cycles, for a table or a figure.
#[derive(Debug, Clone, PartialEq)]
pub struct SampledLives {
    /// Cycles, log-spaced and increasing.
    pub cycles: Vec<f64>,
    /// The curves, each the fraction ended at every `cycles`.
    pub curves: Vec<SampledCurve>,
}

/// What a life distribution is the life of.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LifeOf {
    /// A wearing joint, by name.
    Joint(String),
    /// The mechanism: its first joint to reach the limit.
    Mechanism,
}

impl LifeOf {
    /// For a legend or a table: `joint A`, `mechanism`.
    pub fn label(&self) -> String {
        match self {
            Self::Joint(name) => format!("joint {name}"),
            Self::Mechanism => "mechanism".into(),
        }
    }

    /// Its column in a table of sampled distributions (`life_distribution.csv`, the Python
    /// frame): `failed_A`, `failed_mechanism`.
    pub fn column(&self) -> String {
        match self {
            Self::Joint(name) => format!("failed_{name}"),
            Self::Mechanism => "failed_mechanism".into(),
        }
    }
}

/// One distribution of [`SampledLives`].
#[derive(Debug, Clone, PartialEq)]
pub struct SampledCurve {
    /// What it is the life of.
    pub of: LifeOf,
    /// The fraction of lives ended by each of the grid's cycles.
    pub failed: Vec<f64>,
    /// Its B lives.
    pub lives: BLives,
}

/// `curves` (what, distribution, B lives) sampled at `points` (≥ 2) log-spaced cycles from
/// where the first of them has 0.1 % ended to where the last has 99.9 %, widened to at least
/// half and twice the B50s (where a curve without scatter steps); `None` without curves.
pub fn sample(
    curves: &[(LifeOf, &dyn LifeDistribution, BLives)],
    points: usize,
) -> Option<SampledLives> {
    let low = curves
        .iter()
        .filter_map(|(_, l, b)| Some(quantile(*l, 1e-3)?.min(b.b50_cycles / 2.0)))
        .reduce(f64::min)?;
    let high = curves
        .iter()
        .filter_map(|(_, l, b)| Some(quantile(*l, 0.999)?.max(b.b50_cycles * 2.0)))
        .reduce(f64::max)?;
    let points = points.max(2);
    let cycles: Vec<f64> = (0..points)
        .map(|k| low * (high / low).powf(k as f64 / (points - 1) as f64))
        .collect();
    let curves = curves
        .iter()
        .map(|(of, life, lives)| SampledCurve {
            of: of.clone(),
            failed: cycles.iter().map(|n| life.failed_by(*n)).collect(),
            lives: *lives,
        })
        .collect();
    Some(SampledLives { cycles, curves })
}

/// Cycles with their sampling noise for a sentence, a legend or a table: `1.203e6 ± 2.1e4`
/// (the value alone without noise).
pub fn cycles_with_noise(cycles: f64, noise: Option<f64>) -> String {
    match noise {
        Some(n) => format!("{cycles:.3e} ± {n:.1e}"),
        None => format!("{cycles:.3e}"),
    }
}

/// The standard normal distribution function `Φ(x) = erfc(−x/√2)/2` (libm's erfc: accurate
/// in the tails, where `1 − Φ` would cancel).
pub fn standard_normal_cdf(x: f64) -> f64 {
    0.5 * libm::erfc(-x / std::f64::consts::SQRT_2)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Φ⁻¹(0.1), to 16 digits (a published constant, not computed here).
    const Z10: f64 = -1.281_551_565_544_600_5;

    fn joint(cycles: f64, scatter: f64) -> JointLife {
        JointLife {
            cycles,
            noise: Some(0.01 * cycles),
            scatter,
        }
    }

    #[test]
    fn a_joints_b_lives_are_its_lognormal_quantiles() {
        for s in [0.1, 0.5, 1.5] {
            let life = MechanismLife {
                joints: vec![joint(1.3e6, s)],
                correlation: KdCorrelation::Independent,
            };
            let b = b_lives(&life).unwrap();
            assert!((b.b50_cycles / 1.3e6 - 1.0).abs() < 1e-12, "{b:?}");
            assert!((b.b10_cycles / (1.3e6 * (s * Z10).exp()) - 1.0).abs() < 1e-12);
            // The noise scales with the life: 1 % of each.
            let n10 = b.b10_noise.unwrap() / b.b10_cycles;
            assert!((n10 - 0.01).abs() < 1e-6, "{n10}");
        }
        // No scatter: every such joint lasts the simulated life.
        let b = b_lives(&MechanismLife {
            joints: vec![joint(2e6, 0.0)],
            correlation: KdCorrelation::Shared,
        })
        .unwrap();
        assert!((b.b10_cycles / 2e6 - 1.0).abs() < 1e-12, "{b:?}");
        assert!((b.b50_cycles / 2e6 - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_shared_scatter_makes_the_first_joint_the_mechanisms_life() {
        // One factor scales both: the earlier joint always goes first.
        let life = MechanismLife {
            joints: vec![joint(1e6, 0.5), joint(1.5e6, 0.5)],
            correlation: KdCorrelation::Shared,
        };
        let b = b_lives(&life).unwrap();
        assert!((b.b50_cycles / 1e6 - 1.0).abs() < 1e-12, "{b:?}");
        assert!((b.b10_cycles / (1e6 * (0.5 * Z10).exp()) - 1.0).abs() < 1e-12);
        // Only the first joint moves it: its noise alone.
        assert!((b.b50_noise.unwrap() / 1e4 - 1.0).abs() < 1e-5, "{b:?}");
    }

    #[test]
    fn independent_joints_survive_together() {
        // Two equal joints on their own: S(n) = S1(n)², so the median solves
        // Φ(ln(n/N)/s) = 1 − 1/√2 (closed form checked by its own definition).
        let (n, s) = (1e6, 0.5);
        let life = MechanismLife {
            joints: vec![joint(n, s), joint(n, s)],
            correlation: KdCorrelation::Independent,
        };
        let b50 = quantile(&life, B50).unwrap();
        let one = joint(n, s);
        let survives = 1.0 - one.failed_by(b50);
        assert!((survives * survives - 0.5).abs() < 1e-12, "{b50}");
        // Earlier than either joint's median, later than the shared case's B10.
        assert!(b50 < n && b50 > n * (s * Z10).exp());
        // A joint that lasts far longer changes nothing.
        let far = MechanismLife {
            joints: vec![joint(n, s), joint(1e3 * n, s)],
            correlation: KdCorrelation::Independent,
        };
        assert!((quantile(&far, B50).unwrap() / n - 1.0).abs() < 1e-9);
    }

    #[test]
    fn a_mixture_of_equal_lives_is_that_life_and_of_two_lies_between() {
        let a = joint(1e6, 0.4);
        let same = Mixture {
            members: vec![a, a, a],
        };
        assert!((quantile(&same, B10).unwrap() / quantile(&a, B10).unwrap() - 1.0).abs() < 1e-12);
        let b = joint(4e6, 0.4);
        let two = Mixture {
            members: vec![a, b],
        };
        let m = quantile(&two, B50).unwrap();
        // Symmetric about the geometric mean of the medians: exactly 2e6.
        assert!((m / 2e6 - 1.0).abs() < 1e-9, "{m}");
        assert!((two.failed_by(m) - 0.5).abs() < 1e-9);
    }

    #[test]
    fn a_mixtures_noise_adds_the_bootstrap_over_its_members() {
        let member = |cycles: f64| MechanismLife {
            joints: vec![JointLife {
                cycles,
                noise: Some(0.0),
                scatter: 0.4,
            }],
            correlation: KdCorrelation::Independent,
        };
        let members = [member(1e6), member(4e6)];
        // Two resamples, each one member twice: B50s 1e6 and 4e6, sample sd 1.5e6·√2.
        let b = mixture_b_lives(&members, &[vec![0, 0], vec![1, 1]]).unwrap();
        assert!((b.b50_cycles / 2e6 - 1.0).abs() < 1e-9, "{b:?}");
        let sd = 1.5e6 * 2f64.sqrt();
        assert!((b.b50_noise.unwrap() / sd - 1.0).abs() < 1e-9, "{b:?}");
        // Without resamples, noise-free members give a noise-free mixture.
        let b = mixture_b_lives(&members, &[]).unwrap();
        assert_eq!(b.b50_noise, Some(0.0));
        // A member without noise leaves it unknown.
        let mut unknown = members.clone();
        unknown[0].joints[0].noise = None;
        assert_eq!(mixture_b_lives(&unknown, &[]).unwrap().b50_noise, None);
    }

    #[test]
    fn the_normal_distribution_function_matches_its_table() {
        assert!((standard_normal_cdf(Z10) - 0.1).abs() < 1e-15);
        assert_eq!(standard_normal_cdf(0.0), 0.5);
        // Φ(−8) = 6.22096057e-16: accurate in the tail.
        assert!((standard_normal_cdf(-8.0) / 6.220_960_574_271_785e-16 - 1.0).abs() < 1e-9);
    }
}
