//! `tasks`: seed 001's planning tasks on the energy functional J1 (notes 001 §8) —
//! *collection* (pick-and-place trips container → object → container) and *visiting* (an
//! open tour of target points), with unreachable points reported and skipped, and the largest
//! number of points that fit a time budget.
//!
//! Every point gets one configuration: the IK solution within limits closest to node 0 (the
//! start configuration, or the container's configuration) by `Σ wᵢ·|Δqᵢ|`, or the rank-1
//! solution of the file's `[choose]` ranking. The cost of a move is J1 between configurations;
//! its duration is the synchronised point-to-point duration within the joint speed limits with
//! the file's profile. With `cost = "energy"` the cost of a move is its mechanical energy in
//! joules (`∫ Σ|τᵢ·q̇ᵢ| dt` over that synchronised move); `cost = "positive_work"` counts only
//! the drives' positive power. J1, durations and energies all take joint differences by the one
//! rule [`Robot::joint_difference`] (what the joint-space move travels). Visiting is exact
//! (Held–Karp) up to [`EXACT_MAX_TARGETS`] reachable targets, nearest neighbour + 2-opt
//! beyond; collection's total does not depend on the order, so only the budget selects. The
//! file format is `docs/task-format.md` ("reach tasks").

use crate::error::one_line;
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::Robot;
use crate::decide::sequence::{
    EXACT_MAX_TARGETS, EnergyKind, Sequence, collection, collection_within_budget, config_costs, energy_costs,
    leg_durations, visiting, visiting_within_budget,
};
use crate::error::{Error, Result};
use crate::ik::{IkFailure, IkOptions, IkSolver, IkTarget, SolverKind};
use crate::jobs::ik::{IkChoice, IkChoiceMethod, IkCriterionName};
use crate::jobs::input::{AngleUnit, q_display, to_si};
use crate::jobs::motion::ProfileName;
use crate::motion::{JointRates, Profile};

/// Which planning task.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum TaskKind {
    /// Trips container → object → container for every object.
    Collection,
    /// One open tour from the start through every target.
    Visiting,
}

/// What a plan minimises (task-file key `cost`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum CostKind {
    /// Seed 001's J1 = `Σ wᵢ·|Δqᵢ|` between configurations, rad.
    #[default]
    J1,
    /// Mechanical energy `∫ Σ|τᵢ·q̇ᵢ| dt` of the synchronised point-to-point move, J (needs
    /// link masses); braking counted as spent.
    Energy,
    /// Positive work `∫ Σ max(τᵢ·q̇ᵢ, 0) dt` of that move, J (needs link masses); braking free,
    /// so lifting costs more than lowering.
    PositiveWork,
}

/// The request of `reach tasks`.
///
/// JSON: `{"kind": "tasks", "task_kind": "visiting", "task": "<TOML text>", "budget_s": 6}`.
/// Problems inside the task text are reported with the field `task`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TasksRequest {
    /// Collection or visiting.
    pub task_kind: TaskKind,
    /// The task file's text (TOML, `docs/task-format.md` "reach tasks").
    pub task: String,
    /// Time budget in seconds (overrides the file's `budget_s`): also plan the largest number
    /// of points that fit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub budget_s: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct TasksFile {
    #[serde(default)]
    description: String,
    start: Option<Vec<f64>>,
    container: Option<Vec<f64>>,
    #[serde(default)]
    objects: Vec<Vec<f64>>,
    #[serde(default)]
    targets: Vec<Vec<f64>>,
    orientation: Option<Vec<f64>>,
    weights: Option<Vec<f64>>,
    profile: Option<ProfileName>,
    max_velocity: Option<Vec<f64>>,
    budget_s: Option<f64>,
    #[serde(default)]
    cost: CostKind,
    choose: Option<ChooseFile>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ChooseFile {
    method: String,
    criteria: Option<Vec<String>>,
    weights: Option<Vec<f64>>,
}

/// Names of a task file's `[choose]` keys in messages.
const CHOOSE_FIELDS: [&str; 3] = ["[choose] method", "[choose] criteria", "[choose] weights"];

