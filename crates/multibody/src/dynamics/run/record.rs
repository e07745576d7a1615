//! What the run loop records between step ends: the output frames (interpolated, handed to
//! the observer and kept in the trajectory), the constraint drift, and the energy audit's
//! quadrature of the elements' and drivers' power.

use crate::constraints::ConstraintOwner;
use crate::error::SimulationError;
use crate::state::State;

use super::super::report::{EnergyAudit, Frame};
use super::super::stepper::{Stepper, integrator_error};
use super::Run;

/// Gauss–Legendre nodes and weights on [0, 1], exact for polynomials of degree 5.
const GAUSS_NODES: [(f64, f64); 3] = [
    (0.112_701_665_379_258_3, 5.0 / 18.0),
    (0.5, 8.0 / 18.0),
    (0.887_298_334_620_741_7, 5.0 / 18.0),
];

impl Run<'_, '_, '_> {
    /// Output frames and energy quadrature over the accepted step `(t_start, t_end]`, from the
    /// integrator's interpolant.
    pub(super) fn process_interval<S: Stepper>(
        &mut self,
        solver: &mut S,
        t_start: f64,
        t_end: f64,
        y: &mut [f64],
    ) -> Result<(), SimulationError> {
        while self.next_output < self.output_times.len()
            && self.output_times[self.next_output] <= t_end
        {
            let t = self.output_times[self.next_output];
            solver
                .interpolate(t, y)
                .map_err(|e| integrator_error(t, e))?;
            let mut values = std::mem::take(&mut self.frame_buffer);
            values.copy_from_slice(self.equations.cartesian(t, y, &mut self.mapped));
            let emitted = self.emit_frame(t, &values);
            self.frame_buffer = values;
            emitted?;
        }
        if self.options.energy_audit && t_end > t_start && self.needs_quadrature() {
            for (node, weight) in GAUSS_NODES {
                let t = t_start + node * (t_end - t_start);
                solver
                    .interpolate(t, y)
                    .map_err(|e| integrator_error(t, e))?;
                self.accumulate_power(t, y, weight * (t_end - t_start));
            }
        }
        Ok(())
    }

    fn needs_quadrature(&self) -> bool {
        !self.driver_work.is_empty()
            || self.elements.borrow().iter().any(|e| {
                e.potential_energy(0.0, &self.current[..self.system.coordinate_count()])
                    .is_none()
            })
    }

    /// Adds `weight ×` the power of the non-conservative elements and the drivers at the
    /// integrated state `x`: in one pass of the formulation when it offers one and there are
    /// drivers (whose power needs a solve anyway), else from the Cartesian state.
    fn accumulate_power(&mut self, t: f64, x: &[f64], weight: f64) {
        let elements = self.elements.borrow();
        if !self.driver_work.is_empty() {
            let mut element_powers = std::mem::take(&mut self.element_power);
            let mut driver_powers = std::mem::take(&mut self.driver_power);
            let result =
                self.equations
                    .powers(&elements, t, x, &mut element_powers, &mut driver_powers);
            if let Some(result) = &result
                && result.is_ok()
            {
                let works = self.element_work.iter_mut().chain(&mut self.driver_work);
                for (work, power) in works.zip(element_powers.iter().chain(&driver_powers)) {
                    *work += weight * power;
                }
            }
            self.element_power = element_powers;
            self.driver_power = driver_powers;
            if result.is_some() {
                return;
            }
        }
        let n = self.system.coordinate_count();
        let y = self.equations.cartesian(t, x, &mut self.mapped);
        let (q, qd) = y.split_at(n);
        for (work, element) in self.element_work.iter_mut().zip(elements.iter()) {
            if element.potential_energy(t, q).is_some() {
                continue;
            }
            self.scratch.fill(0.0);
            element.add_forces(t, q, qd, &mut self.scratch);
            *work += weight * self.scratch.iter().zip(qd).map(|(f, v)| f * v).sum::<f64>();
        }
        if self.driver_work.is_empty()
            || self
                .evaluator
                .solve_accelerations(&elements, t, q, qd)
                .is_err()
        {
            return;
        }
        let lambda = self.evaluator.multipliers();
        for (k, owner) in self.system.constraint_owners().iter().enumerate() {
            if let ConstraintOwner::Driver(driver) = owner {
                self.driver_work[driver.0] +=
                    weight * lambda[k] * self.evaluator.local(k).time_rate;
            }
        }
    }

    pub(super) fn emit_frame(&mut self, t: f64, y: &[f64]) -> Result<(), SimulationError> {
        let n = self.system.coordinate_count();
        let (q, qd) = y.split_at(n);
        let elements = self.elements.borrow();
        self.evaluator
            .solve_accelerations(&elements, t, q, qd)
            .map_err(|error| SimulationError::Evaluation { t, error })?;
        let frame = Frame {
            t,
            q,
            qd,
            qdd: self.evaluator.accelerations(),
            lambda: self.evaluator.multipliers(),
            elements: &elements,
        };
        self.observer.output(&frame);
        if self.options.record_trajectory {
            let trajectory = &mut self.trajectory;
            trajectory.times.push(t);
            trajectory.q.extend_from_slice(q);
            trajectory.qd.extend_from_slice(qd);
            trajectory.qdd.extend_from_slice(frame.qdd);
            trajectory.lambda.extend_from_slice(frame.lambda);
        }
        self.next_output += 1;
        drop(elements);
        self.track_drift(t, y);
        Ok(())
    }

    pub(super) fn track_drift(&mut self, t: f64, y: &[f64]) {
        let (q, qd) = y.split_at(self.system.coordinate_count());
        let (position, velocity) = match self.equations.drifting() {
            None => self.system.violation(t, q, qd),
            Some(equations) => self
                .system
                .violation_of(equations.iter().copied(), t, q, qd),
        };
        self.peak_kinetic = self.peak_kinetic.max(self.system.kinetic_energy(qd));
        self.drift.position = self.drift.position.max(position);
        self.drift.velocity = self.drift.velocity.max(velocity);
    }

    pub(super) fn potentials(&self, t: f64, q: &[f64]) -> Vec<Option<f64>> {
        self.elements
            .borrow()
            .iter()
            .map(|e| e.potential_energy(t, q))
            .collect()
    }

    pub(super) fn energy_audit(
        &self,
        initial: &State,
        last: &State,
        initial_potential: &[Option<f64>],
    ) -> EnergyAudit {
        let final_potential = self.potentials(last.t, &last.q);
        let elements = self.elements.borrow();
        let mut audit = EnergyAudit {
            initial_kinetic: self.system.kinetic_energy(&initial.qd),
            final_kinetic: self.system.kinetic_energy(&last.qd),
            peak_kinetic: self.peak_kinetic,
            ..EnergyAudit::default()
        };
        for (k, element) in elements.iter().enumerate() {
            let work = match (
                initial_potential.get(k).copied().flatten(),
                final_potential[k],
            ) {
                (Some(v0), Some(v1)) => {
                    audit.potential.push((element.name().to_string(), v0, v1));
                    v0 - v1
                }
                _ => self.element_work[k],
            };
            audit.element_work.push((element.name().to_string(), work));
        }
        audit.driver_work = self
            .system
            .driver_names()
            .iter()
            .cloned()
            .zip(self.driver_work.iter().copied())
            .collect();
        let total_work: f64 = audit
            .element_work
            .iter()
            .chain(&audit.driver_work)
            .map(|(_, w)| w)
            .sum();
        audit.residual = audit.final_kinetic - audit.initial_kinetic - total_work;
        audit
    }
}
