//! The planar geometry shared with the yaw solvers: a chain of parallel revolute axes, the
//! planar two-link IK and the feasible intervals of the last link's angle `φ`.

use std::f64::consts::{PI, TAU};

use nalgebra::{Rotation3, Vector3};

use crate::ik::SingularityKind;
use crate::model::chain::ChainLink;
use crate::tolerance::{BOUNDARY, IK_AXIS_DISTANCE, IK_DUPLICATE, STRUCTURE_ANGLE, STRUCTURE_LENGTH};

/// One link of a chain of joints whose axes are parallel to z of the frame they start in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PlanarLink {
    /// Distance from this joint's axis to the next joint's axis (or to the tool point).
    pub length: f64,
    /// Direction of the link in the frame turned by the joint (DH: 0; MDH/URDF offsets).
    pub delta: f64,
    /// Rotation about z from the frame turned by the joint to the next joint's motion frame.
    pub psi: f64,
    /// −1 for a flipped joint, +1 otherwise: the physical angle is `sign·q`.
    pub sign: f64,
}

/// A chain of `N` revolute joints with parallel axes, read from the compiled chain.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PlanarChain<const N: usize> {
    pub links: [PlanarLink; N],
    /// Offset of the tool point along the common axis (sum of the offsets along z).
    pub height: f64,
    /// Rotation of the last fixed transform (tool included), after the last joint's motion.
    pub last_rotation: Rotation3<f64>,
}

impl<const N: usize> PlanarChain<N> {
    /// Reads `links` (the compiled chain's joints `first_joint ..= first_joint + N − 1`,
    /// 1-based numbers for messages). Fails with the violated condition.
    pub fn from_chain(links: &[ChainLink], first_joint: usize) -> Result<Self, String> {
        if links.len() != N {
            return Err(format!("expected {N} planar joints, got {}", links.len()));
        }
        let mut out = [PlanarLink { length: 0.0, delta: 0.0, psi: 0.0, sign: 1.0 }; N];
        let mut height = 0.0;
        let mut last_rotation = Rotation3::identity();
        for (i, link) in links.iter().enumerate() {
            let number = first_joint + i;
            if link.prismatic {
                return Err(format!("joint {number} is prismatic (a revolute joint is needed)"));
            }
            let r = link.after.rotation;
            let p = link.after.translation.vector;
            let length = p.x.hypot(p.y);
            out[i] = PlanarLink {
                length,
                delta: if length > STRUCTURE_LENGTH { p.y.atan2(p.x) } else { 0.0 },
                psi: 0.0,
                sign: link.sign,
            };
            height += p.z;
            if i + 1 < N {
                let z = r * Vector3::z();
                if (z - Vector3::z()).norm() > STRUCTURE_ANGLE {
                    let angle = z.z.clamp(-1.0, 1.0).acos().to_degrees();
                    return Err(if (z + Vector3::z()).norm() <= STRUCTURE_ANGLE {
                        format!("joint {} axis is antiparallel to joint {number} axis (not supported)", number + 1)
                    } else {
                        format!("joint {} axis is not parallel to joint {number} axis (angle {angle:.6}°)", number + 1)
                    });
                }
                out[i].psi = r[(1, 0)].atan2(r[(0, 0)]);
            } else {
                last_rotation = r;
            }
        }
        Ok(PlanarChain { links: out, height, last_rotation })
    }

    /// Link lengths.
    pub fn lengths(&self) -> [f64; N] {
        self.links.map(|l| l.length)
    }

    /// Absolute link angles `φ` (in the frame the first joint turns in) of joint values `q`.
    pub fn link_angles(&self, q: &[f64]) -> [f64; N] {
        let mut phi = [0.0; N];
        let mut acc = 0.0;
        for (i, (link, &v)) in self.links.iter().zip(q).enumerate() {
            let theta = link.sign * v;
            phi[i] = acc + theta + link.delta;
            acc += theta + link.psi;
        }
        phi
    }

    /// Joint values (unwrapped) that give the absolute link angles `phi`.
    pub fn joints(&self, phi: &[f64; N]) -> [f64; N] {
        let mut q = [0.0; N];
        let mut acc = 0.0;
        for (i, link) in self.links.iter().enumerate() {
            let theta = phi[i] - link.delta - acc;
            q[i] = link.sign * theta;
            acc += theta + link.psi;
        }
        q
    }

    /// Absolute angle of the last link when the last joint's frame is turned by `heading`
    /// about z (`φ_N = Θ + δ_N`).
    pub fn heading_to_last_angle(&self, heading: f64) -> f64 {
        heading + self.links[N - 1].delta
    }
}

/// One solution of a planar two-link problem.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Elbow {
    /// Absolute angles of the two links.
    pub phi: [f64; 2],
    /// Relative angle of link 2 to link 1 (`φ2 − φ1`), in [−π, π].
    pub bend: f64,
    /// Singularity of this solution (stretched/folded elbow, or wrist on the shoulder axis).
    pub singular: Option<SingularityKind>,
}

/// Result of a planar two-link IK.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum TwoLink {
    /// The point is outside the annulus `|l1 − l2| ≤ r ≤ l1 + l2`.
    Out { distance: f64, reach: f64 },
    /// One (singular) or two solutions.
    In([Option<Elbow>; 2]),
}

