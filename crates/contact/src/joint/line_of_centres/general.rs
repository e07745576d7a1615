//! The general kernel: any surface profiles, with the force derived from a potential.
//!
//! On a worn (non-round) surface the penetration `δ(q) = |e| − R_i(φ − θ_i) + R_j(φ − θ_j)`
//! and the stiffness `K(q)` depend on both bodies' coordinates through the contact direction
//! `φ` and the body angles. A force pushed along the line of centres is then not the gradient
//! of anything, and an orbiting pin pumps energy into the mechanism. Here the elastic force is
//! `Q = −∇V` with `V = K(q) W(δ(q))`, `W = V/K` (for Hertz `δⁿ⁺¹/(n + 1)`):
//!
//! `Q = −F_e ∇δ − W ∇K`, with `∇δ = m·∂e/∂q + R_i' ∂θ_i/∂q − R_j' ∂θ_j/∂q`,
//! `m = n − ((R_i' − R_j')/|e|) t`.
//!
//! So the pin gets the force `−F m` at its centre and the pure torque `+F R_j'`; the bearing
//! `+F m` and `−F R_i'`; the `∇K` term adds a small force along `t` and torques of the same
//! kind. The damped law uses the same rate `δ̇ = ∇δ·q̇`, and its whole force `F_n` replaces `F_e`
//! along `∇δ` (the `∇K` term goes with it when the clamp switches the contact off), so damping
//! dissipates `(F_n − F_e) δ̇ ≥ 0` and an elastic law conserves energy exactly.
//!
//! Friction acts along the contact tangent `t̂ = m̂` turned by +90°, with the load `F_n |m|` (the
//! magnitude of the normal force), at the material contact points `r^c + R n` of the two
//! bodies, so its power on the material sliding velocity is what it dissipates. For round
//! surfaces every extra term vanishes (`m = n`), and the result is the round kernel's.
//!
//! The exact Jacobian follows the same chain; it needs the profiles' curvature `R''`.

use nalgebra::{Vector2, Vector3};

use super::{
    ArmPartials, COL_THETA_I, COL_THETA_J, COL_VEL_I, COL_VEL_J, Loads, PositionPartials, Row,
    Rows2, diagnostics, moment_partials, perp, rotate_columns,
};
use crate::friction::{FrictionForce, FrictionLaw};
use crate::joint::pair::ContactPair;
use crate::joint::types::{
    ContactForces, ContactJacobian, Geometry, JointKinematics, JointState, SlidingVelocity,
};
use crate::normal::{NormalForce, NormalLaw};
use crate::surface::SurfaceProfile;

/// Every intermediate value of one evaluation, kept for the Jacobian.
pub(super) struct GeneralValues {
    pub(super) forces: ContactForces,
    kappa: f64,
    m: Vector2<f64>,
    m_norm: f64,
    m_hat: Vector2<f64>,
    t_hat: Vector2<f64>,
    phi_rate: f64,
    normal: NormalForce,
    bearing_stiffness_slope: f64,
    pin_stiffness_slope: f64,
    energy_per_stiffness: f64,
    slope_term: f64,
    h: f64,
    g_e: Vector2<f64>,
    friction: FrictionForce,
}