/// One point of the task.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct TaskPointReport {
    /// 1-based point number (as in the file).
    pub index: usize,
    /// Tool position, metres.
    pub xyz_m: [f64; 3],
    /// Tool orientation roll, pitch, yaw in degrees (`null`: position only).
    pub rpy_deg: Option<[f64; 3]>,
    /// The chosen configuration (degrees; prismatic metres), `null` when unreachable.
    pub q_deg: Option<Vec<f64>>,
    /// Branch label of the chosen configuration.
    pub branch: Option<String>,
    /// Why the point is unreachable (`null` when reachable).
    pub reason: Option<String>,
}

/// One leg (visiting) or trip (collection).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct TaskLegReport {
    /// 1-based point number.
    pub point: usize,
    /// J1 of the leg (visiting: from the previous point; collection: container → object →
    /// container), rad.
    pub j1_rad: f64,
    /// With `cost = "energy"` or `"positive_work"`: that energy of the leg (collection: of both
    /// moves of the trip), J.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub energy_j: Option<f64>,
    /// Duration of the leg within the speed limits, seconds (`null` without limits).
    pub duration_s: Option<f64>,
}

/// A plan: an order of points with its costs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct TaskPlanReport {
    /// Point numbers in execution order.
    pub order: Vec<usize>,
    /// Per leg or trip.
    pub legs: Vec<TaskLegReport>,
    /// Σ J1, rad.
    pub total_j1_rad: f64,
    /// With `cost = "energy"` or `"positive_work"`: Σ energy, J (what the plan minimises).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub total_energy_j: Option<f64>,
    /// Σ duration, seconds (`null` without limits).
    pub total_duration_s: Option<f64>,
    /// Whether the plan is provably optimal.
    pub exact: bool,
    /// How it was found.
    pub method: String,
}

/// The report of `reach tasks`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct TasksReport {
    /// Robot name.
    pub robot: String,
    /// `collection` or `visiting`.
    pub task: TaskKind,
    /// The file's description.
    pub description: String,
    /// IK solver.
    pub solver: String,
    /// How each point's configuration was chosen.
    pub choice: String,
    /// What the plan minimises: `j1` (rad), `energy` or `positive_work` (J).
    pub cost: CostKind,
    /// Collection only: why the container is unreachable (then there is no node 0 and no
    /// plan; `null` otherwise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub container_unreachable: Option<String>,
    /// Node 0: the start (visiting) or container (collection) configuration, degrees
    /// (prismatic metres); `null` when the container is unreachable.
    pub node0_q_deg: Option<Vec<f64>>,
    /// The tool position at node 0, metres.
    pub node0_xyz_m: Option<[f64; 3]>,
    /// The robot base position, metres.
    pub base_xyz_m: [f64; 3],
    /// Every point.
    pub points: Vec<TaskPointReport>,
    /// Unreachable point numbers (skipped).
    pub unreachable: Vec<usize>,
    /// The least-cost plan over every reachable point (`null` when the container is
    /// unreachable).
    pub plan: Option<TaskPlanReport>,
    /// With a budget: the budget, seconds.
    pub budget_s: Option<f64>,
    /// With a budget: the largest number of points that fit, and how.
    pub within_budget: Option<TaskPlanReport>,
}

fn file_error(reason: impl Into<String>) -> Error {
    Error::request("task", reason)
}

