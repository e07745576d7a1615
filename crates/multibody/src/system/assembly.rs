//! Position and velocity analysis: assembling a state on the constraints by Newton's method
//! with least-norm steps, and the kinematic analysis of a fully driven mechanism built on it.

use nalgebra::DMatrix;

use crate::error::{AssemblyError, KinematicsError};
use crate::linalg::DenseLu;
use crate::state::State;
use crate::trajectory::Trajectory;

use super::{Baumgarte, SINGULAR_PIVOT, System, local_dot};

/// Newton iterations of position analysis stop when every `|Φ_k|` is below this (m or rad).
const POSITION_TOLERANCE: f64 = 1e-12;
/// Position analysis fails if after its iterations some `|Φ_k|` is still above this.
const POSITION_ACCEPTANCE: f64 = 1e-9;
const MAX_NEWTON_ITERATIONS: usize = 50;

impl System {
    fn check_length(&self, values: &[f64], what: &'static str) -> Result<(), AssemblyError> {
        if values.len() != self.coordinate_count() {
            return Err(AssemblyError::WrongLength {
                expected: self.coordinate_count(),
                actual: values.len(),
            });
        }
        if !values.iter().all(|v| v.is_finite()) {
            return Err(AssemblyError::NonFinite { what });
        }
        Ok(())
    }

    /// Assembly: Newton–Raphson (least-norm steps) from `q_guess` onto `Φ(q, t) = 0`, then the
    /// velocities closest to `qd_guess` that satisfy `Φ_q q̇ = −Φ_t`.
    pub fn assemble(
        &self,
        t: f64,
        q_guess: &[f64],
        qd_guess: &[f64],
    ) -> Result<State, AssemblyError> {
        self.check_length(q_guess, "position guess")?;
        self.check_length(qd_guess, "velocity guess")?;
        let (n, m) = (self.coordinate_count(), self.constraint_count());
        if m > n {
            return Err(AssemblyError::Overconstrained {
                equations: m,
                coordinates: n,
            });
        }
        self.assemble_in(&mut Projector::new(n, m), t, q_guess, qd_guess)
    }

    /// [`System::assemble`] in `projector`'s storage (sized for this system), so that a
    /// series of assemblies ([`System::kinematics`]) allocates it once.
    fn assemble_in(
        &self,
        projector: &mut Projector,
        t: f64,
        q_guess: &[f64],
        qd_guess: &[f64],
    ) -> Result<State, AssemblyError> {
        let m = self.constraint_count();
        let mut q = q_guess.to_vec();
        let mut converged = false;
        for _ in 0..MAX_NEWTON_ITERATIONS {
            projector.evaluate(self, t, &q)?;
            if projector
                .residual
                .iter()
                .all(|r| r.abs() <= POSITION_TOLERANCE)
            {
                converged = true;
                break;
            }
            let step = projector.least_norm(&projector.residual);
            for (qi, dqi) in q.iter_mut().zip(step) {
                *qi -= dqi;
            }
            if !q.iter().all(|v| v.is_finite()) {
                break;
            }
        }
        if !converged {
            projector.evaluate_residual(self, t, &q);
            let residual = projector
                .residual
                .iter()
                .fold(0.0_f64, |a, r| a.max(r.abs()));
            if residual.is_nan() || residual > POSITION_ACCEPTANCE {
                return Err(self.not_converged(t, &projector.residual, residual));
            }
            projector.evaluate(self, t, &q)?;
        }
        // Velocities: q̇ = q̇₀ − Φ_qᵀ (Φ_q Φ_qᵀ)⁻¹ (Φ_q q̇₀ + Φ_t).
        let mut velocity_error = vec![0.0; m];
        for (k, error) in velocity_error.iter_mut().enumerate() {
            let d = self.constraints.local(k, &q, qd_guess, t);
            *error = local_dot(&d, self.constraints.slots(k), qd_guess) + d.time_rate;
        }
        let correction = projector.least_norm(&velocity_error);
        let qd = qd_guess
            .iter()
            .zip(correction)
            .map(|(v, c)| v - c)
            .collect();
        Ok(State { t, q, qd })
    }

    fn not_converged(&self, t: f64, residual: &[f64], max: f64) -> AssemblyError {
        let mut order: Vec<usize> = (0..residual.len()).collect();
        order.sort_by(|a, b| residual[*b].abs().total_cmp(&residual[*a].abs()));
        let worst = order
            .iter()
            .take(4)
            .map(|&k| format!("{} = {:.3e}", self.constraints.labels()[k], residual[k]))
            .collect::<Vec<_>>()
            .join(", ");
        AssemblyError::NotConverged {
            t,
            iterations: MAX_NEWTON_ITERATIONS,
            residual: max,
            worst,
        }
    }

