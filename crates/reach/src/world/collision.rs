//! Collision and clearance of a robot's links against a scene, and self-collision.

use nalgebra::{IsometryMatrix3, Vector3};
use serde::Serialize;

use super::sweep::{Clearances, Sweep, SweepOptions, segment_rate, sweep};
use super::{Scene, Touching, WorldError};
use crate::model::Robot;
use crate::tolerance::CONTACT;

/// Below this length (metres) a segment between consecutive frame origins is skipped: it is
/// a joint with coincident frames (e.g. a wrist centre), not a link.
const MIN_SEGMENT: f64 = 1e-9;

/// In a swept check, a box farther than this (metres, by its bounding sphere) is measured by
/// the bounding sphere alone (a lower bound of its distance).
const FAR_BOX: f64 = 0.1;

/// Refuses times of a timed swept check that are not finite and non-decreasing.
fn check_times(times: &[f64]) -> Result<(), WorldError> {
    if let Some(t) = times.iter().find(|t| !t.is_finite()) {
        return Err(WorldError::Input(format!("swept check: the times must be finite seconds, got {t}")));
    }
    if let Some(w) = times.windows(2).find(|w| w[1] < w[0]) {
        return Err(WorldError::Input(format!(
            "swept check: the times must not decrease, got {} s after {} s",
            w[1], w[0]
        )));
    }
    Ok(())
}

/// The outcome of one collision check, in the order the checks run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(tag = "verdict", rename_all = "snake_case")]
pub enum Verdict {
    /// No collision, tool inside its zone.
    Free,
    /// The tool point is not strictly inside tool-zone entry `zone` (0-based).
    OutsideZone {
        /// Index into [`Scene::tool_zone`].
        zone: usize,
    },
    /// Two non-adjacent links collide.
    SelfCollision {
        /// 1-based link number (`dof + 1` is the tool segment).
        link_a: usize,
        /// 1-based link number of the other link.
        link_b: usize,
    },
    /// A link collides with an obstacle.
    Obstacle {
        /// 1-based link number (`dof + 1` is the tool segment).
        link: usize,
        /// Index into [`Scene::obstacles`].
        obstacle: usize,
    },
}

impl Verdict {
    /// Whether the configuration is allowed.
    #[must_use]
    pub fn is_free(&self) -> bool {
        matches!(self, Verdict::Free)
    }
}

/// Clearance between one link and one obstacle.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct LinkClearance {
    /// 1-based link number (`dof + 1` is the segment from the last frame to the tool point).
    pub link: usize,
    /// Obstacle name.
    pub obstacle: String,
    /// Signed clearance, metres: distance between the link's capsule and the obstacle, or
    /// minus the penetration depth of the link axis less the link radius.
    pub clearance_m: f64,
    /// Whether this pair collides under the scene's touching policy.
    pub colliding: bool,
}

/// Clearance between two non-adjacent links.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct SelfClearance {
    /// 1-based link number.
    pub link_a: usize,
    /// 1-based link number.
    pub link_b: usize,
    /// Distance between the two capsules, metres (negative: overlap).
    pub clearance_m: f64,
    /// Whether they collide under the touching policy (always `false` for an exempt pair).
    pub colliding: bool,
    /// Whether the pair is on the scene's allowed-collision list (not checked).
    pub exempt: bool,
}

/// Where the tool point is relative to one tool-zone entry.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct Contact {
    /// Zone name.
    pub zone: String,
    /// Signed distance of the tool point to the zone's boundary (negative: inside), metres.
    pub signed_distance_m: f64,
    /// Whether the tool point is strictly inside (by more than the contact tolerance).
    pub inside: bool,
}

/// Full clearance report of one configuration.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct Report {
    /// The first failed check (or free).
    pub verdict: Verdict,
    /// Every (link, obstacle) pair.
    pub links: Vec<LinkClearance>,
    /// Every pair of non-adjacent links.
    pub self_pairs: Vec<SelfClearance>,
    /// The tool point against every zone entry.
    pub tool_zone: Vec<Contact>,
    /// Smallest link–obstacle clearance (`None` without obstacles), metres.
    pub min_obstacle_clearance_m: Option<f64>,
    /// Smallest link–link clearance (`None` without non-adjacent pairs), metres.
    pub min_self_clearance_m: Option<f64>,
}