/// A tool target from 3 numbers (position; with `orientation` a pose) or 6 (pose).
fn target_of(field: &str, v: &[f64], orientation: Option<&[f64]>) -> Result<(IkTarget, TaskPointReport)> {
    if let Some(i) = v.iter().position(|x| !x.is_finite()) {
        return Err(file_error(format!("{field}: value {} is not a finite number", i + 1)));
    }
    let (xyz, rpy) = match (v.len(), orientation) {
        (3, None) => ([v[0], v[1], v[2]], None),
        (3, Some(o)) => ([v[0], v[1], v[2]], Some([o[0], o[1], o[2]])),
        (6, _) => ([v[0], v[1], v[2]], Some([v[3], v[4], v[5]])),
        (n, _) => {
            return Err(file_error(format!(
                "{field}: expected 3 numbers x,y,z [m] or 6 x,y,z [m], roll,pitch,yaw [deg], got {n}"
            )));
        }
    };
    let p = Point3::new(xyz[0], xyz[1], xyz[2]);
    let target = match rpy {
        None => IkTarget::Position(p),
        Some(r) => IkTarget::Pose(Isometry3::from_parts(
            Translation3::from(p.coords),
            UnitQuaternion::from_euler_angles(r[0].to_radians(), r[1].to_radians(), r[2].to_radians()),
        )),
    };
    Ok((target, TaskPointReport { index: 0, xyz_m: xyz, rpy_deg: rpy, q_deg: None, branch: None, reason: None }))
}

/// How configurations are picked: the closest rule or a `[choose]` ranking.
struct Picker<'a> {
    robot: &'a Robot,
    solver: Box<dyn IkSolver>,
    weights: Vec<f64>,
    choose: Option<IkChoice>,
}

impl Picker<'_> {
    /// The configuration for `target` relative to `from` with its branch, or why there is none.
    fn pick(&self, target: &IkTarget, from: &[f64]) -> Result<std::result::Result<(Vec<f64>, String), String>> {
        let options = IkOptions { seed: Some(from.to_vec()), ..IkOptions::default() };
        let all = self.solver.solve(self.robot, target, &options)?;
        let index = match (all.closest_index(from, &self.weights), &self.choose) {
            (None, _) => None,
            (Some(i), None) => Some(i),
            (Some(_), Some(choice)) => choice
                .rank(self.robot, &all, from, &self.weights, CHOOSE_FIELDS, "[choose]")?
                .ranked
                .first()
                .map(|e| e.solution),
        };
        Ok(match index {
            Some(i) => Ok((all.solutions[i].q.clone(), all.solutions[i].branch.to_string())),
            None => Err(one_line(&all.failure.unwrap_or(IkFailure::OrientationUnreachable).to_string())),
        })
    }
}

/// The `[choose]` section as a checked [`IkChoice`].
fn choice_of(ch: &ChooseFile) -> Result<IkChoice> {
    let [method_field, criteria_field, _] = CHOOSE_FIELDS;
    let choice = IkChoice {
        method: IkChoiceMethod::parse(method_field, &ch.method)?,
        criteria: match &ch.criteria {
            None => vec![IkCriterionName::Change, IkCriterionName::Limits, IkCriterionName::Manipulability],
            Some(names) => names.iter().map(|n| IkCriterionName::parse(criteria_field, n)).collect::<Result<_>>()?,
        },
        weights: ch.weights.clone(),
    };
    choice.check(CHOOSE_FIELDS)?;
    Ok(choice)
}

/// A joint vector of the file in degrees (prismatic metres) to SI, checked.
fn joints_of(robot: &Robot, key: &str, v: &[f64], unit: &str) -> Result<Vec<f64>> {
    if v.len() != robot.dof() || v.iter().any(|x| !x.is_finite()) {
        return Err(file_error(format!("`{key}` needs {} finite joint values [{unit}]", robot.dof())));
    }
    Ok(robot.joints().iter().zip(v).map(|(j, &x)| to_si(j.kind, x, AngleUnit::Deg)).collect())
}

