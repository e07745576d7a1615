//! Three-stage Radau IIA (order 5, L-stable, stiffly accurate) after Hairer & Wanner's RADAU5
//! (Solving ODEs II, §IV.8).
//!
//! Each step solves the collocation equations by a simplified Newton iteration. The
//! transformation `T⁻¹ A⁻¹ T` of the Butcher matrix (one real eigenvalue, one complex pair)
//! splits the `3n` iteration into one real `n × n` system `(γ/h − J)` and one complex
//! `n × n` system `((α + iβ)/h − J)`, each LU-factored once per step size and reused by all
//! iterations and, while `h` stays (nearly) the same, by later steps. The Jacobian is kept
//! across steps while Newton converges fast. The local error is the embedded order-3
//! estimate filtered by `(γ/h − J)⁻¹` (which keeps it bounded for stiff components), and the
//! step size follows Gustafsson's predictive controller. The collocation polynomial of the
//! last step is the dense output (output times, quadrature nodes, root location) and, scaled
//! to the next step, the Newton starting value.

use nalgebra::{Complex, DMatrix, DVector, Dyn, linalg::LU};

/// The right-hand side or the root functions, in diffsol's closure signature `(y, p, t, out)`.
pub(crate) type VectorFunction<'a> = &'a dyn Fn(&[f64], &[f64], f64, &mut [f64]);
/// The dense Jacobian `∂f/∂y` at `(t, y)`.
pub(crate) type JacobianFunction<'a> = &'a dyn Fn(&[f64], f64, &mut DMatrix<f64>);

/// Why a Radau step could not be taken.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RadauError {
    /// The step size fell below the minimum.
    #[error("Radau IIA: step size {h:e} s below the minimum {min:e} s at t = {t}")]
    StepTooSmall {
        /// Time (s).
        t: f64,
        /// The step that was needed (s).
        h: f64,
        /// The minimum step (s).
        min: f64,
    },
    /// Too many consecutive error-test failures in one step.
    #[error("Radau IIA: {count} consecutive error-test failures at t = {t}")]
    ErrorTestFailures {
        /// Time (s).
        t: f64,
        /// Failures.
        count: usize,
    },
    /// Too many Newton failures over the run.
    #[error("Radau IIA: {count} Newton failures, the limit, at t = {t}")]
    NonlinearFailures {
        /// Time (s).
        t: f64,
        /// Failures.
        count: usize,
    },
    /// A stop time at or before the current time.
    #[error("Radau IIA: stop time {stop} not after the current time {t}")]
    StopTime {
        /// Requested stop time (s).
        stop: f64,
        /// Current time (s).
        t: f64,
    },
    /// Dense output asked outside the last step.
    #[error("Radau IIA: interpolation at {t} outside the last step [{from}, {to}]")]
    Interpolation {
        /// Requested time (s).
        t: f64,
        /// Start of the last step (s).
        from: f64,
        /// End of the last step (s).
        to: f64,
    },
}

/// Limits of a run, as diffsol's `OdeSolverOptions`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct RadauLimits {
    pub min_step: f64,
    pub max_error_test_failures: usize,
    pub max_nonlinear_failures: usize,
}

/// Counters, named as diffsol's.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct RadauStatistics {
    pub steps: usize,
    pub error_test_failures: usize,
    pub nonlinear_failures: usize,
    pub nonlinear_iterations: usize,
    /// LU factorisations of the pair (real, complex) of iteration matrices.
    pub factorizations: usize,
}

/// What a successful [`Radau5::step`] reached.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum RadauStop {
    /// An ordinary accepted step.
    Step,
    /// The step ended exactly at the stop time.
    StopTime,
    /// Root function `index` changed sign at `t` within the step (the state stays at the
    /// step's end until [`Radau5::move_back`]).
    Root(f64, usize),
}

