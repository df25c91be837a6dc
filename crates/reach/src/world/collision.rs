//! Collision and clearance of a robot's links against a scene, and self-collision.

use nalgebra::{IsometryMatrix3, Vector3};
use serde::Serialize;

use super::elements::Elements;
use super::sweep::{Clearances, JointCurve, Sweep, SweepOptions, segment_rate, sweep_curve};
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
    /// 1-based link number ([`CollisionChecker`]'s numbering).
    pub link: usize,
    /// The link's name ([`CollisionChecker::link_name`]).
    pub link_name: String,
    /// Obstacle name.
    pub obstacle: String,
    /// Signed clearance, metres: the smallest over the link's solids of the distance to the
    /// obstacle (a certified lower bound where GJK measures it), negative when they overlap.
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
    /// Name of link `a`.
    pub name_a: String,
    /// Name of link `b`.
    pub name_b: String,
    /// Smallest distance between the two links' solids, metres (negative: overlap).
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
    /// Smallest link–link clearance of the checked pairs (exempt pairs, reported in
    /// `self_pairs`, left out; `None` without a checked pair), metres.
    pub min_self_clearance_m: Option<f64>,
}

/// Checks configurations of one robot against one scene.
///
/// The robot is its collision body ([`Robot::bodies`]): every solid of every link, placed by
/// the link's chain frame; links are numbered `1..` in the order of [`Robot::bodies`] and named
/// by [`CollisionChecker::link_name`]. Two links are checked against each other unless they
/// are adjacent (one is the nearest ancestor with solids of the other), the robot disables
/// the pair ([`Robot::disabled_collisions`], an SRDF) or the scene allows it
/// ([`Scene::allowed_self_collisions`]).
///
/// A robot without bodies is checked as its **stick figure**: the segments between
/// consecutive points of [`Robot::joint_positions`] (base origin, every frame origin, tool
/// point), swept by the links' radii: segment `k` (0-based) is link `k + 1`, the last one
/// (last frame → tool point) is link `dof + 1` and takes the last link's radius. Segments
/// shorter than 1 nm (coincident frames) are skipped; two remaining segments are adjacent
/// when they are consecutive in that list (they share a joint).
///
/// # Performance
/// [`CollisionChecker::check`] allocates nothing: forward kinematics into preallocated frames,
/// the solids placed, then one distance per pair (closed forms for spheres and capsules, GJK
/// for boxes, cylinders and meshes), after a bounding-sphere test, stopping at the first hit.
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
    /// The robot's solids and where they are.
    elements: Elements<'a>,
    /// Elements tested against obstacles (stick segments of non-zero length; every solid).
    active: Vec<usize>,
    /// Element pairs tested against each other, with whether the scene or robot exempts
    /// them (stick: recomputed per configuration from `active`; bodies: fixed).
    pairs: Vec<(usize, usize, bool)>,
    margin: f64,
    /// Bounding sphere of each obstacle (broad phase; `None`: always tested).
    bounds: Vec<Option<(Vector3<f64>, f64)>>,
    /// Per pair of 0-based links `(i, j)`, at `i · links + j`: exempt from self-collision.
    exempt: Vec<bool>,
    /// A bad allowed-collision entry or an incomplete body (reported by `check`).
    exempt_error: Option<WorldError>,
    /// The element pairs of the swept check in progress ([`Clearances::prepare`]).
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