/// Runs `reach tasks`: parses the task text, chooses a configuration per point, costs every
/// leg, and sequences (and budgets) the reachable points.
///
/// # Errors
/// [`Error::File`] for task text that is not a task file; [`Error::Request`] naming `task`
/// (the problem inside the file: `` `targets` is empty ``, `[choose] weights`, …), or
/// `budget_s` for a bad budget or one the robot cannot time; a task in which no point is
/// reachable is an error too. An unreachable container is not: it is in the report.
pub fn tasks(robot: &Robot, request: &TasksRequest) -> Result<TasksReport> {
    let file: TasksFile = toml::from_str(&request.task)
        .map_err(|e| Error::File { what: "task file", message: one_line(&e.to_string()) })?;
    let (points_field, points) = match request.task_kind {
        TaskKind::Collection => {
            if !file.targets.is_empty() {
                return Err(file_error("`targets` belong to visiting; use `objects`"));
            }
            ("objects", &file.objects)
        }
        TaskKind::Visiting => {
            if file.container.is_some() || !file.objects.is_empty() {
                return Err(file_error("`container`/`objects` belong to collection; use `targets`"));
            }
            ("targets", &file.targets)
        }
    };
    if points.is_empty() {
        return Err(file_error(format!("`{points_field}` is empty (empty candidate set)")));
    }
    if let Some(o) = &file.orientation
        && (o.len() != 3 || o.iter().any(|v| !v.is_finite()))
    {
        return Err(file_error("`orientation` needs 3 finite numbers roll,pitch,yaw [deg]"));
    }
    let dof = robot.dof();
    let weights = crate::effort::joint_weights(robot, file.weights.as_deref())
        .map_err(|e| file_error(format!("`weights` needs {dof} finite joint weights >= 0 ({e})")))?;
    let start = match &file.start {
        Some(v) => joints_of(robot, "start", v, "deg")?,
        None => robot.home(),
    };
    let rates = match &file.max_velocity {
        Some(v) => {
            if v.len() != dof {
                return Err(file_error(format!("`max_velocity` needs {dof} values [deg/s]")));
            }
            let si = robot.joints().iter().zip(v).map(|(j, &x)| to_si(j.kind, x, AngleUnit::Deg)).collect();
            Some(JointRates::new(si, None).map_err(|e| file_error(format!("max_velocity: {e}")))?)
        }
        None => JointRates::from_robot(robot, None).ok(),
    };
    let profile: Profile = file.profile.unwrap_or(ProfileName::Cycloidal).profile()?;
    let budget = request.budget_s.or(file.budget_s);
    if let Some(b) = budget {
        if !b.is_finite() || b < 0.0 {
            return Err(Error::request("budget_s", format!("must be a finite number of seconds >= 0, got {b}")));
        }
        if rates.is_none() {
            return Err(Error::request(
                "budget_s",
                format!(
                    "robot `{}` has no joint speed limits; give `max_velocity` [deg/s] in the task file",
                    robot.name()
                ),
            ));
        }
    }
    if file.cost != CostKind::J1 {
        let key = if file.cost == CostKind::Energy { "energy" } else { "positive_work" };
        if !robot.has_dynamics() {
            return Err(file_error(format!(
                "`cost = \"{key}\"`: robot `{}` has no link masses (`inertial` in the robot description); use `cost = \"j1\"` or a robot with masses",
                robot.name()
            )));
        }
        if rates.is_none() {
            return Err(file_error(format!(
                "`cost = \"{key}\"`: robot `{}` has no joint speed limits to time the moves; give `max_velocity` [deg/s] in the task file",
                robot.name()
            )));
        }
    }
    let kind = SolverKind::detect(robot);
    let picker = Picker {
        robot,
        solver: kind.build(robot)?,
        weights: weights.clone(),
        choose: file.choose.as_ref().map(choice_of).transpose()?,
    };
    let mut report = TasksReport {
        robot: robot.name().to_string(),
        task: request.task_kind,
        description: file.description.clone(),
        solver: kind.as_str().to_string(),
        choice: match &file.choose {
            None => "closest: least Σ wᵢ·|Δqᵢ| from node 0 within limits".into(),
            Some(ch) => format!(
                "[choose] {} over {}",
                ch.method,
                ch.criteria.as_ref().map_or("change,limits,manipulability".into(), |c| c.join(","))
            ),
        },
        cost: file.cost,
        container_unreachable: None,
        node0_q_deg: None,
        node0_xyz_m: None,
        base_xyz_m: xyz(&robot.base().translation.vector),
        points: Vec::with_capacity(points.len()),
        unreachable: Vec::new(),
        plan: None,
        budget_s: budget,
        within_budget: None,
    };
    let mut targets = Vec::with_capacity(points.len());
    for (k, p) in points.iter().enumerate() {
        let (target, mut row) = target_of(&format!("{points_field}[{}]", k + 1), p, file.orientation.as_deref())?;
        row.index = k + 1;
        targets.push(target);
        report.points.push(row);
    }
    let node0 = match request.task_kind {
        TaskKind::Visiting => start,
        TaskKind::Collection => {
            let Some(c) = &file.container else {
                return Err(file_error("collection needs `container` = [x, y, z]"));
            };
            let (target, _) = target_of("container", c, file.orientation.as_deref())?;
            match picker.pick(&target, &start)? {
                Ok((q, _)) => q,
                Err(reason) => {
                    report.container_unreachable = Some(reason);
                    return Ok(report);
                }
            }
        }
    };
    report.node0_q_deg = Some(display(robot, &node0));
    report.node0_xyz_m = Some(xyz(&robot.fk(&node0)?.translation.vector));
    let mut configs = vec![Some(node0.clone())];
    for (row, target) in report.points.iter_mut().zip(&targets) {
        match picker.pick(target, &node0)? {
            Ok((q, branch)) => {
                row.q_deg = Some(display(robot, &q));
                row.branch = Some(branch);
                configs.push(Some(q));
            }
            Err(reason) => {
                row.reason = Some(reason);
                configs.push(None);
            }
        }
    }
    report.unreachable = report.points.iter().filter(|r| r.reason.is_some()).map(|r| r.index).collect();
    if report.unreachable.len() == report.points.len() {
        let reasons: Vec<String> =
            report.points.iter().map(|r| format!("{} ({})", r.index, r.reason.clone().unwrap_or_default())).collect();
        return Err(file_error(format!("no point of `{points_field}` is reachable: {}", reasons.join("; "))));
    }
    let costs = config_costs(robot, configs.clone(), &weights)?;
    let durations = rates.as_ref().map(|r| leg_durations(robot, &configs, r, profile)).transpose()?;
    let energy_kind = match file.cost {
        CostKind::J1 => None,
        CostKind::Energy => Some(EnergyKind::Absolute),
        CostKind::PositiveWork => Some(EnergyKind::PositiveWork),
    };
    let energy = match (energy_kind, &durations) {
        (Some(k), Some(d)) => Some(energy_costs(robot, &configs, d, profile, k)?),
        _ => None,
    };
    let matrices = Matrices { j1: &costs.costs, energy: energy.as_deref(), durations: durations.as_deref() };
    let c = energy.as_deref().unwrap_or(&costs.costs);
    let plan = match request.task_kind {
        TaskKind::Visiting => visiting(c),
        TaskKind::Collection => collection(c),
    }?;
    let within = match (budget, &durations) {
        (Some(b), Some(d)) => Some(match request.task_kind {
            TaskKind::Visiting => visiting_within_budget(c, d, b),
            TaskKind::Collection => collection_within_budget(c, d, b),
        }?),
        _ => None,
    };
    report.plan = Some(plan_report(request.task_kind, &plan, &matrices, false));
    report.within_budget = within.as_ref().map(|s| plan_report(request.task_kind, s, &matrices, true));
    Ok(report)
}