/// Planar two-link IK: links `l1, l2` from the origin to the point `w`. `seed_phi1` is the
/// first link's angle used when it is undetermined (`w` on the shoulder axis, `l1 = l2`).
pub(crate) fn two_link(l1: f64, l2: f64, w: [f64; 2], seed_phi1: f64) -> TwoLink {
    let r2 = w[0] * w[0] + w[1] * w[1];
    let r = r2.sqrt();
    let c = (r2 - l1 * l1 - l2 * l2) / (2.0 * l1 * l2);
    if c > 1.0 + BOUNDARY {
        return TwoLink::Out { distance: r, reach: l1 + l2 };
    }
    if c < -1.0 - BOUNDARY {
        return TwoLink::Out { distance: r, reach: (l1 - l2).abs() };
    }
    if r <= IK_AXIS_DISTANCE {
        // Folded with l1 = l2: the wrist is on the shoulder axis and φ1 is free.
        let e = Elbow { phi: [seed_phi1, seed_phi1 + PI], bend: PI, singular: Some(SingularityKind::Shoulder) };
        return TwoLink::In([Some(e), None]);
    }
    let base = w[1].atan2(w[0]);
    let solve = |bend: f64, singular: Option<SingularityKind>| {
        let phi1 = base - (l2 * bend.sin()).atan2(l1 + l2 * bend.cos());
        Elbow { phi: [phi1, phi1 + bend], bend, singular }
    };
    // Bend angle by the half-angle form tan²(e/2) = ((l1+l2)² − r²)/(r² − (l1−l2)²): full
    // precision near 0 and π, where acos(c) keeps only half the digits (an exactly stretched
    // or folded arm gives e = 0 or π and one solution).
    let (sum, diff) = (l1 + l2, (l1 - l2).abs());
    let e = 2.0 * ((sum - r) * (sum + r)).max(0.0).sqrt().atan2(((r - diff) * (r + diff)).max(0.0).sqrt());
    let singular = (c.abs() >= 1.0 - BOUNDARY).then_some(SingularityKind::Elbow);
    // Branches closer than IK_DUPLICATE are one solution (`finish` would merge them): report
    // it exactly stretched or folded. (Not for a folded equal-link arm: there the snap would
    // move the wrist by |w| onto the shoulder axis.)
    if e <= IK_DUPLICATE / 2.0 {
        return TwoLink::In([Some(solve(0.0, singular)), None]);
    }
    if PI - e <= IK_DUPLICATE / 2.0 && diff > STRUCTURE_LENGTH {
        return TwoLink::In([Some(solve(PI, singular)), None]);
    }
    TwoLink::In([Some(solve(-e, singular)), Some(solve(e, singular))])
}

/// A closed interval of the redundancy parameter `φ` (radians, `start ≤ end`; the values are
/// not wrapped, an interval may cross ±π).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhiInterval {
    /// Lower end.
    pub start: f64,
    /// Upper end.
    pub end: f64,
}

impl PhiInterval {
    /// Width, radians.
    #[must_use]
    pub fn width(&self) -> f64 {
        self.end - self.start
    }
}

/// The angles `φ` of the last link (length `l3`) for which a two-link arm `l1, l2` at the
/// origin reaches the wrist `p − l3·(cos φ, sin φ)`: at most two intervals, or one full turn.
pub(crate) fn phi_intervals(l1: f64, l2: f64, l3: f64, p: [f64; 2]) -> Vec<PhiInterval> {
    let r = p[0].hypot(p[1]);
    let (outer, inner) = (l1 + l2, (l1 - l2).abs());
    let inside = |d: f64| d <= outer * (1.0 + BOUNDARY) && d >= inner * (1.0 - BOUNDARY);
    let psi = p[1].atan2(p[0]);
    let full = vec![PhiInterval { start: psi - PI, end: psi + PI }];
    if l3 <= STRUCTURE_LENGTH {
        return if inside(r) { full } else { Vec::new() };
    }
    if r <= IK_AXIS_DISTANCE {
        return if inside(l3) { full } else { Vec::new() };
    }
    // |W|² = r² + l3² − 2·r·l3·cos ω, ω = φ − ψ; inner² ≤ |W|² ≤ outer².
    let c_lo = (r * r + l3 * l3 - outer * outer) / (2.0 * r * l3);
    let c_hi = (r * r + l3 * l3 - inner * inner) / (2.0 * r * l3);
    if c_lo > 1.0 + BOUNDARY || c_hi < -1.0 - BOUNDARY {
        return Vec::new();
    }
    let w_max = c_lo.clamp(-1.0, 1.0).acos();
    let w_min = c_hi.clamp(-1.0, 1.0).acos();
    if w_min > w_max {
        return Vec::new();
    }
    match (w_min <= 0.0, w_max >= PI) {
        (true, true) => full,
        (true, false) => vec![PhiInterval { start: psi - w_max, end: psi + w_max }],
        (false, true) => vec![PhiInterval { start: psi + w_min, end: psi + TAU - w_min }],
        (false, false) => vec![
            PhiInterval { start: psi - w_max, end: psi - w_min },
            PhiInterval { start: psi + w_min, end: psi + w_max },
        ],
    }
}

/// Sample values of `intervals`, spaced at most `step`, both ends included (a full turn
/// without repeating its end).
pub(crate) fn sample_intervals(intervals: &[PhiInterval], step: f64) -> Vec<f64> {
    let mut out = Vec::new();
    for iv in intervals {
        let width = iv.width();
        let full_turn = width >= TAU * (1.0 - BOUNDARY);
        // Bounded by MAX_SELF_MOTION_SAMPLES through `check_options`.
        let n = (width / step).ceil().max(0.0) as usize;
        if n == 0 {
            out.push(iv.start);
            continue;
        }
        let last = if full_turn { n - 1 } else { n };
        out.extend((0..=last).map(|k| iv.start + width * (k as f64) / (n as f64)));
    }
    out
}