/// Checks configurations of one robot against one scene.
///
/// Links are the segments between consecutive points of
/// [`Robot::joint_positions`] (base origin, every frame origin, tool point): segment `k`
/// (0-based) is link `k + 1`, the last one (last frame → tool point) is link `dof + 1` and
/// takes the last link's radius. Segments shorter than 1 nm (coincident frames) are skipped;
/// two remaining segments are adjacent when they are consecutive in that list (they share a
/// joint), and only non-adjacent pairs are tested for self-collision.
///
/// # Performance
/// [`CollisionChecker::check`] allocates nothing: forward kinematics into preallocated frames,
/// then one exact distance (with early outs for boxes) per pair, stopping at the first hit.
#[derive(Debug, Clone)]
pub struct CollisionChecker<'a> {
    robot: &'a Robot,
    scene: &'a Scene,
    frames: Vec<IsometryMatrix3<f64>>,
    /// The transforms before each joint's motion of [`CollisionChecker::check_changed`]'s
    /// last configuration (and its tool pose), valid while `prefix_valid`.
    before: Vec<IsometryMatrix3<f64>>,
    prefix_valid: bool,
    points: Vec<Vector3<f64>>,
    radii: Vec<f64>,
    active: Vec<usize>,
    margin: f64,
    /// Bounding sphere of each obstacle (broad phase; `None`: always tested).
    bounds: Vec<Option<(Vector3<f64>, f64)>>,
    max_radius: f64,
    /// Per 0-based link `i`: bit `j` set when the pair `(i, j)` is exempt from self-collision.
    exempt: Vec<u64>,
    /// An allowed-collision entry that names no link of the robot (reported by `check`).
    exempt_error: Option<WorldError>,
    /// The link pairs of the swept check in progress ([`Clearances::prepare`]).
    sweep_pairs: Vec<(usize, usize)>,
    /// The instant of [`CollisionChecker::check_at`] and [`CollisionChecker::report_at`],
    /// seconds from the start of the motion: where moving obstacles are.
    time: f64,
    /// The time interval `[t_a, t_b]` of the swept check in progress (`None`: untimed, only
    /// for scenes without moving obstacles).
    span: Option<(f64, f64)>,
}

/// How often one pair of non-adjacent links collides over random configurations
/// ([`CollisionChecker::survey_self_collisions`]), ignoring the allowed-collision list.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PairSurvey {
    /// 1-based link number.
    pub link_a: usize,
    /// 1-based link number.
    pub link_b: usize,
    /// Name of link `a` as an allowed-collision entry takes it (joint name or `tool`).
    pub name_a: String,
    /// Name of link `b`.
    pub name_b: String,
    /// Configurations in which the pair collides.
    pub colliding: usize,
    /// Configurations sampled.
    pub samples: usize,
}

impl PairSurvey {
    /// Collides in every sample: a candidate for the allowed-collision list (the links'
    /// capsules overlap by construction, as MoveIt's setup assistant's "always in collision").
    #[must_use]
    pub fn always(&self) -> bool {
        self.samples > 0 && self.colliding == self.samples
    }

    /// Collides in no sample.
    #[must_use]
    pub fn never(&self) -> bool {
        self.colliding == 0
    }
}

/// The name of 0-based link `k` for allowed-collision entries.
fn link_name(robot: &Robot, k: usize) -> String {
    robot.joints().get(k).map_or_else(|| "tool".to_string(), |j| j.name.clone())
}

/// Resolves one link name of an allowed-collision entry to a 0-based link index: a joint
/// name (link `k` ends at joint `k`'s frame), `link<k>` (1-based) or `tool` (link `dof + 1`).
fn link_index(robot: &Robot, name: &str) -> Result<usize, WorldError> {
    let n = robot.dof();
    if let Some(k) = robot.joints().iter().position(|j| j.name == name) {
        return Ok(k);
    }
    if name == "tool" {
        return Ok(n);
    }
    if let Some(k) = name.strip_prefix("link").and_then(|k| k.parse::<usize>().ok())
        && (1..=n + 1).contains(&k)
    {
        return Ok(k - 1);
    }
    let names: Vec<&str> = robot.joints().iter().map(|j| j.name.as_str()).collect();
    Err(WorldError::Input(format!(
        "allowed_self_collisions: unknown link `{name}` (expected a joint name of {} ({}), link1..link{}, or tool)",
        robot.name(),
        names.join(", "),
        n + 1
    )))
}

