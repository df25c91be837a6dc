//! Seed 000's angle conventions and their conversion to DH joint angles.
//!
//! The thesis describes the planar three-link arm (`planar3`) by **interior** angles, all
//! in [0°, 180°] (notes 000 §2):
//!
//! * `γ` — absolute angle of link 1 (OB) from the +x axis;
//! * `β` — interior angle at joint B between links BO and BA;
//! * `α` — interior angle at joint A between links AB and AK.
//!
//! Interior angles ≤ 180° make the chain always bend clockwise. The standard-DH joint angles
//! of the `planar3` preset (relative angles, counter-clockwise positive) are
//!
//! ```text
//! q1 = γ,   q2 = β − 180°,   q3 = α − 180°          (so q2, q3 ∈ [−180°, 0°])
//! γ = q1,   β = q2 + 180°,   α = q3 + 180°
//! ```
//!
//! and the absolute link directions are `φ1 = γ`, `φ2 = γ + β − 180°`,
//! `φ3 = γ + β + α − 360°`.
//!
//! The appendix paper (P2011, `log-loader` preset) names the angles differently: `α` is the
//! base rotation about the vertical, `γ` the elevation of link A, `β` the interior angle
//! between links A and B. There `q1 = α`, `q2 = γ`, `q3 = β − 180°` (elbow bent downwards).

use std::f64::consts::PI;

/// The thesis's angles of the planar arm, radians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanarPaperAngles {
    /// Interior angle at joint A (between links AB and AK).
    pub alpha: f64,
    /// Interior angle at joint B (between links BO and BA).
    pub beta: f64,
    /// Absolute angle of link OB from +x.
    pub gamma: f64,
}

impl PlanarPaperAngles {
    /// DH joint angles `[q1, q2, q3]` of the `planar3` preset.
    #[must_use]
    pub fn to_joints(self) -> [f64; 3] {
        [self.gamma, self.beta - PI, self.alpha - PI]
    }

    /// The paper's angles from DH joint angles `[q1, q2, q3]`.
    #[must_use]
    pub fn from_joints(q: [f64; 3]) -> Self {
        PlanarPaperAngles { gamma: q[0], beta: q[1] + PI, alpha: q[2] + PI }
    }
}

/// The appendix paper's angles of the log loader (`log-loader` preset), radians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LogLoaderPaperAngles {
    /// Base rotation about the vertical axis.
    pub alpha: f64,
    /// Interior angle between links A and B.
    pub beta: f64,
    /// Elevation of link A above the horizontal plane.
    pub gamma: f64,
}

impl LogLoaderPaperAngles {
    /// DH joint angles `[q1, q2, q3]` of the `log-loader` preset.
    #[must_use]
    pub fn to_joints(self) -> [f64; 3] {
        [self.alpha, self.gamma, self.beta - PI]
    }

    /// The paper's angles from DH joint angles.
    #[must_use]
    pub fn from_joints(q: [f64; 3]) -> Self {
        LogLoaderPaperAngles { alpha: q[0], gamma: q[1], beta: q[2] + PI }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conversions_round_trip() {
        let p = PlanarPaperAngles { alpha: 1.0, beta: 2.0, gamma: 0.5 };
        assert_eq!(PlanarPaperAngles::from_joints(p.to_joints()), p);
        let l = LogLoaderPaperAngles { alpha: -0.3, beta: 2.5, gamma: 0.7 };
        let back = LogLoaderPaperAngles::from_joints(l.to_joints());
        assert!((back.beta - l.beta).abs() < 1e-15 && back.alpha == l.alpha && back.gamma == l.gamma);
    }
}