fn xyz(v: &nalgebra::Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// Display units without negative zeros.
fn display(robot: &Robot, q: &[f64]) -> Vec<f64> {
    q_display(robot, q).into_iter().map(|v| v + 0.0).collect()
}

/// The per-leg matrices of a task: J1 (rad), energy (J), durations (s).
struct Matrices<'a> {
    j1: &'a [Vec<f64>],
    energy: Option<&'a [Vec<f64>]>,
    durations: Option<&'a [Vec<f64>]>,
}

fn plan_report(kind: TaskKind, s: &Sequence, m: &Matrices<'_>, budget: bool) -> TaskPlanReport {
    let mut prev = 0;
    // A leg from `prev` to `j` (visiting) or the trip to `j` and back (collection).
    let leg = |c: &[Vec<f64>], prev: usize, j: usize| match kind {
        TaskKind::Visiting => c[prev][j],
        TaskKind::Collection => c[0][j] + c[j][0],
    };
    let legs: Vec<TaskLegReport> = s
        .order
        .iter()
        .map(|&j| {
            let l = TaskLegReport {
                point: j,
                j1_rad: leg(m.j1, prev, j),
                energy_j: m.energy.map(|e| leg(e, prev, j)),
                duration_s: m.durations.map(|d| leg(d, prev, j)),
            };
            prev = j;
            l
        })
        .collect();
    let total_duration_s = m.durations.map(|_| legs.iter().filter_map(|l| l.duration_s).sum());
    let total_j1_rad = legs.iter().map(|l| l.j1_rad).sum();
    let total_energy_j = m.energy.map(|_| legs.iter().filter_map(|l| l.energy_j).sum());
    let cost = if m.energy.is_some() { "energy" } else { "J1" };
    let method = match (kind, budget, s.exact) {
        (TaskKind::Collection, false, _) => {
            format!("trips in increasing {cost} (the total does not depend on the order)")
        }
        (TaskKind::Collection, true, _) => "shortest trips first (optimal for the count)".into(),
        (TaskKind::Visiting, false, true) => {
            format!("exact: Held–Karp dynamic programming (≤ {EXACT_MAX_TARGETS} targets)")
        }
        (TaskKind::Visiting, true, true) => format!(
            "exact: dynamic programming over subsets, most targets then least time (≤ {EXACT_MAX_TARGETS} targets)"
        ),
        (TaskKind::Visiting, false, false) => {
            format!("heuristic: nearest neighbour + 2-opt (> {EXACT_MAX_TARGETS} targets; not proven optimal)")
        }
        (TaskKind::Visiting, true, false) => format!(
            "heuristic: longest prefix within budget of the nearest-neighbour + 2-opt tour on durations (> {EXACT_MAX_TARGETS} targets)"
        ),
    };
    TaskPlanReport {
        order: s.order.clone(),
        total_j1_rad,
        total_energy_j,
        total_duration_s,
        legs,
        exact: s.exact,
        method,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;

    fn request(kind: TaskKind, task: &str) -> TasksRequest {
        TasksRequest { task_kind: kind, task: task.into(), budget_s: None }
    }

    #[test]
    fn visiting_plans_every_reachable_target_and_skips_the_rest() {
        let ur5 = presets::get("ur5").unwrap();
        let task = "targets = [[0.4, 0.1, 0.3], [5.0, 0.0, 0.0], [0.3, -0.2, 0.4]]\n";
        let r = tasks(&ur5, &request(TaskKind::Visiting, task)).unwrap();
        assert_eq!(r.unreachable, vec![2]);
        let plan = r.plan.unwrap();
        let mut order = plan.order.clone();
        order.sort_unstable();
        assert_eq!(order, vec![1, 3]);
        assert!(plan.exact);
        assert!((plan.total_j1_rad - plan.legs.iter().map(|l| l.j1_rad).sum::<f64>()).abs() < 1e-12);
    }

    #[test]
    fn an_unreachable_container_is_in_the_report_not_an_error() {
        let ur5 = presets::get("ur5").unwrap();
        let task = "container = [9.0, 0.0, 0.0]\nobjects = [[0.4, 0.1, 0.3]]\n";
        let r = tasks(&ur5, &request(TaskKind::Collection, task)).unwrap();
        assert!(r.container_unreachable.is_some());
        assert!(r.plan.is_none() && r.node0_q_deg.is_none());
    }

    #[test]
    fn problems_in_the_file_name_the_task_field() {
        let ur5 = presets::get("ur5").unwrap();
        let e = tasks(&ur5, &request(TaskKind::Visiting, "targets = []\n")).unwrap_err();
        assert!(
            matches!(&e, Error::Request { field, reason } if field == "task" && reason.contains("`targets` is empty"))
        );
        let mut r = request(TaskKind::Visiting, "targets = [[0.4, 0.1, 0.3]]\n");
        r.budget_s = Some(-1.0);
        assert!(matches!(tasks(&ur5, &r).unwrap_err(), Error::Request { field, .. } if field == "budget_s"));
    }
}