/// The exemption bit masks of `scene`'s allowed-collision list for `robot`.
fn exempt_masks(robot: &Robot, scene: &Scene) -> Result<Vec<u64>, WorldError> {
    let n = robot.dof();
    if n + 1 > 64 && !scene.allowed_self_collisions.is_empty() {
        return Err(WorldError::Input(format!("allowed_self_collisions: at most 63 joints, the robot has {n}")));
    }
    let mut masks = vec![0_u64; n + 1];
    for [a, b] in &scene.allowed_self_collisions {
        let (i, j) = (link_index(robot, a)?, link_index(robot, b)?);
        if i == j {
            return Err(WorldError::Input(format!(
                "allowed_self_collisions: pair [`{a}`, `{b}`] names one link twice"
            )));
        }
        masks[i] |= 1 << j;
        masks[j] |= 1 << i;
    }
    Ok(masks)
}

impl<'a> CollisionChecker<'a> {
    /// Prepares buffers for `robot` in `scene`, checking the scene's allowed-collision list.
    ///
    /// # Errors
    /// [`WorldError::Input`] naming the entry when [`Scene::allowed_self_collisions`] names a
    /// link the robot does not have, or one link twice.
    pub fn try_new(robot: &'a Robot, scene: &'a Scene) -> Result<Self, WorldError> {
        let checker = CollisionChecker::new(robot, scene);
        match checker.exempt_error {
            Some(e) => Err(e),
            None => Ok(checker),
        }
    }

    /// Prepares buffers for `robot` in `scene`. A bad allowed-collision list is reported by
    /// every [`CollisionChecker::check`] and [`CollisionChecker::report`] (use
    /// [`CollisionChecker::try_new`] to see it at once).
    #[must_use]
    pub fn new(robot: &'a Robot, scene: &'a Scene) -> Self {
        let n = robot.dof();
        let radii = robot.segment_radii();
        let exempt = exempt_masks(robot, scene);
        let margin = match scene.touching {
            Touching::Closed => CONTACT,
            Touching::Open => -CONTACT,
        };
        CollisionChecker {
            robot,
            scene,
            frames: vec![IsometryMatrix3::identity(); n],
            before: vec![IsometryMatrix3::identity(); n + 1],
            prefix_valid: false,
            points: vec![Vector3::zeros(); n + 2],
            radii,
            active: Vec::with_capacity(n + 1),
            margin,
            bounds: scene.obstacles.iter().map(|o| o.shape.bounding_sphere()).collect(),
            max_radius: robot.links().iter().map(|l| l.radius).fold(0.0, f64::max),
            exempt: exempt.as_ref().map_or_else(|_| vec![0; n + 1], Clone::clone),
            exempt_error: exempt.err(),
            sweep_pairs: Vec::new(),
            time: 0.0,
            span: None,
        }
    }

    /// The robot.
    #[must_use]
    pub fn robot(&self) -> &Robot {
        self.robot
    }

    /// The scene.
    #[must_use]
    pub fn scene(&self) -> &Scene {
        self.scene
    }

    /// Computes the link points of `q` into the buffers.
    fn update(&mut self, q: &[f64]) -> Result<(), WorldError> {
        if let Some(e) = &self.exempt_error {
            return Err(e.clone());
        }
        self.update_points(q)
    }

    /// Computes the link points of `q` into the buffers (no allowed-collision check).
    fn update_points(&mut self, q: &[f64]) -> Result<(), WorldError> {
        self.prefix_valid = false;
        let tool = self.robot.frames_into(q, &mut self.frames)?;
        self.set_points(&tool);
        Ok(())
    }

    /// Sets the link points from the frames in the buffers and the tool pose.
    fn set_points(&mut self, tool: &IsometryMatrix3<f64>) {
        self.points[0] = self.robot.base().translation.vector;
        for (p, f) in self.points[1..].iter_mut().zip(&self.frames) {
            *p = f.translation.vector;
        }
        let last = self.points.len() - 1;
        self.points[last] = tool.translation.vector;
        self.active.clear();
        for k in 0..last {
            if (self.points[k + 1] - self.points[k]).norm_squared() > MIN_SEGMENT * MIN_SEGMENT {
                self.active.push(k);
            }
        }
    }

