//! Seed 000's future work (notes 000 §8): the table scan and minimum-change choice for a planar
//! arm of **n ≥ 3** links (`planar4`).
//!
//! # Method
//!
//! The thesis steps the interior angle at the wrist, `α`, and solves the other two joints in
//! closed form (notes 000 §4.1). For `n` links a position target leaves `n − 2` free
//! parameters; the generalisation steps the **last `n − 2` joints** `q3 … qn` over their limits
//! on a grid of step `Δ` (every grid node from the lower limit up to the upper one), and for each
//! node the tail from joint 2 to the tool is a rigid vector `v` (its shape fixed by `q3 … qn`).
//! Joints 1 and 2 then form a two-link arm with links `l1` and `|v|`, solved in closed form:
//! two elbow branches per node (one at a stretched or folded elbow). Every node gives at most
//! two configurations; those within the joint limits are candidates, and the choice is the
//! thesis's: the least total joint change `S = Σ|qᵢ − q0ᵢ|` from the current configuration
//! (notes 000 §4.1 step 5; for three links `S` equals the thesis's `|Δα| + |Δβ| + |Δγ|`), the
//! first minimum in grid order winning. The table is not stored — at `Δ` = 0.1° a four-link arm
//! already has 3.2 million rows — only counted, and at most [`MAX_SCAN_NODES`] grid nodes are
//! visited.

use nalgebra::Point3;

use super::planar::{PlanarChain, TwoLink, two_link};
use super::solution::fit_revolute;
use super::{IkError, IkFailure};
use crate::model::Robot;
use crate::tolerance::{IK_POSITION, LIMIT_SLACK};

/// Most grid nodes one scan visits (each costs a two-link solution): 4 links at a step of
/// 0.18° over two 180° ranges, or 5 links at about 1.8°.
pub const MAX_SCAN_NODES: usize = 1_000_000;

/// The minimum-change configuration of a scan.
#[derive(Debug, Clone, PartialEq)]
pub struct ScanChoice {
    /// The chosen joint values, radians.
    pub q: Vec<f64>,
    /// Its total joint change `S` from the current configuration, radians.
    pub s: f64,
    /// Grid nodes visited.
    pub nodes: usize,
    /// Configurations found (two elbow branches per node where the wrist is reachable).
    pub configurations: usize,
    /// Of those, within the joint limits (the candidates).
    pub within_limits: usize,
}

/// The scan's answer: the choice, or why there is none.
#[derive(Debug, Clone, PartialEq)]
pub enum ScanOutcome {
    /// The minimum-change configuration.
    Chosen(ScanChoice),
    /// No configuration within the limits reaches the target.
    NoSolution(IkFailure),
}

/// Scans the configurations of a planar arm of 3 to 6 revolute joints with parallel axes that
/// put the tool point at `target` (world frame, metres), with joints 3…n on a grid of `step`
/// radians, and chooses the one of least total joint change from `current` (see the module
/// docs).
///
/// # Errors
/// [`IkError::Unsupported`] for a robot that is not such an arm (or has an unbounded joint
/// among 3…n); [`IkError::InvalidInput`] for a non-finite target or current configuration, a
/// step that is not positive, or a grid of more than [`MAX_SCAN_NODES`] nodes.
///
/// # Example
/// ```
/// use reach::ik::planar_scan::{ScanOutcome, scan_min_change};
/// let robot = reach::model::presets::get("planar4").unwrap();
/// let d = f64::to_radians;
/// let current = [d(60.0), d(-40.0), d(-30.0), d(-20.0)];
/// let here = robot.fk(&current).unwrap().translation.vector;
/// // The target is where the tool already is: the current configuration, S = 0.
/// let ScanOutcome::Chosen(c) = scan_min_change(&robot, &here.into(), &current, d(1.0)).unwrap() else { panic!() };
/// assert!(c.s < 1e-9);
/// ```
pub fn scan_min_change(
    robot: &Robot,
    target: &Point3<f64>,
    current: &[f64],
    step: f64,
) -> Result<ScanOutcome, IkError> {
    match robot.dof() {
        3 => scan::<3>(robot, target, current, step),
        4 => scan::<4>(robot, target, current, step),
        5 => scan::<5>(robot, target, current, step),
        6 => scan::<6>(robot, target, current, step),
        n => Err(unsupported(robot, format!("needs 3 to 6 planar joints, the robot has {n}"))),
    }
}

fn unsupported(robot: &Robot, reason: String) -> IkError {
    IkError::Unsupported { solver: "planar scan", robot: robot.name().to_string(), reason }
}