impl<B: SurfaceProfile, P: SurfaceProfile, N: NormalLaw, F: FrictionLaw> ContactPair<B, P, N, F> {
    /// Forces of a penetrating contact on any surfaces (see the module docs).
    pub(super) fn general_values(
        &self,
        geometry: &Geometry,
        kin: &JointKinematics,
        at: JointState,
    ) -> GeneralValues {
        let (bearing_body, pin_body) = (at.bearing, at.pin);
        let n = kin.normal;
        let t = kin.tangent;
        let rho = kin.eccentricity_norm;
        let (r_i, r_j) = (kin.bearing.radius, kin.pin.radius);
        let (s_i, s_j) = (kin.bearing.slope, kin.pin.slope);
        let e_rate = kin.eccentricity_rate;
        let phi_rate = t.dot(&e_rate) / rho;

        let kappa = (s_i - s_j) / rho;
        let m = n - t * kappa;
        let m_norm = m.norm();
        let m_hat = m / m_norm;
        let t_hat = perp(&m_hat);
        let delta_rate = m.dot(&e_rate) + s_i * bearing_body.omega - s_j * pin_body.omega;

        let stiffness = self.stiffness(r_i, r_j);
        let onset = at.onset_velocity.unwrap_or(delta_rate);
        let normal = self
            .normal_law
            .evaluate(stiffness, kin.penetration, delta_rate, onset);
        // ∂K/∂R_i and ∂K/∂R_j of K = κ √(R_i R_j/(R_i − R_j)).
        let clearance = r_i - r_j;
        let k_i = -stiffness * r_j / (2.0 * r_i * clearance);
        let k_j = stiffness * r_i / (2.0 * r_j * clearance);
        let active = normal.force > 0.0;
        let w = if active {
            normal.potential / stiffness
        } else {
            0.0
        };
        let slope_term = k_i * s_i + k_j * s_j;
        let h = w * slope_term / rho;
        // Gradient coefficients of F_n δ + W K: along e, and on θ_i, θ_j directly.
        let g_e = m * normal.force + t * h;
        let g_i = (normal.force - w * k_i) * s_i;
        let g_j = -(normal.force + w * k_j) * s_j;

        let load = normal.force * m_norm;
        let relative_velocity = kin.relative_velocity();
        let material_sliding = relative_velocity.dot(&t_hat);
        let sliding = match self.friction_sliding {
            SlidingVelocity::Material => material_sliding,
            SlidingVelocity::Paper => kin.penetration * phi_rate,
        };
        let friction = self.friction_law.evaluate(sliding, load);
        let friction_on_pin = -t_hat * friction.force;

        let bearing_centre_arm = geometry.bearing_centre_arm;
        let pin_centre_arm = geometry.pin_centre_arm;
        let pin_arm = kin.pin_point - pin_body.position();
        let bearing_arm = kin.bearing_point - bearing_body.position();
        let pin_force = friction_on_pin - g_e;
        let pin_moment =
            super::cross(&pin_centre_arm, &-g_e) - g_j + super::cross(&pin_arm, &friction_on_pin);
        let bearing_force = g_e - friction_on_pin;
        let bearing_moment = super::cross(&bearing_centre_arm, &g_e) - g_i
            + super::cross(&bearing_arm, &-friction_on_pin);

        // Stored energy released without work where the clamp switches the contact off.
        let stiffness_rate =
            k_i * s_i * (phi_rate - bearing_body.omega) + k_j * s_j * (phi_rate - pin_body.omega);
        let released = if active {
            0.0
        } else {
            normal.potential / stiffness * stiffness_rate
        };
        let loads = Loads {
            normal_velocity: delta_rate,
            tangential_velocity: material_sliding,
            geometric_sliding_velocity: kin.penetration * phi_rate,
            normal_force: load,
            elastic_force: normal.elastic * m_norm,
            friction_force: friction.force,
            elastic_energy: normal.potential,
            damping_power: (normal.force - normal.elastic) * delta_rate - released,
            friction_power: friction.force * material_sliding,
        };
        GeneralValues {
            forces: ContactForces {
                bearing: Vector3::new(bearing_force.x, bearing_force.y, bearing_moment),
                pin: Vector3::new(pin_force.x, pin_force.y, pin_moment),
                diagnostics: diagnostics(kin, bearing_body, pin_body, &loads),
            },
            kappa,
            m,
            m_norm,
            m_hat,
            t_hat,
            phi_rate,
            normal,
            bearing_stiffness_slope: k_i,
            pin_stiffness_slope: k_j,
            energy_per_stiffness: w,
            slope_term,
            h,
            g_e,
            friction,
        }
    }