    /// [`CollisionChecker::check`] of a configuration that differs from the one of the
    /// previous call of this method (with no other check between) only in the joints from
    /// `changed_from` (0-based) on: the link frames before them are reused, the verdict is
    /// [`CollisionChecker::check`]'s bit for bit (a configuration-space grid, whose inner
    /// joints change most often). Moving obstacles are where they are at time 0.
    ///
    /// # Errors
    /// As [`CollisionChecker::check`].
    pub(crate) fn check_changed(&mut self, q: &[f64], changed_from: usize) -> Result<Verdict, WorldError> {
        self.set_time(0.0)?;
        if let Some(e) = &self.exempt_error {
            return Err(e.clone());
        }
        let from = if self.prefix_valid { changed_from } else { 0 };
        // Invalid until the frames are complete (an error leaves them partly updated).
        self.prefix_valid = false;
        let tool = self.robot.frames_from(q, from, &mut self.before, &mut self.frames)?;
        self.prefix_valid = true;
        self.set_points(&tool);
        Ok(self.classify())
    }

    /// Whether the pair of 0-based links `i`, `j` is on the scene's allowed-collision list.
    #[inline]
    fn exempt_pair(&self, i: usize, j: usize) -> bool {
        // `checked_shr`: robots of 64 or more joints have no list (all masks 0).
        self.exempt[i].checked_shr(u32::try_from(j).unwrap_or(u32::MAX)).is_some_and(|m| m & 1 == 1)
    }

