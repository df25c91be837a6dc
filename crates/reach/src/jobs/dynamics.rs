//! The `dynamics` workflow: inverse-dynamics torques, gravity torques and the joint-space mass
//! matrix at one state, from the rigid-body model of [`crate::effort::dynamics`] (recursive
//! Newton–Euler; ideal joints, no friction or rotor inertia).
//!
//! Rates and accelerations are typed in the unit of the positions: degrees per second (per
//! second squared) for revolute joints when `q` is in degrees, radians otherwise, metres per
//! second (squared) for prismatic joints. The report is in SI, with the unit in each field name
//! where one unit fits every joint, and `_si` (N·m revolute / N prismatic) where it does not.

use nalgebra::DMatrix;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::input::{Joints, dense_rows, joints_outside_limits};
use crate::Robot;
use crate::effort::dynamics::Dynamics;
use crate::error::Result;

/// Rigid-body dynamics at one state (`reach dynamics`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DynamicsRequest {
    /// Joint positions.
    pub q: Joints,
    /// Joint rates in the unit of `q` per second (deg/s or rad/s; m/s prismatic); zero when
    /// absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub qd: Option<Joints>,
    /// Joint accelerations in the unit of `q` per second squared (deg/s² or rad/s²; m/s²
    /// prismatic); zero when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub qdd: Option<Joints>,
}

/// Torques and the mass matrix at one state (`reach dynamics --json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct DynamicsReport {
    /// Robot name.
    pub robot: String,
    /// Joint positions: revolute joints in degrees, prismatic joints in metres.
    pub q_deg: Vec<f64>,
    /// Joint positions in SI: radians, metres.
    pub q_si: Vec<f64>,
    /// Joint rates in SI: rad/s revolute, m/s prismatic.
    pub qd_si: Vec<f64>,
    /// Joint accelerations in SI: rad/s² revolute, m/s² prismatic.
    pub qdd_si: Vec<f64>,
    /// 1-based numbers of the joints outside their limits (computed regardless).
    pub outside_limits: Vec<usize>,
    /// Gravity acceleration in the world frame, m/s².
    pub gravity_m_s2: [f64; 3],
    /// Inverse dynamics `τ = M(q)·q̈ + C(q, q̇)·q̇ + g(q)`: N·m for revolute joints, N for
    /// prismatic joints.
    pub tau_si: Vec<f64>,
    /// Gravity torques `g(q)` that hold the arm still: N·m revolute, N prismatic.
    pub gravity_tau_si: Vec<f64>,
    /// The joint-space mass matrix `M(q)`, row-major n×n, SI (kg·m² between revolute joints,
    /// kg·m between a revolute and a prismatic joint, kg between prismatic joints). Symmetric.
    pub mass_matrix_si: Vec<Vec<f64>>,
}

/// Computes the dynamics at one state.
///
/// # Errors
/// [`crate::Error::Request`] for a wrong joint count or a non-finite value (fields `q`, `qd`,
/// `qdd`, naming the joint); [`crate::Error::Dynamics`] when the robot has no inertial data.
pub fn dynamics(robot: &Robot, request: &DynamicsRequest) -> Result<DynamicsReport> {
    let q = request.q.si(robot, "q")?;
    let rates = |field: &str, given: &Option<Joints>| -> Result<Vec<f64>> {
        match given {
            Some(values) => values.si(robot, field),
            None => Ok(vec![0.0; robot.dof()]),
        }
    };
    let qd = rates("qd", &request.qd)?;
    let qdd = rates("qdd", &request.qdd)?;
    let mut workspace = Dynamics::new(robot)?;
    let n = robot.dof();
    let mut tau = vec![0.0; n];
    workspace.inverse_dynamics_into(&q, &qd, &qdd, &mut tau)?;
    let mut gravity_tau = vec![0.0; n];
    workspace.gravity_torques_into(&q, &mut gravity_tau)?;
    let mut m = DMatrix::zeros(n, n);
    workspace.mass_matrix_into(&q, &mut m)?;
    let g = robot.gravity();
    Ok(DynamicsReport {
        robot: robot.name().to_string(),
        q_deg: request.q.display(robot),
        outside_limits: joints_outside_limits(robot, &q),
        q_si: q,
        qd_si: qd,
        qdd_si: qdd,
        gravity_m_s2: [g.x, g.y, g.z],
        tau_si: tau,
        gravity_tau_si: gravity_tau,
        mass_matrix_si: dense_rows(&m),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;

    fn request(q: Vec<f64>, qd: Option<Vec<f64>>, qdd: Option<Vec<f64>>) -> DynamicsRequest {
        DynamicsRequest { q: Joints::Deg(q), qd: qd.map(Joints::Deg), qdd: qdd.map(Joints::Deg) }
    }

    /// Degrees per second are converted like degrees: the report equals the library's call in
    /// radians, and τ = M·q̈ + g at rest.
    #[test]
    fn rates_in_degrees_are_converted_and_tau_is_m_qdd_plus_g_at_rest() {
        let puma = presets::get("puma560").unwrap();
        let qdd_deg = vec![10.0, -20.0, 30.0, 5.0, -5.0, 40.0];
        let r = dynamics(&puma, &request(vec![0.0, 45.0, -90.0, 0.0, 30.0, 0.0], None, Some(qdd_deg.clone()))).unwrap();
        let qdd: Vec<f64> = qdd_deg.iter().map(|v| v.to_radians()).collect();
        assert_eq!(r.qdd_si, qdd);
        for i in 0..6 {
            let m_qdd: f64 = (0..6).map(|j| r.mass_matrix_si[i][j] * qdd[j]).sum();
            assert!((r.tau_si[i] - m_qdd - r.gravity_tau_si[i]).abs() < 1e-9, "joint {}", i + 1);
        }
        let direct = crate::effort::dynamics::inverse_dynamics(&puma, &r.q_si, &[0.0; 6], &qdd).unwrap();
        assert_eq!(r.tau_si, direct);
    }

    #[test]
    fn bad_input_names_the_field() {
        let puma = presets::get("puma560").unwrap();
        let short = dynamics(&puma, &request(vec![0.0; 6], Some(vec![0.0; 5]), None)).unwrap_err().to_string();
        assert!(short.contains("qd") && short.contains("got 5"), "{short}");
        let nan = dynamics(&puma, &request(vec![0.0; 6], None, Some(vec![0.0, f64::NAN, 0.0, 0.0, 0.0, 0.0])))
            .unwrap_err()
            .to_string();
        assert!(nan.contains("qdd: joint 2"), "{nan}");
        let planar = presets::get("planar3").unwrap();
        assert!(!planar.has_dynamics());
        let none = dynamics(&planar, &request(vec![0.0; 3], None, None)).unwrap_err().to_string();
        assert!(none.contains("no inertial data"), "{none}");
    }
}
