//! The `planar_scan` workflow: seed 000's scan and minimum-change choice for a planar arm of 3
//! to 6 links ([`crate::ik::planar_scan`]; `reach ik planar4 --xyz … --scan STEP`). The table of
//! four or more links is counted, not listed.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::ik::status;
use super::input::{Joints, q_display};
use crate::Robot;
use crate::error::Result;
use crate::ik::planar_scan::{ScanOutcome, scan_min_change};

/// The scan of one tool position.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PlanarScanRequest {
    /// The tool position, metres (in the arm's plane).
    pub xyz_m: [f64; 3],
    /// The grid step of joints 3…n, degrees (> 0).
    pub step_deg: f64,
    /// The current configuration (default: home).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub from: Option<Joints>,
}

/// The minimum-change configuration (`reach ik planar4 --scan --json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct PlanarScanReport {
    /// Robot name.
    pub robot: String,
    /// The grid step of joints 3…n, degrees.
    pub step_deg: f64,
    /// The current configuration, degrees.
    pub from_q_deg: Vec<f64>,
    /// `ok`, or why there is no configuration: a code as in the `ik` report.
    pub status: String,
    /// The reason in words (`null` when the status is `ok`).
    pub reason: Option<String>,
    /// Grid nodes visited (0 when there is no configuration).
    pub nodes: usize,
    /// Configurations found (both elbows of every node whose wrist is reachable; 0 when none
    /// is within the limits).
    pub configurations: usize,
    /// Of those, within the joint limits.
    pub within_limits: usize,
    /// The chosen configuration (least `S`), degrees; `null` without one.
    pub q_deg: Option<Vec<f64>>,
    /// Its total joint change `S = Σ|Δqᵢ|` from `from`, degrees.
    pub s_deg: Option<f64>,
}

/// Scans and chooses.
///
/// # Errors
/// [`Error::Request`](crate::Error::Request) for a non-finite position, a step that is not a positive angle
/// (`step_deg`), a bad `from`; [`Error::Ik`](crate::Error::Ik) for a robot that is not a planar arm of 3 to 6
/// links, or a grid beyond the node cap.
pub fn planar_scan(robot: &Robot, request: &PlanarScanRequest) -> Result<PlanarScanReport> {
    let step = request.step_deg;
    let from = super::ik::scan_input(robot, step, &request.xyz_m, request.from.as_ref())?;
    let outcome = scan_min_change(robot, &nalgebra::Point3::from(request.xyz_m), &from, step.to_radians())?;
    let mut report = PlanarScanReport {
        robot: robot.name().to_string(),
        step_deg: step,
        from_q_deg: q_display(robot, &from),
        status: "ok".into(),
        reason: None,
        nodes: 0,
        configurations: 0,
        within_limits: 0,
        q_deg: None,
        s_deg: None,
    };
    match outcome {
        ScanOutcome::Chosen(c) => {
            report.nodes = c.nodes;
            report.configurations = c.configurations;
            report.within_limits = c.within_limits;
            report.q_deg = Some(q_display(robot, &c.q));
            report.s_deg = Some(c.s.to_degrees());
        }
        ScanOutcome::NoSolution(f) => (report.status, report.reason) = status(Some(&f)),
    }
    Ok(report)
}