    /// Every pair of links in the buffers that are not adjacent (not consecutive among the
    /// segments of non-zero length), with whether it is exempt.
    fn link_pairs(&self) -> impl Iterator<Item = (usize, usize, bool)> + '_ {
        let act = &self.active;
        act.iter()
            .enumerate()
            .flat_map(move |(x, &i)| act.iter().skip(x + 2).map(move |&j| (i, j, self.exempt_pair(i, j))))
    }

    /// Clearance between the capsules of 0-based links `i` and `j` in the buffers, metres.
    #[inline]
    fn pair_clearance(&self, i: usize, j: usize) -> f64 {
        super::distance::segment_segment_sq(&self.points[i], &self.points[i + 1], &self.points[j], &self.points[j + 1])
            .sqrt()
            - self.radii[i]
            - self.radii[j]
    }

    /// World positions of the link points of the last checked configuration (base origin,
    /// frame origins, tool point).
    #[must_use]
    pub fn points(&self) -> &[Vector3<f64>] {
        &self.points
    }

    /// Checks `q`: tool zone, then self-collision, then obstacles; the first failure wins.
    /// Moving obstacles are where they are at time 0 (the scene's shapes as given); see
    /// [`CollisionChecker::check_at`].
    ///
    /// # Errors
    /// [`WorldError::Kinematics`] when `q` has the wrong length or a non-finite value;
    /// [`WorldError::Input`] when the scene's allowed-collision list names an unknown link.
    pub fn check(&mut self, q: &[f64]) -> Result<Verdict, WorldError> {
        self.check_at(q, 0.0)
    }

    /// Checks `q` at time `t` (seconds from the start of the motion): as
    /// [`CollisionChecker::check`], every moving obstacle translated by `velocity·t`.
    ///
    /// # Errors
    /// As [`CollisionChecker::check`]; [`WorldError::Input`] for a non-finite `t`.
    pub fn check_at(&mut self, q: &[f64], t: f64) -> Result<Verdict, WorldError> {
        self.set_time(t)?;
        self.update(q)?;
        Ok(self.classify())
    }

    /// Sets the instant of the next configuration check.
    fn set_time(&mut self, t: f64) -> Result<(), WorldError> {
        if !t.is_finite() {
            return Err(WorldError::Input(format!("the time of a check must be a finite number of seconds, got {t}")));
        }
        self.time = t;
        Ok(())
    }

    /// Classifies the configuration in the buffers.
    #[inline]
    fn classify(&self) -> Verdict {
        let tool = self.points[self.points.len() - 1];
        for (i, z) in self.scene.tool_zone.iter().enumerate() {
            if z.shape.point_sdf(&tool) >= -CONTACT {
                return Verdict::OutsideZone { zone: i };
            }
        }
        for (i, j, exempt) in self.link_pairs() {
            if !exempt && self.pair_clearance(i, j) <= self.margin {
                return Verdict::SelfCollision { link_a: i + 1, link_b: j + 1 };
            }
        }
        let act = &self.active;
        // Broad phase: a sphere around every link point (centre of their bounding box).
        let (mut lo, mut hi) = (self.points[0], self.points[0]);
        for p in &self.points[1..] {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        let centre = (lo + hi) * 0.5;
        let reach = self.points.iter().map(|p| (p - centre).norm_squared()).fold(0.0, f64::max).sqrt()
            + self.max_radius
            + self.margin.max(0.0);
        for (o, obstacle) in self.scene.obstacles.iter().enumerate() {
            // A moving obstacle at `time`: the link points taken relative to its displacement.
            let shift = obstacle.displacement(self.time);
            if let Some((c, r)) = self.bounds[o] {
                let gap = r + reach;
                if (c + shift - centre).norm_squared() > gap * gap {
                    continue;
                }
            }
            for &k in act {
                let (a, b) = (self.points[k] - shift, self.points[k + 1] - shift);
                if obstacle.shape.segment_within(&a, &b, self.radii[k], self.margin) {
                    return Verdict::Obstacle { link: k + 1, obstacle: o };
                }
            }
        }
        Verdict::Free
    }

    /// Samples `samples` configurations uniformly within the joint limits (revolute joints
    /// with infinite limits over `[−π, π)`), seeded by `seed`, and counts per pair of
    /// non-adjacent links how often they collide, ignoring the scene's allowed-collision list.
    /// Pairs that collide [`PairSurvey::always`] are the candidates for that list.
    ///
    /// # Errors
    /// [`WorldError::Input`] for `samples == 0` or a prismatic joint with an infinite limit;
    /// as [`CollisionChecker::check`] otherwise.
    pub fn survey_self_collisions(&mut self, samples: usize, seed: u64) -> Result<Vec<PairSurvey>, WorldError> {
        if samples == 0 {
            return Err(WorldError::Input("the self-collision survey needs at least one sample".into()));
        }
        let mut ranges = Vec::with_capacity(self.robot.dof());
        for j in self.robot.joints() {
            let (lo, hi) = (j.limits.lower, j.limits.upper);
            if lo.is_finite() && hi.is_finite() {
                ranges.push((lo, hi));
            } else if j.kind == crate::model::JointKind::Revolute {
                ranges.push((-std::f64::consts::PI, std::f64::consts::PI));
            } else {
                return Err(WorldError::Input(format!(
                    "joint `{}`: cannot sample a prismatic joint with an infinite limit",
                    j.name
                )));
            }
        }
        let n = self.robot.dof() + 1;
        let mut counts = vec![0_usize; n * n];
        let mut seen = vec![false; n * n];
        let mut rng = crate::rng::SplitMix64(seed);
        let mut q = vec![0.0; ranges.len()];
        for _ in 0..samples {
            for (v, (lo, hi)) in q.iter_mut().zip(&ranges) {
                *v = lo + (hi - lo) * rng.next_f64();
            }
            self.update_points(&q)?;
            for (x, &i) in self.active.iter().enumerate() {
                for &j in self.active.iter().skip(x + 2) {
                    seen[i * n + j] = true;
                    if self.pair_clearance(i, j) <= self.margin {
                        counts[i * n + j] += 1;
                    }
                }
            }
        }
        let mut out = Vec::new();
        for i in 0..n {
            for j in i + 1..n {
                if seen[i * n + j] {
                    out.push(PairSurvey {
                        link_a: i + 1,
                        link_b: j + 1,
                        name_a: link_name(self.robot, i),
                        name_b: link_name(self.robot, j),
                        colliding: counts[i * n + j],
                        samples,
                    });
                }
            }
        }
        Ok(out)
    }

    /// Every clearance of `q` (allocates the report), moving obstacles where they are at
    /// time 0.
    ///
    /// # Errors
    /// As [`CollisionChecker::check`].
    pub fn report(&mut self, q: &[f64]) -> Result<Report, WorldError> {
        self.report_at(q, 0.0)
    }

    /// Every clearance of `q` at time `t` (seconds from the start of the motion; moving
    /// obstacles translated by `velocity·t`).
    ///
    /// # Errors
    /// As [`CollisionChecker::check_at`].
    pub fn report_at(&mut self, q: &[f64], t: f64) -> Result<Report, WorldError> {
        self.set_time(t)?;
        self.update(q)?;
        let verdict = self.classify();
        let tool = self.points[self.points.len() - 1];
        let tool_zone = self
            .scene
            .tool_zone
            .iter()
            .map(|z| {
                let sd = z.shape.point_sdf(&tool);
                Contact { zone: z.name.clone(), signed_distance_m: sd, inside: sd < -CONTACT }
            })
            .collect();
        let mut links = Vec::new();
        for &k in &self.active {
            for o in &self.scene.obstacles {
                let shift = o.displacement(self.time);
                let c = o.shape.segment_sdf(&(self.points[k] - shift), &(self.points[k + 1] - shift)) - self.radii[k];
                links.push(LinkClearance {
                    link: k + 1,
                    obstacle: o.name.clone(),
                    clearance_m: c,
                    colliding: c <= self.margin,
                });
            }
        }
        let self_pairs: Vec<SelfClearance> = self
            .link_pairs()
            .map(|(i, j, exempt)| {
                let d = self.pair_clearance(i, j);
                SelfClearance {
                    link_a: i + 1,
                    link_b: j + 1,
                    clearance_m: d,
                    colliding: !exempt && d <= self.margin,
                    exempt,
                }
            })
            .collect();
        let min_obstacle_clearance_m = links.iter().map(|l| l.clearance_m).reduce(f64::min);
        let min_self_clearance_m = self_pairs.iter().map(|l| l.clearance_m).reduce(f64::min);
        Ok(Report { verdict, links, self_pairs, tool_zone, min_obstacle_clearance_m, min_self_clearance_m })
    }
}

