//! One Radau step's collocation equations: the simplified Newton iteration on the
//! transformed stage increments and the filtered embedded error estimate, both with the
//! factorisations of the current step size.

use super::*;

impl Radau5<'_> {
    /// Simplified Newton on the transformed stage increments `F = T⁻¹ Z`; on success `z`
    /// holds the stage increments `Z`.
    pub(super) fn newton(&mut self, h: f64) -> Newton {
        let Some(factors) = self.factors.as_ref() else {
            return Newton::Failed(0.5);
        };
        let n = self.y.len();
        let fac1 = self.gamma / h;
        let alphn = self.alpha / h;
        let betan = self.beta / h;
        let s = &mut self.scratch;
        let [z1, z2, z3] = &mut s.z;
        let [f1, f2, f3] = &mut s.f;
        if self.cold_start || self.h_old == 0.0 {
            for v in [&mut *z1, &mut *z2, &mut *z3, &mut *f1, &mut *f2, &mut *f3] {
                v.fill(0.0);
            }
        } else {
            let c3q = h / self.h_old;
            let [k1, k2, k3] = &self.cont;
            for (c, z) in [(C1 * c3q, &mut *z1), (C2 * c3q, &mut *z2), (c3q, &mut *z3)] {
                for i in 0..n {
                    z[i] = c * (k1[i] + (c - C2M1) * (k2[i] + (c - C1M1) * k3[i]));
                }
            }
            for i in 0..n {
                let (a, b, c) = (z1[i], z2[i], z3[i]);
                f1[i] = TI11 * a + TI12 * b + TI13 * c;
                f2[i] = TI21 * a + TI22 * b + TI23 * c;
                f3[i] = TI31 * a + TI32 * b + TI33 * c;
            }
        }
        self.faccon = self.faccon.max(f64::EPSILON).powf(0.8);
        let mut theta = JACOBIAN_REUSE_RATE;
        let mut previous = 0.0;
        let mut theta_previous = 0.0;
        let mut iterations = 0;
        loop {
            if iterations >= MAX_NEWTON {
                self.theta = theta;
                return Newton::Failed(0.5);
            }
            for (c, z) in [(C1, &mut *z1), (C2, &mut *z2), (1.0, &mut *z3)] {
                s.stage.copy_from(&self.y);
                s.stage += &*z;
                (self.rhs)(s.stage.as_slice(), &[], self.t + c * h, z.as_mut_slice());
            }
            for i in 0..n {
                let (a, b, c) = (z1[i], z2[i], z3[i]);
                let a1 = TI11 * a + TI12 * b + TI13 * c;
                let a2 = TI21 * a + TI22 * b + TI23 * c;
                let a3 = TI31 * a + TI32 * b + TI33 * c;
                s.real[i] = a1 - f1[i] * fac1;
                s.complex[i] = Complex::new(
                    a2 - f2[i] * alphn + f3[i] * betan,
                    a3 - f3[i] * alphn - f2[i] * betan,
                );
            }
            let solved =
                factors.real.solve_mut(&mut s.real) && factors.complex.solve_mut(&mut s.complex);
            iterations += 1;
            self.statistics.nonlinear_iterations += 1;
            let mut sum = 0.0;
            for i in 0..n {
                let w = s.scale[i];
                z1[i] = s.real[i];
                z2[i] = s.complex[i].re;
                z3[i] = s.complex[i].im;
                sum += (z1[i] / w).powi(2) + (z2[i] / w).powi(2) + (z3[i] / w).powi(2);
            }
            let dyno = (sum / (3 * n.max(1)) as f64).sqrt();
            if !solved || !dyno.is_finite() {
                self.theta = theta;
                return Newton::Failed(0.5);
            }
            if iterations > 1 && iterations < MAX_NEWTON {
                let rate = dyno / previous;
                theta = if iterations == 2 {
                    rate
                } else {
                    (rate * theta_previous).sqrt()
                };
                theta_previous = rate;
                if theta < 0.99 {
                    self.faccon = theta / (1.0 - theta);
                    let predicted =
                        self.faccon * dyno * theta.powi((MAX_NEWTON - 1 - iterations) as i32)
                            / self.newton_tolerance;
                    if predicted >= 1.0 {
                        let q = predicted.clamp(1e-4, 20.0);
                        self.theta = theta;
                        return Newton::Failed(
                            0.8 * q.powf(-1.0 / (4 + MAX_NEWTON - 1 - iterations) as f64),
                        );
                    }
                } else {
                    self.theta = theta;
                    return Newton::Failed(0.5);
                }
            }
            previous = dyno.max(f64::EPSILON);
            for i in 0..n {
                f1[i] += z1[i];
                f2[i] += z2[i];
                f3[i] += z3[i];
                z1[i] = T11 * f1[i] + T12 * f2[i] + T13 * f3[i];
                z2[i] = T21 * f1[i] + T22 * f2[i] + T23 * f3[i];
                z3[i] = T31 * f1[i] + f2[i];
            }
            if self.faccon * dyno <= self.newton_tolerance {
                self.theta = theta;
                return Newton::Converged(iterations);
            }
        }
    }

    /// The filtered embedded error estimate (weighted RMS); after a rejection or on a first
    /// step an estimate above 1 is filtered once more (RADAU5's ESTRAD).
    pub(super) fn error_estimate(&mut self, h: f64, rejected: bool) -> f64 {
        let Some(factors) = self.factors.as_ref() else {
            return f64::INFINITY;
        };
        let s = &mut self.scratch;
        let [z1, z2, z3] = &s.z;
        let (e1, e2, e3) = (DD1 / h, DD2 / h, DD3 / h);
        // f2 serves as scratch for the combination of the stages.
        let combination = &mut s.f[1];
        for i in 0..self.y.len() {
            combination[i] = e1 * z1[i] + e2 * z2[i] + e3 * z3[i];
            s.real[i] = combination[i] + self.dy[i];
        }
        let mut error = if factors.real.solve_mut(&mut s.real) {
            norm_of(&s.real, &s.scale)
        } else {
            f64::INFINITY
        };
        if error >= 1.0 && (self.first || rejected) {
            s.stage.copy_from(&self.y);
            s.stage += &s.real;
            (self.rhs)(s.stage.as_slice(), &[], self.t, s.real.as_mut_slice());
            s.real += &*combination;
            error = if factors.real.solve_mut(&mut s.real) {
                norm_of(&s.real, &s.scale)
            } else {
                f64::INFINITY
            };
        }
        if error.is_nan() {
            f64::INFINITY
        } else {
            error.max(1e-10)
        }
    }
}