// Method coefficients (RADAU5's, Hairer & Wanner).
const SQ6: f64 = 2.449_489_742_783_178;
const C1: f64 = (4.0 - SQ6) / 10.0;
const C2: f64 = (4.0 + SQ6) / 10.0;
const C1M1: f64 = C1 - 1.0;
const C2M1: f64 = C2 - 1.0;
const C1MC2: f64 = C1 - C2;
const DD1: f64 = -(13.0 + 7.0 * SQ6) / 3.0;
const DD2: f64 = (-13.0 + 7.0 * SQ6) / 3.0;
const DD3: f64 = -1.0 / 3.0;
const T11: f64 = 9.123_239_487_089_294e-2;
const T12: f64 = -0.141_255_295_020_954_2;
const T13: f64 = -3.002_919_410_514_742_4e-2;
const T21: f64 = 0.241_717_932_707_107;
const T22: f64 = 0.204_129_352_293_799_9;
const T23: f64 = 0.382_942_112_757_261_9;
const T31: f64 = 0.966_048_182_615_093;
const TI11: f64 = 4.325_579_890_063_155;
const TI12: f64 = 0.339_199_251_815_809_87;
const TI13: f64 = 0.541_770_539_935_874_9;
const TI21: f64 = -4.178_718_591_551_905;
const TI22: f64 = -0.327_682_820_761_062_4;
const TI23: f64 = 0.476_623_554_500_550_45;
const TI31: f64 = -0.502_872_634_945_786_9;
const TI32: f64 = 2.571_926_949_855_605;
const TI33: f64 = -0.596_039_204_828_224_9;

/// Newton iterations before a step is retried smaller (RADAU5's default).
const MAX_NEWTON: usize = 7;
/// Keep the Jacobian for the next step when the last Newton contraction rate was below this.
/// RADAU5 uses 0.001 for small systems; on the LGRES (joint coordinates, 0.3 s, rtol 1e-6 and
/// 1e-8) 0.001, 0.01, 0.1 and 0.3 ran equally fast within the noise (the exact Jacobian costs
/// about 4–7 right-hand sides, docs/performance.md).
const JACOBIAN_REUSE_RATE: f64 = 0.01;
/// Keep `h` (and the factorisations) when the controller proposes a ratio in this range.
const KEEP_STEP: (f64, f64) = (1.0, 1.2);
const SAFETY: f64 = 0.9;
/// Bounds of `h_new / h`.
const SHRINK_LIMIT: f64 = 0.2;
const GROWTH_LIMIT: f64 = 8.0;

/// The real eigenvalue `γ` and the complex pair `α ± iβ` of `A⁻¹`.
fn eigenvalues() -> (f64, f64, f64) {
    let cbrt81 = 81f64.cbrt();
    let cbrt9 = 9f64.cbrt();
    let u1 = (6.0 + cbrt81 - cbrt9) / 30.0;
    let alpha = (12.0 - cbrt81 + cbrt9) / 60.0;
    let beta = (cbrt81 + cbrt9) * 3f64.sqrt() / 60.0;
    let norm = alpha * alpha + beta * beta;
    (1.0 / u1, alpha / norm, beta / norm)
}

/// The two LU factorisations of one step size.
struct Factors {
    h: f64,
    real: LU<f64, Dyn, Dyn>,
    complex: LU<Complex<f64>, Dyn, Dyn>,
}

/// The Radau IIA integrator: state, step control and dense output.
pub(crate) struct Radau5<'a> {
    rhs: VectorFunction<'a>,
    jacobian_of: JacobianFunction<'a>,
    roots: Option<(VectorFunction<'a>, usize)>,
    limits: RadauLimits,
    /// Tolerances rescaled as RADAU5 does for its order-3 error estimate.
    rtol: f64,
    atol: Vec<f64>,
    newton_tolerance: f64,
    gamma: f64,
    alpha: f64,
    beta: f64,
    t: f64,
    y: DVector<f64>,
    dy: DVector<f64>,
    /// `dy` does not belong to `(t, y)` (after [`Radau5::move_back`]) until the caller
    /// writes it or the next step evaluates it.
    dy_stale: bool,
    /// The next step size.
    h: f64,
    stop: Option<f64>,
    /// The last accepted step `[t_old, t_old + h_old]`, its end state and the collocation
    /// polynomial's coefficients.
    t_old: f64,
    h_old: f64,
    y_end: DVector<f64>,
    cont: [DVector<f64>; 3],
    /// Start the Newton iteration from zero rather than the last polynomial.
    cold_start: bool,
    /// No step accepted since the start or a restart: the error estimate is filtered twice.
    first: bool,
    jacobian: DMatrix<f64>,
    /// `jacobian` is that of the current `(t, y)`.
    jacobian_fresh: bool,
    /// `jacobian` may be used (it is of this or an earlier state of the same regime).
    jacobian_usable: bool,
    factors: Option<Factors>,
    /// Newton contraction rate of the last step.
    theta: f64,
    faccon: f64,
    /// Gustafsson's memory: the last accepted step and its error.
    h_accepted: f64,
    error_accepted: f64,
    g0: Vec<f64>,
    statistics: RadauStatistics,
    scratch: Scratch,
}

