//! Seed 003's measures of a target without solving: Δ and the shoulder, elbow and wrist
//! singularity measures per branch ([`ParallelAxes::measures`]), and the ones path tracking
//! scans ([`PathMeasures`]).

use serde::Serialize;

use super::*;

/// Seed 003's quantities of one target for one shoulder and wrist branch (notes 003 §3.3).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ArmMeasures {
    /// Shoulder branch.
    pub shoulder: Shoulder,
    /// Wrist branch.
    pub wrist: Wrist,
    /// `r2`: length of the in-plane vector from the shoulder to the elbow-triangle apex
    /// (|OB| for the welder), metres.
    pub r2: f64,
    /// The paper's `Δ = (l2² + r2² − l3²)/(2·l2·r2) = cos β` (eq. 14, l = |a|). |Δ| ≤ 1 is
    /// reachable, |Δ| = 1 an elbow singularity. For r2 = 0 it is computed with r2 =
    /// `f64::MIN_POSITIVE` (huge, or 0 when l2 = l3 — see [`ArmMeasures::elbow_margin`]).
    pub delta: f64,
    /// Cosine of the angle between links 2 and 3 (`(r2² − a2² − a3²)/(2·a2·a3)`): ±1 at the
    /// elbow singularity, also for l2 = l3 where Δ misses the folded arm.
    pub cos_elbow: f64,
    /// `sin∠(w, e6) = ‖z1 × z5‖`: 0 at the wrist singularity.
    pub wrist_sine: f64,
}

impl ArmMeasures {
    /// β = arccos Δ (radians) when |Δ| ≤ 1 (within [`BOUNDARY`]), else `None`.
    #[must_use]
    pub fn beta(&self) -> Option<f64> {
        (self.delta.abs() <= 1.0 + BOUNDARY).then(|| self.delta.clamp(-1.0, 1.0).acos())
    }

    /// `1 − |cos_elbow|`: positive inside the workspace, 0 at the elbow singularity
    /// (|Δ| = 1), negative when the target is out of reach on this branch.
    #[must_use]
    pub fn elbow_margin(&self) -> f64 {
        1.0 - self.cos_elbow.abs()
    }
}

/// Δ and the singularity measures of a target (see [`ParallelAxes::measures`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TargetMeasures {
    /// Horizontal distance ρ of the wrist point C from the column axis, metres.
    pub column_distance: f64,
    /// |D| = |d2 + d3·cos α2 + d4·cos α2·cos α3|, metres: the shoulder is singular at
    /// ρ = |D| (0 for the welder: C on the column axis).
    pub lateral_offset: f64,
    /// Per branch, in the order (w, e5), (w, −e5), (−w, e5), (−w, −e5); `None` when the
    /// shoulder equation has no root (ρ < |D|).
    pub arms: [Option<ArmMeasures>; 4],
}

impl TargetMeasures {
    /// ρ − |D|: 0 at the shoulder singularity, negative when out of reach.
    #[must_use]
    pub fn shoulder_margin(&self) -> f64 {
        self.column_distance - self.lateral_offset
    }

    /// The measures of one branch.
    #[must_use]
    pub fn arm(&self, shoulder: Shoulder, wrist: Wrist) -> Option<&ArmMeasures> {
        let i = match (shoulder, wrist) {
            (Shoulder::W, Wrist::E5) => 0,
            (Shoulder::W, Wrist::MinusE5) => 1,
            (Shoulder::MinusW, Wrist::E5) => 2,
            (Shoulder::MinusW, Wrist::MinusE5) => 3,
        };
        self.arms[i].as_ref()
    }

    /// The branch the paper uses (shoulder `w`, wrist `e5`): its Δ is the paper's Δ.
    #[must_use]
    pub fn paper(&self) -> Option<&ArmMeasures> {
        self.arm(Shoulder::W, Wrist::E5)
    }
}