    /// [`general_values`](Self::general_values) and the exact 6×12 Jacobian.
    pub(super) fn general_forces_and_jacobian(
        &self,
        geometry: &Geometry,
        kin: &JointKinematics,
        at: JointState,
    ) -> (ContactForces, ContactJacobian) {
        let v = self.general_values(geometry, kin, at);
        let n = kin.normal;
        let t = kin.tangent;
        let rho = kin.eccentricity_norm;
        let (r_i, r_j) = (kin.bearing.radius, kin.pin.radius);
        let (s_i, s_j) = (kin.bearing.slope, kin.pin.slope);
        let (c_i, c_j) = (kin.bearing.curvature, kin.pin.curvature);
        let (omega_i, omega_j) = (at.bearing.omega, at.pin.omega);
        let e_rate = kin.eccentricity_rate;
        let unit = |column: usize| {
            let mut row = Row::zeros();
            row[column] = 1.0;
            row
        };

        // Positions: |e|, φ, the local radii and their slopes.
        let p = PositionPartials::new(geometry);
        let (d_rho, d_phi) = (p.d_rho, p.d_phi);
        let (d_r_i, d_r_j) = (p.d_bearing_radius, p.d_pin_radius);
        let d_s_i = (d_phi - unit(COL_THETA_I)) * c_i;
        let d_s_j = (d_phi - unit(COL_THETA_J)) * c_j;
        let d_delta = d_rho - d_r_i + d_r_j;

        // m = n − κ t and the contact frame (m̂, t̂).
        let d_kappa = (d_s_i - d_s_j) / rho - d_rho * (v.kappa / rho);
        let d_m: Rows2 = t * (d_phi - d_kappa) + n * (d_phi * v.kappa);
        let d_m_norm: Row = v.m_hat.transpose() * d_m;
        let d_m_hat: Rows2 = (d_m - v.m_hat * d_m_norm) / v.m_norm;
        let d_t_hat = rotate_columns(&d_m_hat);

        // ė and δ̇ = m·ė + R_i' ω_i − R_j' ω_j.
        let mut d_e_rate = Rows2::zeros();
        d_e_rate.set_column(COL_THETA_I, &(geometry.bearing_centre_arm * omega_i));
        d_e_rate.set_column(COL_THETA_J, &(-geometry.pin_centre_arm * omega_j));
        d_e_rate[(0, COL_VEL_I)] = -1.0;
        d_e_rate[(1, COL_VEL_I + 1)] = -1.0;
        d_e_rate.set_column(COL_VEL_I + 2, &-perp(&geometry.bearing_centre_arm));
        d_e_rate[(0, COL_VEL_J)] = 1.0;
        d_e_rate[(1, COL_VEL_J + 1)] = 1.0;
        d_e_rate.set_column(COL_VEL_J + 2, &perp(&geometry.pin_centre_arm));
        let d_delta_rate: Row =
            e_rate.transpose() * d_m + v.m.transpose() * d_e_rate + d_s_i * omega_i
                - d_s_j * omega_j
                + unit(COL_VEL_I + 2) * s_i
                - unit(COL_VEL_J + 2) * s_j;

        // The normal law and the ∇K term.
        let (stiffness, d_stiffness) = self.stiffness_partials(kin, &p);
        let normal = v.normal;
        let d_force = d_delta * normal.d_penetration
            + d_delta_rate * normal.d_velocity
            + d_stiffness * normal.d_stiffness;
        let (k_i, k_j, w) = (
            v.bearing_stiffness_slope,
            v.pin_stiffness_slope,
            v.energy_per_stiffness,
        );
        let d_w = if w > 0.0 {
            d_delta * (normal.elastic / stiffness)
        } else {
            Row::zeros()
        };
        let d_clearance = d_r_i - d_r_j;
        let clearance = r_i - r_j;
        let d_log_k = d_stiffness / stiffness - d_clearance / clearance;
        let d_k_i = (d_log_k + d_r_j / r_j - d_r_i / r_i) * k_i;
        let d_k_j = (d_log_k + d_r_i / r_i - d_r_j / r_j) * k_j;
        let d_slope_term = d_k_i * s_i + d_s_i * k_i + d_k_j * s_j + d_s_j * k_j;
        let d_h = (d_w * v.slope_term + d_slope_term * w) / rho - d_rho * (v.h / rho);
        let d_g_e: Rows2 = v.m * d_force + d_m * normal.force + t * d_h - n * (d_phi * v.h);
        let d_g_i = (d_force - d_w * k_i - d_k_i * w) * s_i + d_s_i * (normal.force - w * k_i);
        let d_g_j = -((d_force + d_w * k_j + d_k_j * w) * s_j) - d_s_j * (normal.force + w * k_j);

        // Friction along t̂ under the load F_n |m|.
        let arms = ArmPartials::new(geometry, kin, at.bearing, at.pin, &p);
        let d_load = d_force * v.m_norm + d_m_norm * normal.force;
        let d_sliding: Row = match self.friction_sliding {
            SlidingVelocity::Material => {
                v.t_hat.transpose() * arms.d_relative_velocity
                    + kin.relative_velocity().transpose() * d_t_hat
            }
            SlidingVelocity::Paper => {
                let d_phi_rate = (t.transpose() * d_e_rate - d_phi * n.dot(&e_rate)) / rho
                    - d_rho * (v.phi_rate / rho);
                d_delta * v.phi_rate + d_phi_rate * kin.penetration
            }
        };
        let d_friction = d_sliding * v.friction.d_velocity + d_load * v.friction.d_normal_force;
        let friction_on_pin = -v.t_hat * v.friction.force;
        let d_friction_on_pin: Rows2 = -(v.t_hat * d_friction + d_t_hat * v.friction.force);

        // Assemble: normal part at the centres plus torques, friction at the contact points.
        let centre_arm_partials = |arm: &Vector2<f64>, column: usize| {
            let mut d = Rows2::zeros();
            d.set_column(column, &perp(arm));
            d
        };
        let d_pin_centre_arm = centre_arm_partials(&geometry.pin_centre_arm, COL_THETA_J);
        let d_bearing_centre_arm = centre_arm_partials(&geometry.bearing_centre_arm, COL_THETA_I);
        let d_pin_force = d_friction_on_pin - d_g_e;
        let d_pin_moment = moment_partials(
            &geometry.pin_centre_arm,
            &d_pin_centre_arm,
            &-v.g_e,
            &-d_g_e,
        ) - d_g_j
            + moment_partials(
                &arms.pin_arm,
                &arms.d_pin_arm,
                &friction_on_pin,
                &d_friction_on_pin,
            );
        let d_bearing_moment = moment_partials(
            &geometry.bearing_centre_arm,
            &d_bearing_centre_arm,
            &v.g_e,
            &d_g_e,
        ) - d_g_i
            + moment_partials(
                &arms.bearing_arm,
                &arms.d_bearing_arm,
                &-friction_on_pin,
                &-d_friction_on_pin,
            );

        let mut jacobian = ContactJacobian::zeros();
        jacobian.fixed_rows_mut::<2>(0).copy_from(&-d_pin_force);
        jacobian.set_row(2, &d_bearing_moment);
        jacobian.fixed_rows_mut::<2>(3).copy_from(&d_pin_force);
        jacobian.set_row(5, &d_pin_moment);
        (v.forces, jacobian)
    }
}