/// What one clearance of the checker's swept check measures (see [`CollisionChecker::swept`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum SweptPair {
    /// The tool point inside tool-zone entry `zone` (0-based): its distance to the boundary.
    ToolZone {
        /// Index into [`Scene::tool_zone`].
        zone: usize,
    },
    /// A link against an obstacle.
    Obstacle {
        /// 1-based link number (`dof + 1` is the tool segment).
        link: usize,
        /// Index into [`Scene::obstacles`].
        obstacle: usize,
    },
    /// Two non-adjacent links.
    SelfPair {
        /// 1-based link number.
        link_a: usize,
        /// 1-based link number.
        link_b: usize,
    },
}

/// The swept check of a piecewise-straight joint path ([`CollisionChecker::swept_path`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathSweep {
    /// Whether every segment is proven clear.
    pub clear: bool,
    /// Certified lower bound of the clearance over the path (up to where the check stopped
    /// when not clear), metres; `+∞` without constraints.
    pub lower_bound: f64,
    /// Clearance evaluations over all segments checked.
    pub evaluations: usize,
    /// 0-based segment (between points `segment` and `segment + 1`) of `closest`.
    pub segment: usize,
    /// That segment's sweep: the closest approach of the path, or the first segment not
    /// proven clear.
    pub closest: Sweep,
    /// A timed check ([`CollisionChecker::swept_path_timed`]): the instant of `closest.at`,
    /// seconds from the start of the path.
    pub t_s: Option<f64>,
    /// What `closest`'s smallest clearance measures.
    pub pair: SweptPair,
}