impl ParallelAxes {
    /// Δ (cos β) and the singularity measures of `target` without solving (notes 003 §3.3,
    /// §3.6), for every shoulder and wrist branch: the motion module tracks these along a
    /// path to find the singular positions (|Δ| = 1, ρ = |D|, sin∠(w, e6) = 0).
    ///
    /// # Arguments
    /// * `target` — tool pose in the world frame;
    /// * `options` — only `seed` is used, for the undetermined angles at singularities
    ///   (θ1 when C is on the column axis, θ6 when e6 ∥ w).
    ///
    /// # Errors
    /// [`IkError::InvalidInput`] for a non-finite target, [`IkError::Kinematics`] for a bad seed.
    ///
    /// # Example
    /// ```
    /// use reach::ik::parallel_axes::ParallelAxes;
    /// let welder = reach::model::presets::get("welder6r").unwrap();
    /// let solver = ParallelAxes::from_robot(&welder).unwrap();
    /// let pose = welder.fk(&[0.3, 0.2, 0.9, -1.0, -0.8, 0.4]).unwrap();
    /// let m = solver.measures(&welder, &pose, &Default::default()).unwrap();
    /// let paper = m.paper().unwrap();
    /// assert!(paper.delta.abs() < 1.0 && paper.elbow_margin() > 0.0);
    /// ```
    pub fn measures(
        &self,
        robot: &Robot,
        target: &Isometry3<f64>,
        options: &IkOptions,
    ) -> Result<TargetMeasures, IkError> {
        IkTarget::Pose(*target).validate()?;
        let seed = self.seed_theta(robot, options)?;
        let frame = frame_of(&self.frame.target(robot, target));
        let (z5, c) = self.wrist_point(&frame);
        let rho = c.x.hypot(c.y);
        let mut out = TargetMeasures { column_distance: rho, lateral_offset: self.lateral.abs(), arms: [None; 4] };
        if let Ok(roots) = self.shoulder_roots(&c, seed[0]) {
            for root in &roots {
                let shared = self.shoulder_arm(&frame, &z5, root, seed[5]);
                for (j, wrist) in [Wrist::E5, Wrist::MinusE5].into_iter().enumerate() {
                    let arm = self.arm(&shared, &c, wrist);
                    let (l2, l3) = (self.a[1], self.a[2]);
                    let delta =
                        (l2 * l2 + arm.r2 * arm.r2 - l3 * l3) / (2.0 * l2.abs() * arm.r2.max(f64::MIN_POSITIVE));
                    let cos_elbow = (arm.r2 * arm.r2 - l2 * l2 - l3 * l3) / (2.0 * l2 * l3);
                    let slot = match root.label {
                        Shoulder::W => j,
                        Shoulder::MinusW => 2 + j,
                    };
                    out.arms[slot] = Some(ArmMeasures {
                        shoulder: root.label,
                        wrist,
                        r2: arm.r2,
                        delta,
                        cos_elbow,
                        wrist_sine: shared.wrist_sine,
                    });
                }
            }
        }
        Ok(out)
    }
}

/// Seed 003's closed-form singularity measures along a path (notes 003 §3.6), from
/// [`ParallelAxes::measures`]: for every shoulder/wrist branch the configurations use (a
/// configuration without a `shoulder` or `wrist` pair uses both of that pair), the elbow
/// measure `sign(m)·√|m|` with `m = 1 − |cos θ_elbow|` (0 where |Δ| = 1, negative out of
/// reach) and the wrist measure `sin∠(w, e6)`; then the shoulder measure `(ρ − |D|)/L`, `L`
/// the sum of the DH lengths `|a| + |d|` (at least 1 mm).
#[derive(Debug, Clone)]
pub struct PathMeasures {
    solver: ParallelAxes,
    arms: Vec<(Shoulder, Wrist)>,
    kinds: Vec<SingularityKind>,
    length_scale: f64,
}

impl PathMeasures {
    /// The measures of the shoulder/wrist branches `configurations` use.
    #[must_use]
    pub fn new(solver: ParallelAxes, configurations: &[Branch]) -> Self {
        let mut arms = Vec::new();
        let mut kinds = Vec::new();
        for shoulder in [Shoulder::W, Shoulder::MinusW] {
            for wrist in [Wrist::E5, Wrist::MinusE5] {
                let used = configurations.iter().any(|c| {
                    c.get("shoulder").is_none_or(|v| v == shoulder.label())
                        && c.get("wrist").is_none_or(|v| v == wrist.label())
                });
                if used {
                    arms.push((shoulder, wrist));
                    kinds.extend([SingularityKind::Elbow, SingularityKind::Wrist]);
                }
            }
        }
        kinds.push(SingularityKind::Shoulder);
        let length_scale = solver.a.iter().zip(&solver.d).map(|(a, d)| a.abs() + d.abs()).sum::<f64>().max(1e-3);
        PathMeasures { solver, arms, kinds, length_scale }
    }
}

impl SingularityMeasures for PathMeasures {
    fn kinds(&self) -> &[SingularityKind] {
        &self.kinds
    }

    fn at(&self, robot: &Robot, pose: &Isometry3<f64>) -> Result<Vec<Option<f64>>, IkError> {
        let m = self.solver.measures(robot, pose, &IkOptions::default())?;
        let mut out = Vec::with_capacity(self.kinds.len());
        for &(shoulder, wrist) in &self.arms {
            let arm = m.arm(shoulder, wrist);
            out.push(arm.map(|a| {
                let e = a.elbow_margin();
                e.signum() * e.abs().sqrt()
            }));
            out.push(arm.map(|a| a.wrist_sine));
        }
        out.push(Some(m.shoulder_margin() / self.length_scale));
        Ok(out)
    }
}