fn scan<const N: usize>(
    robot: &Robot,
    target: &Point3<f64>,
    current: &[f64],
    step: f64,
) -> Result<ScanOutcome, IkError> {
    if robot.chain.has_mimics() {
        return Err(unsupported(robot, "the chain has mimic joints".into()));
    }
    let chain = PlanarChain::<N>::from_chain(&robot.chain.links, 1).map_err(|r| unsupported(robot, r))?;
    if !target.iter().all(|v| v.is_finite()) {
        return Err(IkError::InvalidInput(format!("target must be finite, got {target}")));
    }
    if current.len() != N || !current.iter().all(|v| v.is_finite()) {
        return Err(IkError::InvalidInput(format!(
            "current configuration: expected {N} finite values, got {current:?}"
        )));
    }
    if !(step.is_finite() && step > 0.0) {
        return Err(IkError::InvalidInput(format!("scan step must be a positive angle, got {step} rad")));
    }
    let limits: Vec<_> = robot.joints().iter().map(|j| j.limits).collect();
    // The grid of each scanned joint: lower limit + k·step up to the upper limit.
    let mut counts = [0usize; N];
    let mut nodes = 1.0f64;
    for i in 2..N {
        if !limits[i].is_bounded() {
            return Err(unsupported(robot, format!("joint {} has no finite limits to scan", i + 1)));
        }
        counts[i] = (limits[i].span() / step + 1e-9).floor() as usize + 1;
        nodes *= counts[i] as f64;
    }
    if nodes > MAX_SCAN_NODES as f64 {
        return Err(IkError::InvalidInput(format!(
            "scan step {step} rad gives {nodes} grid nodes, more than {MAX_SCAN_NODES}"
        )));
    }
    let p = robot.chain.first.inverse_transform_point(target);
    let offset = p.z - chain.height;
    let lengths = chain.lengths();
    if offset.abs() > IK_POSITION {
        let failure =
            IkFailure::Unreachable { distance: offset.abs(), reach: 0.0, point: "the target", from: "the arm's plane" };
        return Ok(ScanOutcome::NoSolution(failure));
    }
    let mut choice = ScanChoice { q: Vec::new(), s: f64::INFINITY, nodes: 0, configurations: 0, within_limits: 0 };
    let mut q = [0.0; N];
    let mut index = [0usize; N];
    let mut reach = 0.0f64;
    let mut first_violation: Option<usize> = None;
    loop {
        for i in 2..N {
            q[i] = limits[i].lower + index[i] as f64 * step;
        }
        q[0] = 0.0;
        q[1] = 0.0;
        // At q1 = q2 = 0: link 1's vector and the rigid tail from joint 2 to the tool.
        let phi = chain.link_angles(&q);
        let a0 = phi[0];
        let v = (1..N).fold([0.0, 0.0], |v, k| [v[0] + lengths[k] * phi[k].cos(), v[1] + lengths[k] * phi[k].sin()]);
        let tail = v[0].hypot(v[1]);
        reach = reach.max(lengths[0] + tail);
        let b0 = v[1].atan2(v[0]);
        if let TwoLink::In(elbows) = two_link(lengths[0], tail, [p.x, p.y], 0.0) {
            for elbow in elbows.iter().flatten() {
                choice.configurations += 1;
                // Joint 1 turns everything by θ1 = s1·q1; joint 2 turns the tail by θ2 = s2·q2.
                let theta1 = elbow.phi[0] - a0;
                let theta2 = elbow.phi[1] - b0 - theta1;
                let mut candidate = q;
                candidate[0] = fit_revolute(chain.links[0].sign * theta1, &limits[0]);
                candidate[1] = fit_revolute(chain.links[1].sign * theta2, &limits[1]);
                if let Some(i) = (0..2).find(|&i| !limits[i].contains(candidate[i], LIMIT_SLACK)) {
                    first_violation.get_or_insert(i);
                    continue;
                }
                choice.within_limits += 1;
                let s: f64 = candidate.iter().zip(current).map(|(a, b)| (a - b).abs()).sum();
                if s < choice.s {
                    choice.s = s;
                    choice.q = candidate.to_vec();
                }
            }
        }
        choice.nodes += 1;
        // Next grid node (odometer over joints 3…n).
        let mut i = 2;
        while i < N {
            index[i] += 1;
            if index[i] < counts[i] {
                break;
            }
            index[i] = 0;
            i += 1;
        }
        if i == N {
            break;
        }
    }
    if choice.q.is_empty() {
        let distance = p.x.hypot(p.y);
        let failure = match first_violation {
            Some(i) => IkFailure::OutsideLimits { joint: i + 1, name: robot.joints()[i].name.clone() },
            None => IkFailure::Unreachable { distance, reach, point: "the target", from: "joint 1" },
        };
        return Ok(ScanOutcome::NoSolution(failure));
    }
    Ok(ScanOutcome::Chosen(choice))
}