impl CollisionChecker<'_> {
    /// The swept (continuous) check of the straight joint motion `a → b`
    /// ([`super::sweep::sweep`]): the tool point stays inside every tool-zone entry, and every
    /// link keeps a proven positive clearance to every obstacle and to every non-adjacent link
    /// (pairs that are non-adjacent at both ends, allowed-collision pairs excepted). Returns
    /// the sweep and what its smallest clearance measures.
    ///
    /// The motion is untimed, so a scene with a moving obstacle is refused
    /// ([`CollisionChecker::swept_timed`] checks it).
    ///
    /// # Errors
    /// As [`CollisionChecker::check`] at either end; [`WorldError::Input`] for a scene with a
    /// moving obstacle ([`Scene::require_fixed`]).
    pub fn swept(&mut self, a: &[f64], b: &[f64], options: &SweepOptions) -> Result<(Sweep, SweptPair), WorldError> {
        self.scene.require_fixed("a swept check without the motion's timing")?;
        self.swept_in(a, b, None, options)
    }

    /// The swept check of the straight joint motion `a → b` run from time `span[0]` to
    /// `span[1]` (seconds from the start of the motion, at a constant rate in the fraction
    /// `s` of the motion): as [`CollisionChecker::swept`], every obstacle where it is at each
    /// instant. An obstacle moving at `v` travels `|v|·(span[1] − span[0])` during the motion;
    /// that is added to every link's rate bound against it, so a clear verdict is proven for
    /// the moving obstacle too (module [`super::sweep`]). A fixed obstacle gives exactly the
    /// untimed check's result. Where the check stops (`Sweep::at`), the instant is
    /// `span[0] + at·(span[1] − span[0])`.
    ///
    /// # Errors
    /// As [`CollisionChecker::swept`] for the joint vectors; [`WorldError::Input`] for a
    /// non-finite time or `span[1] < span[0]`.
    pub fn swept_timed(
        &mut self,
        a: &[f64],
        b: &[f64],
        span: [f64; 2],
        options: &SweepOptions,
    ) -> Result<(Sweep, SweptPair), WorldError> {
        check_times(&span)?;
        self.swept_in(a, b, Some((span[0], span[1])), options)
    }

    /// The one swept check: untimed (`span = None`, fixed obstacles) or timed.
    fn swept_in(
        &mut self,
        a: &[f64],
        b: &[f64],
        span: Option<(f64, f64)>,
        options: &SweepOptions,
    ) -> Result<(Sweep, SweptPair), WorldError> {
        self.span = span;
        let result = sweep(self, a, b, options);
        self.span = None;
        let result = result?;
        Ok((result, self.swept_pair(result.constraint)))
    }

    /// The swept check of the piecewise-straight joint path through `points` (the path a
    /// drive schedule follows between samples, [`crate::drive::schedule_trajectory`]): each
    /// segment as [`CollisionChecker::swept`], stopping at the first segment not proven clear.
    ///
    /// # Returns
    /// `None` for fewer than two points; otherwise the verdict over the whole path and the
    /// segment that comes closest (or the first not proven clear).
    ///
    /// # Errors
    /// As [`CollisionChecker::swept`] (a scene with a moving obstacle is refused: see
    /// [`CollisionChecker::swept_path_timed`]).
    pub fn swept_path(&mut self, points: &[Vec<f64>], options: &SweepOptions) -> Result<Option<PathSweep>, WorldError> {
        self.scene.require_fixed("a swept check without the motion's timing")?;
        self.swept_path_in(points, None, options)
    }

    /// The swept check of the timed piecewise-straight joint path through `points`, reached
    /// at `times` (seconds from the start of the motion, non-decreasing; the joints move
    /// linearly in time between points, as a drive schedule interpolates them): each segment
    /// as [`CollisionChecker::swept_timed`] over its interval, stopping at the first segment
    /// not proven clear; [`PathSweep::t_s`] is the instant of the closest approach (or of
    /// where the check stopped).
    ///
    /// # Errors
    /// As [`CollisionChecker::swept_timed`]; [`WorldError::Input`] when `times` and `points`
    /// differ in length or the times are not finite and non-decreasing.
    pub fn swept_path_timed(
        &mut self,
        points: &[Vec<f64>],
        times: &[f64],
        options: &SweepOptions,
    ) -> Result<Option<PathSweep>, WorldError> {
        if times.len() != points.len() {
            return Err(WorldError::Input(format!(
                "swept check: {} times for {} points of the path",
                times.len(),
                points.len()
            )));
        }
        check_times(times)?;
        self.swept_path_in(points, Some(times), options)
    }

    /// The one path check: untimed or timed.
    fn swept_path_in(
        &mut self,
        points: &[Vec<f64>],
        times: Option<&[f64]>,
        options: &SweepOptions,
    ) -> Result<Option<PathSweep>, WorldError> {
        let mut path: Option<PathSweep> = None;
        for (k, w) in points.windows(2).enumerate() {
            let span = times.map(|t| (t[k], t[k + 1]));
            let (sweep, pair) = self.swept_in(&w[0], &w[1], span, options)?;
            let t_s = span.map(|(ta, tb)| ta + sweep.at * (tb - ta));
            let p = path.get_or_insert(PathSweep {
                clear: true,
                lower_bound: f64::INFINITY,
                evaluations: 0,
                segment: k,
                closest: sweep,
                t_s,
                pair,
            });
            p.clear &= sweep.clear;
            p.lower_bound = p.lower_bound.min(sweep.lower_bound);
            p.evaluations += sweep.evaluations;
            if !sweep.clear || sweep.min_clearance < p.closest.min_clearance {
                (p.segment, p.closest, p.pair, p.t_s) = (k, sweep, pair, t_s);
            }
            if !sweep.clear {
                break;
            }
        }
        Ok(path)
    }

    /// What clearance `c` of the last swept check measures.
    fn swept_pair(&self, c: usize) -> SweptPair {
        let zones = self.scene.tool_zone.len();
        let obstacles = self.scene.obstacles.len();
        let segments = self.points.len() - 1;
        if c < zones {
            SweptPair::ToolZone { zone: c }
        } else if c < zones + segments * obstacles {
            let k = (c - zones) / obstacles.max(1);
            SweptPair::Obstacle { link: k + 1, obstacle: (c - zones) % obstacles.max(1) }
        } else {
            let (i, j) = self.sweep_pairs.get(c - zones - segments * obstacles).copied().unwrap_or((0, 0));
            SweptPair::SelfPair { link_a: i + 1, link_b: j + 1 }
        }
    }

    /// The time of the point `s` of the swept check in progress (0 when untimed).
    fn time_of(&self, s: f64) -> f64 {
        self.span.map_or(0.0, |(ta, tb)| ta + s * (tb - ta))
    }

    /// Lengths of the segments in the buffers, metres.
    fn segment_lengths(&self) -> Vec<f64> {
        self.points.windows(2).map(|w| (w[1] - w[0]).norm()).collect()
    }
}