struct Scratch {
    z: [DVector<f64>; 3],
    f: [DVector<f64>; 3],
    stage: DVector<f64>,
    scale: DVector<f64>,
    real: DVector<f64>,
    complex: DVector<Complex<f64>>,
    g1: Vec<f64>,
    gmid: Vec<f64>,
    ymid: Vec<f64>,
}

impl<'a> Radau5<'a> {
    /// Starts at `(t0, y0)`; `rtol` and `atol` as the diffsol methods take them.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        rhs: VectorFunction<'a>,
        jacobian_of: JacobianFunction<'a>,
        roots: Option<(VectorFunction<'a>, usize)>,
        t0: f64,
        y0: &[f64],
        rtol: f64,
        atol: &[f64],
        limits: RadauLimits,
    ) -> Self {
        let n = y0.len();
        let rtol_radau = 0.1 * rtol.powf(2.0 / 3.0);
        let atol_radau: Vec<f64> = atol.iter().map(|a| a * rtol_radau / rtol).collect();
        let (gamma, alpha, beta) = eigenvalues();
        let y = DVector::from_column_slice(y0);
        let mut dy = DVector::zeros(n);
        rhs(y.as_slice(), &[], t0, dy.as_mut_slice());
        let root_count = roots.map_or(0, |(_, count)| count);
        let mut g0 = vec![0.0; root_count];
        if let Some((g, _)) = roots {
            g(y.as_slice(), &[], t0, &mut g0);
        }
        let zeros = || DVector::zeros(n);
        let mut radau = Self {
            rhs,
            jacobian_of,
            roots,
            limits,
            rtol: rtol_radau,
            atol: atol_radau,
            newton_tolerance: (10.0 * f64::EPSILON / rtol_radau).max(rtol_radau.sqrt().min(0.03)),
            gamma,
            alpha,
            beta,
            t: t0,
            y: y.clone(),
            dy,
            dy_stale: false,
            h: 0.0,
            stop: None,
            t_old: t0,
            h_old: 0.0,
            y_end: y,
            cont: [zeros(), zeros(), zeros()],
            cold_start: true,
            first: true,
            jacobian: DMatrix::zeros(n, n),
            jacobian_fresh: false,
            jacobian_usable: false,
            factors: None,
            theta: JACOBIAN_REUSE_RATE,
            faccon: 1.0,
            h_accepted: 0.0,
            error_accepted: 0.0,
            g0,
            statistics: RadauStatistics::default(),
            scratch: Scratch {
                z: [zeros(), zeros(), zeros()],
                f: [zeros(), zeros(), zeros()],
                stage: zeros(),
                scale: zeros(),
                real: zeros(),
                complex: DVector::zeros(n),
                g1: vec![0.0; root_count],
                gmid: vec![0.0; root_count],
                ymid: vec![0.0; n],
            },
        };
        radau.h = radau.initial_step();
        radau
    }

    /// Hairer's simple guess `0.01 ‖y‖ / ‖f‖` (weighted norms), 1e-6 s when either is tiny.
    fn initial_step(&mut self) -> f64 {
        self.update_scale();
        let d0 = norm_of(&self.y, &self.scratch.scale);
        let d1 = norm_of(&self.dy, &self.scratch.scale);
        let h = if d0 < 1e-5 || d1 < 1e-5 {
            1e-6
        } else {
            0.01 * d0 / d1
        };
        h.max(self.limits.min_step)
    }

    pub(crate) fn t(&self) -> f64 {
        self.t
    }

    pub(crate) fn y(&self) -> &[f64] {
        self.y.as_slice()
    }

    /// The state and its derivative slot, for the caller to re-evaluate `dy` after an event.
    pub(crate) fn derivative_mut(&mut self) -> (f64, &[f64], &mut [f64]) {
        self.dy_stale = false;
        (self.t, self.y.as_slice(), self.dy.as_mut_slice())
    }

    pub(crate) fn statistics(&self) -> RadauStatistics {
        self.statistics
    }

    /// Steps will end exactly at `stop` when they would pass it (diffsol's semantics).
    pub(crate) fn set_stop_time(&mut self, stop: f64) -> Result<(), RadauError> {
        if stop <= self.t + self.roundoff() {
            return Err(RadauError::StopTime { stop, t: self.t });
        }
        self.stop = Some(stop);
        Ok(())
    }