/// Resolves one link name of an allowed-collision entry to a 0-based link index: a body's
/// name; for the stick figure a joint name (link `k` ends at joint `k`'s frame), `link<k>`
/// (1-based) or `tool` (link `dof + 1`).
fn link_index(robot: &Robot, elements: &Elements, name: &str) -> Result<usize, WorldError> {
    if !elements.stick {
        return elements.names.iter().position(|b| b == name).ok_or_else(|| {
            WorldError::Input(format!(
                "allowed collisions: unknown link `{name}` (the links of {} with bodies: {})",
                robot.name(),
                elements.names.join(", ")
            ))
        });
    }
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

/// The exempt link pairs (`i · links + j`, both orders) of the robot's disabled pairs and the
/// scene's allowed-collision list.
fn exempt_matrix(robot: &Robot, elements: &Elements, scene: &Scene) -> Result<Vec<bool>, WorldError> {
    let links = elements.names.len();
    let mut exempt = vec![false; links * links];
    for [a, b] in robot.disabled_collisions().iter().chain(&scene.allowed_self_collisions) {
        let (i, j) = (link_index(robot, elements, a)?, link_index(robot, elements, b)?);
        if i == j {
            return Err(WorldError::Input(format!(
                "allowed_self_collisions: pair [`{a}`, `{b}`] names one link twice"
            )));
        }
        exempt[i * links + j] = true;
        exempt[j * links + i] = true;
    }
    Ok(exempt)
}

impl<'a> CollisionChecker<'a> {
    /// Prepares buffers for `robot` in `scene`, checking the scene's allowed-collision list
    /// and the robot's body.
    ///
    /// # Errors
    /// [`WorldError::Input`] naming the entry when the allowed-collision lists name a link the
    /// robot does not have, or one link twice; naming the link when the robot's body has a
    /// solid that was not loaded ([`crate::model::BodyShape::Missing`]).
    pub fn try_new(robot: &'a Robot, scene: &'a Scene) -> Result<Self, WorldError> {
        let checker = CollisionChecker::new(robot, scene);
        match checker.exempt_error {
            Some(e) => Err(e),
            None => Ok(checker),
        }
    }

    /// Prepares buffers for `robot` in `scene`. A bad allowed-collision list or an incomplete
    /// body is reported by every [`CollisionChecker::check`] and [`CollisionChecker::report`]
    /// (use [`CollisionChecker::try_new`] to see it at once).
    #[must_use]
    pub fn new(robot: &'a Robot, scene: &'a Scene) -> Self {
        let n = robot.dof();
        let (elements, mut error) = match Elements::of(robot) {
            Ok(e) => (e, None),
            Err(e) => {
                // An incomplete body: checked as an empty one, every check refused.
                let empty = Elements::of_nothing();
                (empty, Some(e))
            }
        };
        let exempt = exempt_matrix(robot, &elements, scene);
        let links = elements.names.len();
        if error.is_none() {
            error = exempt.as_ref().err().cloned();
        }
        let exempt = exempt.unwrap_or_else(|_| vec![false; links * links]);
        let margin = match scene.touching {
            Touching::Closed => CONTACT,
            Touching::Open => -CONTACT,
        };
        let mut checker = CollisionChecker {
            robot,
            scene,
            frames: vec![IsometryMatrix3::identity(); n],
            before: vec![IsometryMatrix3::identity(); n + 1],
            prefix_valid: false,
            points: vec![Vector3::zeros(); n + 2],
            active: Vec::with_capacity(elements.list.len()),
            pairs: Vec::new(),
            elements,
            margin,
            bounds: scene.obstacles.iter().map(|o| o.shape.bounding_sphere()).collect(),
            exempt,
            exempt_error: error,
            sweep_pairs: Vec::new(),
            time: 0.0,
            span: None,
        };
        if !checker.elements.stick {
            checker.active = (0..checker.elements.list.len()).collect();
            let list = &checker.elements.list;
            for i in 0..list.len() {
                for j in i + 1..list.len() {
                    let (a, b) = (list[i].link, list[j].link);
                    if a != b && !checker.elements.adjacent(a, b) {
                        checker.pairs.push((i, j, checker.exempt[a * links + b]));
                    }
                }
            }
        }
        checker
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

    /// The name of 1-based link `link` of this checker's verdicts and reports: the body's
    /// name, or for the stick figure the name of the joint whose frame ends the segment
    /// (`tool` for the last one).
    #[must_use]
    pub fn link_name(&self, link: usize) -> &str {
        link.checked_sub(1).and_then(|k| self.elements.names.get(k)).map_or("?", String::as_str)
    }

    /// Link `link` (1-based) as reports name it: ``link 5 (`wrist_2_link`)`` ([`link_label`]).
    #[must_use]
    pub fn link_label(&self, link: usize) -> String {
        link_label(link, self.link_name(link))
    }

    /// Whether the robot is checked by its collision body (`false`: its stick figure, see the
    /// type's docs).
    #[must_use]
    pub fn has_bodies(&self) -> bool {
        !self.elements.stick
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

    /// Sets the link points and places the solids from the frames in the buffers and the
    /// tool pose.
    fn set_points(&mut self, tool: &IsometryMatrix3<f64>) {
        let base = self.robot.base();
        self.points[0] = base.translation.vector;
        for (p, f) in self.points[1..].iter_mut().zip(&self.frames) {
            *p = f.translation.vector;
        }
        let last = self.points.len() - 1;
        self.points[last] = tool.translation.vector;
        let base = IsometryMatrix3::from_parts(base.translation, base.rotation.to_rotation_matrix());
        self.elements.place(&base, &self.frames, &self.points);
        if self.elements.stick {
            self.active.clear();
            for k in 0..last {
                if (self.points[k + 1] - self.points[k]).norm_squared() > MIN_SEGMENT * MIN_SEGMENT {
                    self.active.push(k);
                }
            }
            self.pairs.clear();
            let links = self.elements.names.len();
            for (x, &i) in self.active.iter().enumerate() {
                for &j in self.active.iter().skip(x + 2) {
                    self.pairs.push((i, j, self.exempt[i * links + j]));
                }
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
    /// [`WorldError::Input`] when the allowed-collision lists name an unknown link or the
    /// robot's body is incomplete.
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

    /// The 1-based link of element `e`.
    fn link_of(&self, e: usize) -> usize {
        self.elements.list[e].link + 1
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
        let spheres = &self.elements.spheres;
        for &(i, j, exempt) in &self.pairs {
            if exempt {
                continue;
            }
            let ((ci, ri), (cj, rj)) = (spheres[i], spheres[j]);
            let gap = ri + rj + self.margin.max(0.0);
            if (ci - cj).norm_squared() > gap * gap {
                continue;
            }
            if self.elements.pair_clearance(i, j) <= self.margin {
                return Verdict::SelfCollision { link_a: self.link_of(i), link_b: self.link_of(j) };
            }
        }
        for (o, obstacle) in self.scene.obstacles.iter().enumerate() {
            // A moving obstacle at `time`: the solids taken relative to its displacement.
            let shift = obstacle.displacement(self.time);
            for &e in &self.active {
                if let Some((c, r)) = self.bounds[o] {
                    let (ce, re) = spheres[e];
                    let gap = r + re + self.margin.max(0.0);
                    if (c + shift - ce).norm_squared() > gap * gap {
                        continue;
                    }
                }
                if self.elements.obstacle_within(e, &obstacle.shape, &shift, self.margin) {
                    return Verdict::Obstacle { link: self.link_of(e), obstacle: o };
                }
            }
        }
        Verdict::Free
    }

    /// Samples `samples` configurations uniformly within the joint limits (revolute joints
    /// with infinite limits over `[−π, π)`), seeded by `seed`, and counts per pair of
    /// non-adjacent links how often they collide, ignoring the allowed-collision lists.
    /// Pairs that collide [`PairSurvey::always`] are the candidates for those lists.
    ///
    /// # Errors
    /// [`WorldError::Input`] for `samples == 0` or a prismatic joint with an infinite limit;
    /// as [`CollisionChecker::check`] otherwise.
    pub fn survey_self_collisions(&mut self, samples: usize, seed: u64) -> Result<Vec<PairSurvey>, WorldError> {
        if samples == 0 {
            return Err(WorldError::Input("the self-collision survey needs at least one sample".into()));
        }
        if let Some(e) = &self.exempt_error {
            return Err(e.clone());
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
        let n = self.elements.names.len();
        let mut counts = vec![0_usize; n * n];
        let mut seen = vec![false; n * n];
        let mut hit = vec![false; n * n];
        let mut rng = crate::rng::SplitMix64(seed);
        let mut q = vec![0.0; ranges.len()];
        for _ in 0..samples {
            for (v, (lo, hi)) in q.iter_mut().zip(&ranges) {
                *v = lo + (hi - lo) * rng.next_f64();
            }
            self.update_points(&q)?;
            hit.fill(false);
            for &(i, j, _) in &self.pairs {
                let (a, b) = (self.elements.list[i].link, self.elements.list[j].link);
                let (a, b) = (a.min(b), a.max(b));
                seen[a * n + b] = true;
                if !hit[a * n + b] && self.elements.pair_clearance(i, j) <= self.margin {
                    hit[a * n + b] = true;
                    counts[a * n + b] += 1;
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
                        name_a: self.elements.names[i].clone(),
                        name_b: self.elements.names[j].clone(),
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
    /// obstacles translated by `velocity·t`): per link and obstacle, and per pair of links
    /// checked against each other, the smallest clearance of their solids.
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
        let mut links: Vec<LinkClearance> = Vec::new();
        for &e in &self.active {
            let link = self.link_of(e);
            for o in &self.scene.obstacles {
                let shift = o.displacement(self.time);
                let c = self.elements.obstacle_clearance(e, &o.shape, &shift);
                match links.iter_mut().find(|l| l.link == link && l.obstacle == o.name) {
                    Some(l) if c < l.clearance_m => {
                        l.clearance_m = c;
                        l.colliding = c <= self.margin;
                    }
                    Some(_) => {}
                    None => links.push(LinkClearance {
                        link,
                        link_name: self.link_name(link).to_string(),
                        obstacle: o.name.clone(),
                        clearance_m: c,
                        colliding: c <= self.margin,
                    }),
                }
            }
        }
        let mut self_pairs: Vec<SelfClearance> = Vec::new();
        for &(i, j, exempt) in &self.pairs {
            let d = self.elements.pair_clearance(i, j);
            let (a, b) = (self.link_of(i), self.link_of(j));
            let (a, b) = (a.min(b), a.max(b));
            match self_pairs.iter_mut().find(|p| p.link_a == a && p.link_b == b) {
                Some(p) if d < p.clearance_m => {
                    p.clearance_m = d;
                    p.colliding = !exempt && d <= self.margin;
                }
                Some(_) => {}
                None => self_pairs.push(SelfClearance {
                    link_a: a,
                    link_b: b,
                    name_a: self.link_name(a).to_string(),
                    name_b: self.link_name(b).to_string(),
                    clearance_m: d,
                    colliding: !exempt && d <= self.margin,
                    exempt,
                }),
            }
        }
        let min_obstacle_clearance_m = links.iter().map(|l| l.clearance_m).reduce(f64::min);
        let min_self_clearance_m = self_pairs.iter().filter(|p| !p.exempt).map(|l| l.clearance_m).reduce(f64::min);
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

    /// A straight motion's check: untimed or timed.
    fn swept_in(
        &mut self,
        a: &[f64],
        b: &[f64],
        span: Option<(f64, f64)>,
        options: &SweepOptions,
    ) -> Result<(Sweep, SweptPair), WorldError> {
        self.swept_curve_in(&JointCurve::Line(a, b), span, options)
    }

    /// The swept check of the untimed motion along `curve` (a straight line as
    /// [`CollisionChecker::swept`], or a quadratic arc: a blend between two straight motions).
    ///
    /// # Errors
    /// As [`CollisionChecker::swept`].
    pub fn swept_curve(
        &mut self,
        curve: &JointCurve,
        options: &SweepOptions,
    ) -> Result<(Sweep, SweptPair), WorldError> {
        self.scene.require_fixed("a swept check without the motion's timing")?;
        self.swept_curve_in(curve, None, options)
    }

    /// The one swept check: untimed (`span = None`, fixed obstacles) or timed.
    fn swept_curve_in(
        &mut self,
        curve: &JointCurve,
        span: Option<(f64, f64)>,
        options: &SweepOptions,
    ) -> Result<(Sweep, SweptPair), WorldError> {
        self.span = span;
        let result = sweep_curve(self, curve, options);
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
        let curves: Vec<JointCurve> = points.windows(2).map(|w| JointCurve::Line(&w[0], &w[1])).collect();
        let spans: Option<Vec<(f64, f64)>> = times.map(|t| t.windows(2).map(|w| (w[0], w[1])).collect());
        self.swept_curves_in(&curves, spans.as_deref(), options)
    }

    /// The swept check of the untimed path made of `curves` (each starting where the one
    /// before ends: lines and the arcs that blend them), each as
    /// [`CollisionChecker::swept_curve`], stopping at the first curve not proven clear;
    /// [`PathSweep::segment`] numbers the curves.
    ///
    /// # Returns
    /// `None` without curves.
    ///
    /// # Errors
    /// As [`CollisionChecker::swept`].
    pub fn swept_curves(
        &mut self,
        curves: &[JointCurve],
        options: &SweepOptions,
    ) -> Result<Option<PathSweep>, WorldError> {
        self.scene.require_fixed("a swept check without the motion's timing")?;
        self.swept_curves_in(curves, None, options)
    }

    /// The one path check: untimed or timed (`spans`, one time interval per curve).
    fn swept_curves_in(
        &mut self,
        curves: &[JointCurve],
        spans: Option<&[(f64, f64)]>,
        options: &SweepOptions,
    ) -> Result<Option<PathSweep>, WorldError> {
        let mut path: Option<PathSweep> = None;
        for (k, curve) in curves.iter().enumerate() {
            let span = spans.map(|t| t[k]);
            let (sweep, pair) = self.swept_curve_in(curve, span, options)?;
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
        let elements = self.elements.list.len();
        if c < zones {
            SweptPair::ToolZone { zone: c }
        } else if c < zones + elements * obstacles {
            let e = (c - zones) / obstacles.max(1);
            SweptPair::Obstacle { link: self.link_of(e), obstacle: (c - zones) % obstacles.max(1) }
        } else {
            let (i, j) = self.sweep_pairs.get(c - zones - elements * obstacles).copied().unwrap_or((0, 0));
            SweptPair::SelfPair { link_a: self.link_of(i), link_b: self.link_of(j) }
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
    /// Rates from [`segment_rate`] ([`Elements::rate`]) with each joint's speed bound: each
    /// chain segment's length is bounded by its largest length at the hull's configurations
    /// (a segment vector is affine in a prismatic joint's value, so its length is convex over
    /// the hull), every revolute joint's axis passes through the frame origin before or after
    /// it, and every point of a solid fixed to frame `f` lies within the solid's farthest
    /// distance from `f`'s origin.
    fn prepare(&mut self, hull: &[&[f64]], speed: &[f64]) -> Result<Vec<f64>, WorldError> {
        let mut lengths: Vec<f64> = Vec::new();
        let mut pairs: Option<Vec<(usize, usize)>> = None;
        for q in hull {
            self.update(q)?;
            let here = self.segment_lengths();
            lengths =
                if lengths.is_empty() { here } else { lengths.iter().zip(&here).map(|(x, y)| x.max(*y)).collect() };
            let active: Vec<(usize, usize)> = self.pairs.iter().filter(|p| !p.2).map(|&(i, j, _)| (i, j)).collect();
            pairs = Some(match pairs {
                // A stick figure's pairs are those non-adjacent at every configuration of the
                // hull; solids' pairs do not depend on the configuration.
                Some(before) if self.elements.stick => before.into_iter().filter(|p| active.contains(p)).collect(),
                _ => active,
            });
        }
        self.sweep_pairs = pairs.unwrap_or_default();
        let revolute: Vec<bool> =
            self.robot.joints().iter().map(|j| j.kind == crate::model::JointKind::Revolute).collect();
        let segments = lengths.len();
        let tool = segment_rate(&lengths, &revolute, speed, 0, segments - 1, 0.0);
        let mut rates = vec![tool; self.scene.tool_zone.len()];
        // A moving obstacle travels |v|·(t_b − t_a) over the motion: relative to it every link
        // point moves that much farther per unit of s (0 for a fixed obstacle).
        let duration = self.span.map_or(0.0, |(ta, tb)| tb - ta);
        let travel: Vec<f64> = self.scene.obstacles.iter().map(|o| o.velocity.norm() * duration).collect();
        for e in 0..self.elements.list.len() {
            let r = self.elements.rate(e, &lengths, &revolute, speed, 0);
            rates.extend(travel.iter().map(|t| r + t));
        }
        // Two solids move relative to each other only by the joints between their frames
        // (stick segments i < j: joints i..=j, as joint i moves segment i in modified DH and URDF).
        rates.extend(self.sweep_pairs.iter().map(|&(i, j)| self.elements.pair_rate(i, j, &lengths, &revolute, speed)));
        Ok(rates)
    }

    /// Moving obstacles where they are at the instant of `s` (the solids taken relative to
    /// their displacement).
    fn evaluate(&mut self, s: f64, q: &[f64], out: &mut [f64]) -> Result<(), WorldError> {
        self.update(q)?;
        let time = self.time_of(s);
        let tool = self.points[self.points.len() - 1];
        let mut c = 0;
        for z in &self.scene.tool_zone {
            out[c] = -z.shape.point_sdf(&tool);
            c += 1;
        }
        for e in 0..self.elements.list.len() {
            let (centre, radius) = self.elements.spheres[e];
            for (o, bound) in self.scene.obstacles.iter().zip(&self.bounds) {
                let shift = o.displacement(time);
                // A far obstacle: the distance between bounding spheres is a lower bound, which
                // keeps the sweep sound and spares the exact distance (up to 14 point/edge
                // distances for a box, GJK for a cylinder or mesh).
                let far = bound.map(|(c, r)| (c + shift - centre).norm() - r - radius).filter(|lb| {
                    *lb > FAR_BOX && !matches!(o.shape, super::Shape::Sphere { .. } | super::Shape::Point { .. })
                });
                out[c] = far.unwrap_or_else(|| self.elements.obstacle_clearance(e, &o.shape, &shift));
                c += 1;
            }
        }
        for &(i, j) in &self.sweep_pairs {
            out[c] = self.elements.pair_clearance(i, j);
            c += 1;
        }
        Ok(())
    }
}

/// A link as every report names it, its number and its name: ``link 5 (`wrist_2_link`)``.
#[must_use]
pub fn link_label(link: usize, name: &str) -> String {
    format!("link {link} (`{name}`)")
}