impl Clearances for CollisionChecker<'_> {
    /// Rates from [`segment_rate`]: each segment's length is bounded by the larger of its
    /// lengths at `a` and `b` (a segment vector is affine in a prismatic joint's value, so its
    /// length is convex along the motion), and every revolute joint's axis passes through the
    /// frame origin before or after it.
    fn prepare(&mut self, a: &[f64], b: &[f64]) -> Result<Vec<f64>, WorldError> {
        self.update(a)?;
        let (lengths_a, pairs_a): (Vec<f64>, Vec<(usize, usize)>) =
            (self.segment_lengths(), self.link_pairs().filter(|p| !p.2).map(|(i, j, _)| (i, j)).collect());
        self.update(b)?;
        let lengths: Vec<f64> = self.segment_lengths().iter().zip(&lengths_a).map(|(x, y)| x.max(*y)).collect();
        let pairs_b: Vec<(usize, usize)> = self.link_pairs().filter(|p| !p.2).map(|(i, j, _)| (i, j)).collect();
        self.sweep_pairs = pairs_a.into_iter().filter(|p| pairs_b.contains(p)).collect();
        let revolute: Vec<bool> =
            self.robot.joints().iter().map(|j| j.kind == crate::model::JointKind::Revolute).collect();
        let delta: Vec<f64> = a.iter().zip(b).map(|(x, y)| y - x).collect();
        let segments = lengths.len();
        let rate = |k: usize| segment_rate(&lengths, &revolute, &delta, 0, k, self.radii[k]);
        let tool = segment_rate(&lengths, &revolute, &delta, 0, segments - 1, 0.0);
        let mut rates = vec![tool; self.scene.tool_zone.len()];
        // A moving obstacle travels |v|·(t_b − t_a) over the motion: relative to it every link
        // point moves that much farther per unit of s (0 for a fixed obstacle).
        let duration = self.span.map_or(0.0, |(ta, tb)| tb - ta);
        let travel: Vec<f64> = self.scene.obstacles.iter().map(|o| o.velocity.norm() * duration).collect();
        for k in 0..segments {
            let r = rate(k);
            rates.extend(travel.iter().map(|t| r + t));
        }
        // Links i < j move relative to each other only by joints i..=j: the joints before i
        // move both rigidly (joint i does too in standard DH, not in modified DH or URDF).
        rates.extend(
            self.sweep_pairs.iter().map(|&(i, j)| segment_rate(&lengths, &revolute, &delta, i, j, self.radii[j])),
        );
        Ok(rates)
    }

    /// Moving obstacles where they are at the instant of `s` (the link points taken relative
    /// to their displacement).
    fn evaluate(&mut self, s: f64, q: &[f64], out: &mut [f64]) -> Result<(), WorldError> {
        self.update(q)?;
        let time = self.time_of(s);
        let tool = self.points[self.points.len() - 1];
        let mut c = 0;
        for z in &self.scene.tool_zone {
            out[c] = -z.shape.point_sdf(&tool);
            c += 1;
        }
        for k in 0..self.points.len() - 1 {
            for (o, bound) in self.scene.obstacles.iter().zip(&self.bounds) {
                let shift = o.displacement(time);
                let (a, b) = (&(self.points[k] - shift), &(self.points[k + 1] - shift));
                // A far box: the distance to its bounding sphere is a lower bound, which keeps
                // the sweep sound and spares the exact box distance (up to 14 point/edge
                // distances). Other shapes have cheap closed forms.
                let far = match (&o.shape, bound) {
                    (super::Shape::Box { .. }, Some((centre, r))) => {
                        Some(super::distance::point_segment_sq(centre, a, b).sqrt() - r - self.radii[k])
                            .filter(|lb| *lb > FAR_BOX)
                    }
                    _ => None,
                };
                out[c] = far.unwrap_or_else(|| o.shape.segment_sdf(a, b) - self.radii[k]);
                c += 1;
            }
        }
        for &(i, j) in &self.sweep_pairs {
            out[c] = self.pair_clearance(i, j);
            c += 1;
        }
        Ok(())
    }
}