    fn roundoff(&self) -> f64 {
        100.0 * f64::EPSILON * (self.t.abs() + self.h.abs())
    }

    /// The collocation polynomial of the last step at `t` (its end state before any step).
    pub(crate) fn interpolate(&self, t: f64, out: &mut [f64]) -> Result<(), RadauError> {
        let end = self.t_old + self.h_old;
        let slack = 100.0 * f64::EPSILON * (end.abs() + self.h_old.abs());
        if t < self.t_old - slack || t > end + slack {
            return Err(RadauError::Interpolation {
                t,
                from: self.t_old,
                to: end,
            });
        }
        if self.h_old == 0.0 {
            out.copy_from_slice(self.y_end.as_slice());
            return Ok(());
        }
        let s = (t - end) / self.h_old;
        let [c1, c2, c3] = &self.cont;
        for (i, out) in out.iter_mut().enumerate() {
            *out = self.y_end[i] + s * (c1[i] + (s - C2M1) * (c2[i] + (s - C1M1) * c3[i]));
        }
        Ok(())
    }

    /// Moves the state back to `t` within the last step (a root) and restarts there: no
    /// starting values extrapolated across it, a fresh Jacobian, the step size kept.
    pub(crate) fn move_back(&mut self, t: f64) -> Result<(), RadauError> {
        let mut y = std::mem::take(&mut self.scratch.ymid);
        let result = self.interpolate(t, &mut y);
        if result.is_ok() {
            self.y.as_mut_slice().copy_from_slice(&y);
            self.t = t;
            self.restart();
        }
        self.scratch.ymid = y;
        result
    }

    fn restart(&mut self) {
        self.dy_stale = true;
        self.cold_start = true;
        self.first = true;
        self.jacobian_usable = false;
        self.jacobian_fresh = false;
        self.h_accepted = 0.0;
        if let Some((g, _)) = self.roots {
            g(self.y.as_slice(), &[], self.t, &mut self.g0);
        }
    }

    fn update_scale(&mut self) {
        for ((s, y), a) in self.scratch.scale.iter_mut().zip(&self.y).zip(&self.atol) {
            *s = a + self.rtol * y.abs();
        }
    }

    /// Factors `γ/h − J` and `(α + iβ)/h − J`.
    fn factorize(&mut self, h: f64) {
        let n = self.y.len();
        let mut real = -self.jacobian.clone();
        let mut complex = DMatrix::<Complex<f64>>::from_fn(n, n, |r, c| {
            Complex::new(-self.jacobian[(r, c)], 0.0)
        });
        for i in 0..n {
            real[(i, i)] += self.gamma / h;
            complex[(i, i)] += Complex::new(self.alpha / h, self.beta / h);
        }
        self.factors = Some(Factors {
            h,
            real: real.lu(),
            complex: complex.lu(),
        });
        self.statistics.factorizations += 1;
    }