    /// Kinematic analysis of a mechanism driven in every degree of freedom: positions,
    /// velocities, accelerations and multipliers at each of `times`, from the constraints
    /// alone. Each time starts Newton from the previous solution (the first from `q_guess`),
    /// so closely spaced times follow one assembly branch. Force elements enter the
    /// multipliers through `M q̈ + Φ_qᵀλ = G`.
    pub fn kinematics(
        &self,
        times: &[f64],
        q_guess: &[f64],
    ) -> Result<Trajectory, KinematicsError> {
        let (n, m) = (self.coordinate_count(), self.constraint_count());
        if n != m {
            return Err(KinematicsError::NotFullyDriven {
                coordinates: n,
                equations: m,
            });
        }
        let zero = vec![0.0; n];
        let mut solution = Trajectory {
            coordinates: n,
            constraints: m,
            ..Trajectory::default()
        };
        self.check_length(q_guess, "position guess")?;
        let mut evaluator = self.evaluator(Baumgarte::NONE);
        let mut projector = Projector::new(n, m);
        let mut guess = q_guess.to_vec();
        for &t in times {
            // Newton starts from the previous time's solution carried forward to second
            // order, `q + q̇ Δt + q̈ Δt²/2`: closer than the previous `q` by a factor of about
            // `Δt`, it saves an iteration (a Jacobian and its factorization) at most times.
            if let Some(&previous) = solution.times.last() {
                let dt = t - previous;
                let k = solution.times.len() - 1;
                let frame = k * n..(k + 1) * n;
                let (q, qd, qdd) = (
                    &solution.q[frame.clone()],
                    &solution.qd[frame.clone()],
                    &solution.qdd[frame],
                );
                for (i, g) in guess.iter_mut().enumerate() {
                    let predicted = q[i] + dt * (qd[i] + 0.5 * dt * qdd[i]);
                    *g = if predicted.is_finite() {
                        predicted
                    } else {
                        q[i]
                    };
                }
            }
            let state = self.assemble_in(&mut projector, t, &guess, &zero)?;
            evaluator
                .solve_accelerations(&self.elements, t, &state.q, &state.qd)
                .map_err(|error| KinematicsError::Evaluation { t, error })?;
            solution.times.push(t);
            solution.q.extend_from_slice(&state.q);
            solution.qd.extend_from_slice(&state.qd);
            solution.qdd.extend_from_slice(evaluator.accelerations());
            solution.lambda.extend_from_slice(evaluator.multipliers());
        }
        Ok(solution)
    }
}

/// Position-level workspace: `Φ`, `Φ_q` and the factors of `Φ_q Φ_qᵀ`.
struct Projector {
    residual: Vec<f64>,
    phi_q: DMatrix<f64>,
    normal: DMatrix<f64>,
    lu: DenseLu,
}

impl Projector {
    fn new(n: usize, m: usize) -> Self {
        Self {
            residual: vec![0.0; m],
            phi_q: DMatrix::zeros(m, n),
            normal: DMatrix::zeros(m, m),
            lu: DenseLu::new(m),
        }
    }

    fn evaluate_residual(&mut self, system: &System, t: f64, q: &[f64]) {
        let zero = vec![0.0; q.len()];
        for (k, r) in self.residual.iter_mut().enumerate() {
            *r = system.constraints.local(k, q, &zero, t).value;
        }
    }

    /// `Φ`, `Φ_q` and the LU of `Φ_q Φ_qᵀ`; a rank-deficient `Φ_q` is an error naming the
    /// dependent constraints.
    fn evaluate(&mut self, system: &System, t: f64, q: &[f64]) -> Result<(), AssemblyError> {
        let zero = vec![0.0; q.len()];
        self.phi_q.fill(0.0);
        for k in 0..self.residual.len() {
            let d = system.constraints.local(k, q, &zero, t);
            self.residual[k] = d.value;
            for (slot, index) in system.constraints.slots(k).iter().enumerate() {
                if let Some(index) = *index {
                    self.phi_q[(k, index)] += d.grad[slot];
                }
            }
        }
        self.normal = &self.phi_q * self.phi_q.transpose();
        if self.lu.factor(&self.normal, SINGULAR_PIVOT).is_err() {
            return Err(AssemblyError::RankDeficient {
                t,
                dependent: system.dependent_constraints(&self.phi_q),
            });
        }
        Ok(())
    }

    /// `Φ_qᵀ (Φ_q Φ_qᵀ)⁻¹ r`: the smallest change of `q` (or `q̇`) that removes `r` to first order.
    fn least_norm(&self, r: &[f64]) -> Vec<f64> {
        let mut mu = r.to_vec();
        self.lu.solve_in_place(&mut mu);
        let mu = nalgebra::DVector::from_vec(mu);
        (self.phi_q.transpose() * mu).as_slice().to_vec()
    }
}
