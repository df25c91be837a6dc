//! Label values of the planar branches (elbow, redundancy parameter), shared with the yaw
//! solvers.

use std::f64::consts::PI;

use super::*;

/// Label value of the elbow: `up` when link 2 turns clockwise from link 1 as seen with the arm
/// reaching to the right (`reach_sign` = −1 mirrors it), `down` otherwise, `stretched` /
/// `folded` for the single solution at the workspace boundary.
pub(crate) fn elbow_label(e: &Elbow, reach_sign: f64) -> &'static str {
    if e.bend == 0.0 {
        "stretched"
    } else if e.bend.abs() == PI {
        "folded"
    } else if reach_sign * e.bend < 0.0 {
        "up"
    } else {
        "down"
    }
}

/// Label value of the redundancy parameter, degrees.
pub(crate) fn phi_label(phi: f64) -> String {
    format!("{:.4}", crate::angle::wrap(phi).to_degrees())
}
