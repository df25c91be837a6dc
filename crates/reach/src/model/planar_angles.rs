//! Interior-angle conventions of planar arms and their conversion to DH joint angles.
//!
//! These are the conventions of seed 000 (notes 000 §2). The thesis describes the planar three-link arm (`planar3`) by **interior** angles, all
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

/// Interior angles of the planar three-link arm, radians: the convention of seed 000
/// (notes 000 §2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InteriorAngles {
    /// Interior angle at joint A (between links AB and AK).
    pub alpha: f64,
    /// Interior angle at joint B (between links BO and BA).
    pub beta: f64,
    /// Absolute angle of link OB from +x.
    pub gamma: f64,
}

impl InteriorAngles {
    /// DH joint angles `[q1, q2, q3]` of the `planar3` preset.
    #[must_use]
    pub fn to_joints(self) -> [f64; 3] {
        [self.gamma, self.beta - PI, self.alpha - PI]
    }

    /// The interior angles from DH joint angles `[q1, q2, q3]` of the `planar3` preset.
    #[must_use]
    pub fn from_joints(q: [f64; 3]) -> Self {
        InteriorAngles { gamma: q[0], beta: q[1] + PI, alpha: q[2] + PI }
    }

    /// The interior angles from the absolute link angles `φ = [φ1, φ2, φ3]` (from +x, the
    /// arm's plane), valid for any DH table of the arm (notes 000 §2): `γ = φ1`,
    /// `β = φ2 − φ1 + 180°`, `α = φ3 − φ2 + 180°`.
    #[must_use]
    pub fn from_link_angles(phi: [f64; 3]) -> Self {
        InteriorAngles { gamma: phi[0], beta: phi[1] - phi[0] + PI, alpha: phi[2] - phi[1] + PI }
    }
}

/// Angles of the log loader (`log-loader` preset), radians, as seed 000's appendix paper
/// (P2011) names them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LogLoaderAngles {
    /// Base rotation about the vertical axis.
    pub alpha: f64,
    /// Interior angle between links A and B.
    pub beta: f64,
    /// Elevation of link A above the horizontal plane.
    pub gamma: f64,
}

impl LogLoaderAngles {
    /// DH joint angles `[q1, q2, q3]` of the `log-loader` preset.
    #[must_use]
    pub fn to_joints(self) -> [f64; 3] {
        [self.alpha, self.gamma, self.beta - PI]
    }

    /// The log loader's angles from DH joint angles.
    #[must_use]
    pub fn from_joints(q: [f64; 3]) -> Self {
        LogLoaderAngles { alpha: q[0], gamma: q[1], beta: q[2] + PI }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conversions_round_trip() {
        let p = InteriorAngles { alpha: 1.0, beta: 2.0, gamma: 0.5 };
        assert_eq!(InteriorAngles::from_joints(p.to_joints()), p);
        // planar3's links point at φ = (q1, q1 + q2, q1 + q2 + q3).
        let q = [0.4, -1.1, -0.7];
        let by_links = InteriorAngles::from_link_angles([q[0], q[0] + q[1], q[0] + q[1] + q[2]]);
        let by_joints = InteriorAngles::from_joints(q);
        assert!((by_links.alpha - by_joints.alpha).abs() < 1e-15 && (by_links.beta - by_joints.beta).abs() < 1e-15);
        assert_eq!(by_links.gamma, by_joints.gamma);
        let l = LogLoaderAngles { alpha: -0.3, beta: 2.5, gamma: 0.7 };
        let back = LogLoaderAngles::from_joints(l.to_joints());
        assert!((back.beta - l.beta).abs() < 1e-15 && back.alpha == l.alpha && back.gamma == l.gamma);
    }
}