    /// Takes one accepted step (retrying smaller after error-test or Newton failures).
    pub(crate) fn step(&mut self) -> Result<RadauStop, RadauError> {
        if self.dy_stale {
            (self.rhs)(self.y.as_slice(), &[], self.t, self.dy.as_mut_slice());
            self.dy_stale = false;
        }
        self.update_scale();
        let mut error_failures = 0;
        let mut rejected = false;
        loop {
            let mut h = self.h;
            if h < self.limits.min_step {
                return Err(RadauError::StepTooSmall {
                    t: self.t,
                    h,
                    min: self.limits.min_step,
                });
            }
            let mut at_stop = false;
            if let Some(stop) = self.stop
                && self.t + h >= stop - self.roundoff()
            {
                h = stop - self.t;
                at_stop = true;
            }
            if !self.jacobian_usable {
                (self.jacobian_of)(self.y.as_slice(), self.t, &mut self.jacobian);
                self.jacobian_usable = true;
                self.jacobian_fresh = true;
                self.factors = None;
            }
            if self.factors.as_ref().is_none_or(|f| f.h != h) {
                self.factorize(h);
            }
            match self.newton(h) {
                Newton::Converged(iterations) => {
                    let error = self.error_estimate(h, rejected);
                    let fac = SAFETY.min(
                        SAFETY * (1 + 2 * MAX_NEWTON) as f64 / (iterations + 2 * MAX_NEWTON) as f64,
                    );
                    let mut quot =
                        (1.0 / GROWTH_LIMIT).max((1.0 / SHRINK_LIMIT).min(error.powf(0.25) / fac));
                    if error < 1.0 {
                        if self.h_accepted > 0.0 {
                            let predictive = (self.h_accepted / h)
                                * (error * error / self.error_accepted).powf(0.25)
                                / SAFETY;
                            let predictive =
                                (1.0 / GROWTH_LIMIT).max((1.0 / SHRINK_LIMIT).min(predictive));
                            quot = quot.max(predictive);
                        }
                        self.h_accepted = h;
                        self.error_accepted = error.max(1e-2);
                        let mut h_new = h / quot;
                        if rejected {
                            h_new = h_new.min(h);
                        }
                        // A step shortened to the stop time says little about longer ones:
                        // keep the earlier proposal unless the error asks for less.
                        if at_stop && quot <= 1.0 {
                            h_new = h_new.max(self.h);
                        }
                        return Ok(self.accept(h, h_new, at_stop));
                    }
                    self.statistics.error_test_failures += 1;
                    error_failures += 1;
                    if error_failures >= self.limits.max_error_test_failures {
                        return Err(RadauError::ErrorTestFailures {
                            t: self.t,
                            count: error_failures,
                        });
                    }
                    rejected = true;
                    self.h = if self.first { 0.1 * h } else { h / quot };
                    if !self.jacobian_fresh {
                        self.jacobian_usable = false;
                    }
                }
                Newton::Failed(factor) => {
                    self.statistics.nonlinear_failures += 1;
                    if self.statistics.nonlinear_failures >= self.limits.max_nonlinear_failures {
                        return Err(RadauError::NonlinearFailures {
                            t: self.t,
                            count: self.statistics.nonlinear_failures,
                        });
                    }
                    rejected = true;
                    self.h = factor * h;
                    if !self.jacobian_fresh {
                        self.jacobian_usable = false;
                    }
                }
            }
        }
    }

    fn accept(&mut self, h: f64, h_new: f64, at_stop: bool) -> RadauStop {
        let s = &self.scratch;
        let [z1, z2, z3] = &s.z;
        let [k1, k2, k3] = &mut self.cont;
        for i in 0..self.y.len() {
            k1[i] = (z2[i] - z3[i]) / C2M1;
            let ak = (z1[i] - z2[i]) / C1MC2;
            let acont3 = (ak - z1[i] / C1) / C2;
            k2[i] = (ak - k1[i]) / C1M1;
            k3[i] = k2[i] - acont3;
        }
        self.t_old = self.t;
        self.h_old = h;
        self.t = if at_stop {
            self.stop.unwrap_or(self.t + h)
        } else {
            self.t + h
        };
        self.y += &self.scratch.z[2];
        self.y_end.copy_from(&self.y);
        (self.rhs)(self.y.as_slice(), &[], self.t, self.dy.as_mut_slice());
        self.statistics.steps += 1;
        self.first = false;
        self.cold_start = false;
        // Keep h and the factorisations when the proposal is close; keep the Jacobian while
        // Newton contracted fast.
        let ratio = h_new / h;
        let keep_jacobian = self.theta <= JACOBIAN_REUSE_RATE;
        self.h = if keep_jacobian && (KEEP_STEP.0..=KEEP_STEP.1).contains(&ratio) {
            h
        } else {
            h_new
        };
        self.jacobian_fresh = false;
        self.jacobian_usable = keep_jacobian;
        if at_stop {
            self.stop = None;
        }
        if let Some(root) = self.check_roots() {
            return root;
        }
        if at_stop {
            RadauStop::StopTime
        } else {
            RadauStop::Step
        }
    }
}

/// Weighted RMS norm.
fn norm_of(v: &DVector<f64>, scale: &DVector<f64>) -> f64 {
    let n = v.len().max(1) as f64;
    (v.iter()
        .zip(scale)
        .map(|(x, s)| (x / s).powi(2))
        .sum::<f64>()
        / n)
        .sqrt()
}

/// How a step's Newton iteration ended (`newton`).
enum Newton {
    /// Converged after this many iterations.
    Converged(usize),
    /// Diverged or too slow: retry with the step scaled by this factor.
    Failed(f64),
}

mod newton;
mod roots;

#[cfg(test)]
mod tests;
