//! `reach tasks` — seed 001's planning tasks on the energy functional J1 (notes 001 §8):
//! *collection* (pick-and-place trips container → object → container) and *visiting* (an
//! open tour of target points), with unreachable points reported and skipped, and the largest
//! number of points that fit a time budget.
//!
//! Every point gets one configuration: the IK solution within limits closest to node 0 (the
//! start configuration, or the container's configuration) by `Σ wᵢ·|Δqᵢ|`, or the rank-1
//! solution of the file's `[choose]` ranking (as `reach ik --choose`). The cost of a move is
//! J1 between configurations (revolute differences wrapped); its duration is the synchronised
//! point-to-point duration within the joint speed limits with the file's profile. With
//! `cost = "energy"` the cost of a move is instead its mechanical energy in joules (Newton–Euler
//! torques with gravity, `∫ Σ|τᵢ·q̇ᵢ| dt` over that synchronised move, 65 samples per leg;
//! robots with link masses only); a move and its reverse cost the same. `cost =
//! "positive_work"` counts only the drives' positive power (`∫ Σ max(τᵢ·q̇ᵢ, 0) dt`, braking
//! free), so lifting costs more than lowering. Visiting is
//! exact (Held–Karp) up to 12 reachable targets, nearest neighbour + 2-opt beyond; collection's
//! total energy does not depend on the order, so only the budget selects (shortest trips first,
//! optimal). See `docs/task-format.md`.
//!
//! Exit status: 0; 2 for bad input, including a task in which no point is reachable; 3 when
//! the container itself is unreachable.

use std::io::Write;
use std::path::PathBuf;

use clap::{Args, ValueEnum};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion};
use reach::Robot;
use reach::decide::sequence::{
    ENERGY_INTERVALS_PER_LEG, EXACT_MAX_TARGETS, EnergyKind, Sequence, collection, collection_within_budget,
    config_costs, energy_costs, leg_durations, visiting, visiting_within_budget,
};
use reach::ik::{IkFailure, IkOptions, IkSolutions, IkSolver, IkTarget, SolverKind};
use reach::motion::JointRates;
use serde::{Deserialize, Serialize};

use super::ik::ChoiceSpec;
use super::move_cmd::{ProfileName, profile_of};
use crate::error::{CliError, one_line};
use crate::numbers::{parse_finite, q_display, q_text, to_si};
use crate::output::{Align, Table, fixed, fixeds, write_json};
use crate::plot::drawings::{Route, tour_top_view};
use crate::plot::{DrawArgs, Svg};

use crate::robot_arg::RobotArgs;

/// Which planning task.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TaskKind {
    /// Trips container → object → container for every object.
    Collection,
    /// One open tour from the start through every target.
    Visiting,
}

/// What a plan minimises (task-file key `cost`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
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

/// Arguments of `reach tasks`.
#[derive(Debug, Clone, Args)]
pub struct TasksArgs {
    /// The robot.
    #[command(flatten)]
    pub robot: RobotArgs,

    /// The task: collection or visiting.
    #[arg(value_name = "TASK_KIND")]
    pub kind: TaskKind,

    /// Task file (TOML, docs/task-format.md "reach tasks").
    #[arg(value_name = "TASK_FILE")]
    pub file: PathBuf,

    /// Time budget in seconds: also report the largest number of points that fit (overrides
    /// the file's `budget_s`).
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub budget: Option<String>,

    /// Print JSON (see docs/task-format.md).
    #[arg(long)]
    pub json: bool,

    /// Draw the plan from above (xy): --svg FILE, --png FILE, --png-width PX.
    #[command(flatten)]
    pub draw: DrawArgs,
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

/// One point of the task in the JSON output.
#[derive(Debug, Clone, Serialize)]
pub struct PointJson {
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
#[derive(Debug, Clone, Serialize)]
pub struct LegJson {
    /// 1-based point number.
    pub point: usize,
    /// J1 of the leg (visiting: from the previous point; collection: container → object →
    /// container), rad.
    pub j1_rad: f64,
    /// With `cost = "energy"` or `"positive_work"`: that energy of the leg (collection: of both
    /// moves of the trip), J.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub energy_j: Option<f64>,
    /// Duration of the leg within the speed limits, seconds (`null` without limits).
    pub duration_s: Option<f64>,
}

/// A plan in the JSON output.
#[derive(Debug, Clone, Serialize)]
pub struct PlanJson {
    /// Point numbers in execution order.
    pub order: Vec<usize>,
    /// Per leg or trip.
    pub legs: Vec<LegJson>,
    /// Σ J1, rad.
    pub total_j1_rad: f64,
    /// With `cost = "energy"` or `"positive_work"`: Σ energy, J (what the plan minimises).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub total_energy_j: Option<f64>,
    /// Σ duration, seconds (`null` without limits).
    pub total_duration_s: Option<f64>,
    /// Whether the plan is provably optimal.
    pub exact: bool,
    /// How it was found.
    pub method: String,
}

/// The JSON output of `reach tasks`.
#[derive(Debug, Clone, Serialize)]
pub struct TasksJson {
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
    /// Node 0: the start (visiting) or container (collection) configuration, degrees.
    pub node0_q_deg: Vec<f64>,
    /// Every point.
    pub points: Vec<PointJson>,
    /// Unreachable point numbers (skipped).
    pub unreachable: Vec<usize>,
    /// The least-energy plan over every reachable point.
    pub plan: PlanJson,
    /// With a budget: the budget, seconds.
    pub budget_s: Option<f64>,
    /// With a budget: the largest number of points that fit, and how.
    pub within_budget: Option<PlanJson>,
}

/// A tool target from 3 numbers (position; with `orientation` a pose) or 6 (pose).
fn target_of(field: &str, v: &[f64], orientation: Option<&[f64]>) -> Result<(IkTarget, PointJson), CliError> {
    if let Some(i) = v.iter().position(|x| !x.is_finite()) {
        return Err(CliError::bad_input(format!("{field}: value {} is not a finite number", i + 1)));
    }
    let (xyz, rpy) = match (v.len(), orientation) {
        (3, None) => ([v[0], v[1], v[2]], None),
        (3, Some(o)) => ([v[0], v[1], v[2]], Some([o[0], o[1], o[2]])),
        (6, _) => ([v[0], v[1], v[2]], Some([v[3], v[4], v[5]])),
        (n, _) => {
            return Err(CliError::bad_input(format!(
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
    Ok((target, PointJson { index: 0, xyz_m: xyz, rpy_deg: rpy, q_deg: None, branch: None, reason: None }))
}

/// How configurations are picked: the closest rule or a `[choose]` ranking.
struct Picker<'a> {
    robot: &'a Robot,
    solver: Box<dyn IkSolver>,
    weights: Vec<f64>,
    choose: Option<&'a ChooseFile>,
}

impl Picker<'_> {
    /// The configuration for `target` relative to `from`, with its branch, or why none.
    /// `choice` is [`Picker::choice`] of the same `from`.
    fn pick(
        &self,
        target: &IkTarget,
        from: &[f64],
        choice: Option<&ChoiceSpec>,
    ) -> Result<Result<(Vec<f64>, String), String>, CliError> {
        let options = IkOptions { seed: Some(from.to_vec()), ..IkOptions::default() };
        let all: IkSolutions = self
            .solver
            .solve(self.robot, target, &options)
            .map_err(|e| CliError::bad_input(format!("IK: {}", one_line(&e.to_string()))))?;
        let index = match (all.closest_index(from, &self.weights), choice) {
            (None, _) => None,
            (Some(i), None) => Some(i),
            (Some(_), Some(spec)) => spec.rank(self.robot, &all)?.ranked.first().map(|e| e.solution),
        };
        Ok(match index {
            Some(i) => Ok((all.solutions[i].q.clone(), all.solutions[i].branch.to_string())),
            None => Err(one_line(&all.failure.unwrap_or(IkFailure::OrientationUnreachable).to_string())),
        })
    }

    /// The `[choose]` ranking relative to `from` (checked), if the file has one.
    fn choice(&self, from: &[f64]) -> Result<Option<ChoiceSpec>, CliError> {
        self.choose.map(|ch| self.spec(ch, from)).transpose()
    }

    fn spec(&self, ch: &ChooseFile, from: &[f64]) -> Result<ChoiceSpec, CliError> {
        let names =
            ch.criteria.clone().unwrap_or_else(|| vec!["change".into(), "limits".into(), "manipulability".into()]);
        ChoiceSpec::new(
            &ch.method,
            &names,
            ch.weights.as_deref(),
            from,
            &self.weights,
            ["[choose] method", "[choose] criteria", "[choose] weights"],
        )
    }
}

/// Runs `reach tasks`.
///
/// # Errors
/// See the module docs.
pub fn run(args: &TasksArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let robot = &args.robot.load()?.robot;
    args.draw.check_files()?;
    let dof = robot.dof();
    let origin = args.file.display().to_string();
    let text = std::fs::read_to_string(&args.file).map_err(|e| CliError::bad_input(format!("{origin}: {e}")))?;
    let file: TasksFile =
        toml::from_str(&text).map_err(|e| CliError::bad_input(format!("{origin}: {}", one_line(&e.to_string()))))?;
    let (points_field, points) = match args.kind {
        TaskKind::Collection => {
            if !file.targets.is_empty() {
                return Err(CliError::bad_input(format!("{origin}: `targets` belong to visiting; use `objects`")));
            }
            ("objects", &file.objects)
        }
        TaskKind::Visiting => {
            if file.container.is_some() || !file.objects.is_empty() {
                return Err(CliError::bad_input(format!(
                    "{origin}: `container`/`objects` belong to collection; use `targets`"
                )));
            }
            ("targets", &file.targets)
        }
    };
    if points.is_empty() {
        return Err(CliError::bad_input(format!("{origin}: `{points_field}` is empty (empty candidate set)")));
    }
    if let Some(o) = &file.orientation
        && (o.len() != 3 || o.iter().any(|v| !v.is_finite()))
    {
        return Err(CliError::bad_input(format!(
            "{origin}: `orientation` needs 3 finite numbers roll,pitch,yaw [deg]"
        )));
    }
    let weights = reach::effort::joint_weights(robot, file.weights.as_deref())
        .map_err(|e| CliError::bad_input(format!("{origin}: `weights` needs {dof} finite joint weights >= 0 ({e})")))?;
    let start = match &file.start {
        Some(v) => {
            if v.len() != dof || v.iter().any(|x| !x.is_finite()) {
                return Err(CliError::bad_input(format!("{origin}: `start` needs {dof} finite joint values [deg]")));
            }
            robot.joints().iter().zip(v).map(|(j, &x)| to_si(j.kind, x, crate::numbers::AngleUnit::Deg)).collect()
        }
        None => robot.home(),
    };
    let rates = match &file.max_velocity {
        Some(v) => {
            if v.len() != dof {
                return Err(CliError::bad_input(format!("{origin}: `max_velocity` needs {dof} values [deg/s]")));
            }
            let si = robot
                .joints()
                .iter()
                .zip(v)
                .map(|(j, &x)| to_si(j.kind, x, crate::numbers::AngleUnit::Deg))
                .collect::<Vec<f64>>();
            Some(JointRates::new(si, None).map_err(|e| CliError::bad_input(format!("{origin}: max_velocity: {e}")))?)
        }
        None => JointRates::from_robot(robot, None).ok(),
    };
    let profile = profile_of(file.profile, ProfileName::Cycloidal)?;
    let budget = match &args.budget {
        Some(t) => Some(parse_finite("--budget", t)?),
        None => file.budget_s,
    };
    if let Some(b) = budget {
        if !b.is_finite() || b < 0.0 {
            return Err(CliError::bad_input(format!(
                "--budget (or budget_s): must be a finite number of seconds >= 0, got {b}"
            )));
        }
        if rates.is_none() {
            return Err(CliError::bad_input(format!(
                "--budget: robot `{}` has no joint speed limits; give `max_velocity` [deg/s] in the task file",
                robot.name()
            )));
        }
    }
    if file.cost != CostKind::J1 {
        let key = if file.cost == CostKind::Energy { "energy" } else { "positive_work" };
        if !robot.has_dynamics() {
            return Err(CliError::bad_input(format!(
                "{origin}: `cost = \"{key}\"`: robot `{}` has no link masses (`inertial` in the robot description); use `cost = \"j1\"` or a robot with masses",
                robot.name()
            )));
        }
        if rates.is_none() {
            return Err(CliError::bad_input(format!(
                "{origin}: `cost = \"{key}\"`: robot `{}` has no joint speed limits to time the moves; give `max_velocity` [deg/s] in the task file",
                robot.name()
            )));
        }
    }
    let kind = SolverKind::detect(robot);
    let picker = Picker {
        robot,
        solver: kind.build(robot).map_err(|e| CliError::bad_input(one_line(&e.to_string())))?,
        weights: weights.clone(),
        choose: file.choose.as_ref(),
    };
    let start_choice = picker.choice(&start)?; // checks the section before solving anything
    // Node 0.
    let node0 = match args.kind {
        TaskKind::Visiting => start.clone(),
        TaskKind::Collection => {
            let Some(c) = &file.container else {
                return Err(CliError::bad_input(format!("{origin}: collection needs `container` = [x, y, z]")));
            };
            let (target, _) = target_of("container", c, file.orientation.as_deref())?;
            match picker.pick(&target, &start, start_choice.as_ref())? {
                Ok((q, _)) => q,
                Err(reason) => return Err(CliError::NoSolution(format!("the container is unreachable: {reason}"))),
            }
        }
    };
    let node0_choice = match args.kind {
        TaskKind::Visiting => start_choice,
        TaskKind::Collection => picker.choice(&node0)?,
    };
    let mut rows = Vec::with_capacity(points.len());
    let mut configs = vec![Some(node0.clone())];
    for (k, p) in points.iter().enumerate() {
        let (target, mut row) = target_of(&format!("{points_field}[{}]", k + 1), p, file.orientation.as_deref())?;
        row.index = k + 1;
        match picker.pick(&target, &node0, node0_choice.as_ref())? {
            Ok((q, branch)) => {
                row.q_deg = Some(q_display(robot, &q).into_iter().map(|v| v + 0.0).collect());
                row.branch = Some(branch);
                configs.push(Some(q));
            }
            Err(reason) => {
                row.reason = Some(reason);
                configs.push(None);
            }
        }
        rows.push(row);
    }
    let unreachable: Vec<usize> = rows.iter().filter(|r| r.reason.is_some()).map(|r| r.index).collect();
    if unreachable.len() == rows.len() {
        let reasons: Vec<String> =
            rows.iter().map(|r| format!("{} ({})", r.index, r.reason.clone().unwrap_or_default())).collect();
        return Err(CliError::bad_input(format!(
            "{origin}: no point of `{points_field}` is reachable: {}",
            reasons.join("; ")
        )));
    }
    let decide = |e: reach::decide::DecideError| CliError::internal(one_line(&e.to_string()));
    let costs = config_costs(robot, configs.clone(), &weights).map_err(decide)?;
    let durations = match &rates {
        None => None,
        Some(r) => Some(leg_durations(robot, &configs, r, profile).map_err(decide)?),
    };
    let energy_kind = match file.cost {
        CostKind::J1 => None,
        CostKind::Energy => Some(EnergyKind::Absolute),
        CostKind::PositiveWork => Some(EnergyKind::PositiveWork),
    };
    let energy = match (energy_kind, &durations) {
        (Some(k), Some(d)) => Some(energy_costs(robot, &configs, d, profile, k).map_err(decide)?),
        _ => None,
    };
    let matrices = Matrices { j1: &costs.costs, energy: energy.as_deref(), durations: durations.as_deref() };
    let c = energy.as_deref().unwrap_or(&costs.costs);
    let plan = match args.kind {
        TaskKind::Visiting => visiting(c),
        TaskKind::Collection => collection(c),
    }
    .map_err(decide)?;
    let within = match (budget, &durations) {
        (Some(b), Some(d)) => Some(
            match args.kind {
                TaskKind::Visiting => visiting_within_budget(c, d, b),
                TaskKind::Collection => collection_within_budget(c, d, b),
            }
            .map_err(decide)?,
        ),
        _ => None,
    };
    let report = TasksJson {
        robot: robot.name().to_string(),
        task: args.kind,
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
        node0_q_deg: q_display(robot, &node0).into_iter().map(|v| v + 0.0).collect(),
        points: rows,
        unreachable,
        plan: plan_json(args.kind, &plan, &matrices, false),
        budget_s: budget,
        within_budget: within.as_ref().map(|s| plan_json(args.kind, s, &matrices, true)),
    };
    if args.draw.any() {
        args.draw.write(&top_view(robot, args.kind, &report, &node0)?)?;
    }
    if args.json {
        return write_json(out, &report);
    }
    write_text(out, robot, &report)
}

/// The plan seen from above: the base, node 0 (the start tool position or the container), the
/// points in plan order (the budget's plan when a budget is given), unreachable points grey.
fn top_view(robot: &Robot, kind: TaskKind, report: &TasksJson, node0: &[f64]) -> Result<Svg, CliError> {
    let xy = |v: &[f64]| [v[0], v[1]];
    let base = xy(robot.base().translation.vector.as_slice());
    let start = xy(robot.fk(node0).map_err(|e| CliError::internal(e.to_string()))?.translation.vector.as_slice());
    let points: Vec<[f64; 2]> = report.points.iter().map(|p| xy(&p.xyz_m)).collect();
    let plan = report.within_budget.as_ref().unwrap_or(&report.plan);
    let order: Vec<usize> = plan.order.iter().map(|&k| k - 1).collect();
    let (route, start_label, what) = match kind {
        TaskKind::Visiting => (Route::Open, "start", "visiting"),
        TaskKind::Collection => (Route::Trips, "container", "collection"),
    };
    let budget = report.budget_s.map_or(String::new(), |b| format!(", budget {b} s"));
    let cost = match plan.total_energy_j {
        Some(e) => format!("energy {e:.2} J"),
        None => format!("J1 {:.4} rad", plan.total_j1_rad),
    };
    let title = format!("{} — {what}: {} of {} points, {cost}{budget}", robot.name(), order.len(), points.len());
    tour_top_view(&title, base, (start, start_label), &points, &order, route)
}

/// The per-leg matrices of a task: J1 (rad), energy (J, with `cost = "energy"`), durations (s).
struct Matrices<'a> {
    j1: &'a [Vec<f64>],
    energy: Option<&'a [Vec<f64>]>,
    durations: Option<&'a [Vec<f64>]>,
}

fn plan_json(kind: TaskKind, s: &Sequence, m: &Matrices<'_>, budget: bool) -> PlanJson {
    let mut prev = 0;
    // A leg from `prev` to `j` (visiting) or the trip to `j` and back (collection).
    let leg = |c: &[Vec<f64>], prev: usize, j: usize| match kind {
        TaskKind::Visiting => c[prev][j],
        TaskKind::Collection => c[0][j] + c[j][0],
    };
    let legs: Vec<LegJson> = s
        .order
        .iter()
        .map(|&j| {
            let l = LegJson {
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
        (TaskKind::Visiting, true, true) => {
            format!(
                "exact: dynamic programming over subsets, most targets then least time (≤ {EXACT_MAX_TARGETS} targets)"
            )
        }
        (TaskKind::Visiting, false, false) => {
            format!("heuristic: nearest neighbour + 2-opt (> {EXACT_MAX_TARGETS} targets; not proven optimal)")
        }
        (TaskKind::Visiting, true, false) => format!(
            "heuristic: longest prefix within budget of the nearest-neighbour + 2-opt tour on durations (> {EXACT_MAX_TARGETS} targets)"
        ),
    };
    PlanJson { order: s.order.clone(), total_j1_rad, total_energy_j, total_duration_s, legs, exact: s.exact, method }
}

fn write_plan(out: &mut dyn Write, kind: TaskKind, p: &PlanJson, points: &[PointJson]) -> Result<(), CliError> {
    let leg = if kind == TaskKind::Collection { "trip" } else { "leg" };
    let energy = p.total_energy_j.is_some();
    let mut columns = vec![
        ("step", Align::Right),
        ("point", Align::Right),
        ("xyz [m]", Align::Left),
        (if kind == TaskKind::Collection { "trip J1 [rad]" } else { "leg J1 [rad]" }, Align::Right),
    ];
    if energy {
        columns.push((if kind == TaskKind::Collection { "trip energy [J]" } else { "leg energy [J]" }, Align::Right));
    }
    columns.push((if kind == TaskKind::Collection { "trip [s]" } else { "leg [s]" }, Align::Right));
    columns.push(("cumulative [s]", Align::Right));
    let mut t = Table::new(&columns);
    let mut cumulative = 0.0;
    for (k, l) in p.legs.iter().enumerate() {
        let point = &points[l.point - 1];
        cumulative += l.duration_s.unwrap_or(0.0);
        let mut row = vec![(k + 1).to_string(), l.point.to_string(), fixeds(&point.xyz_m, 3), fixed(l.j1_rad, 4)];
        if energy {
            row.push(l.energy_j.map_or("-".into(), |e| fixed(e, 3)));
        }
        row.push(l.duration_s.map_or("-".into(), |d| fixed(d, 3)));
        row.push(l.duration_s.map_or("-".into(), |_| fixed(cumulative, 3)));
        t.row(row);
    }
    t.write(out, "  ")?;
    let total_time = p.total_duration_s.map_or(String::new(), |d| format!(", duration {} s", fixed(d, 3)));
    let total_energy = p.total_energy_j.map_or(String::new(), |e| format!(", energy {} J", fixed(e, 3)));
    writeln!(out, "  total: {} {leg}(s), J1 {} rad{total_energy}{total_time}", p.legs.len(), fixed(p.total_j1_rad, 4))?;
    Ok(())
}

fn write_text(out: &mut dyn Write, robot: &Robot, r: &TasksJson) -> Result<(), CliError> {
    if !r.description.is_empty() {
        writeln!(out, "{}", r.description)?;
    }
    let mut head = Table::key_value();
    head.pair("robot", format!("{} ({} joints)", r.robot, robot.dof()));
    let (kind, node) = match r.task {
        TaskKind::Collection => ("collection: trips container -> object -> container", "container q"),
        TaskKind::Visiting => ("visiting: one open tour from the start", "start q"),
    };
    head.pair("task", kind);
    let shown: Vec<f64> = r.node0_q_deg.iter().map(|v| (v * 1e4).round() / 1e4 + 0.0).collect();
    head.pair(node, q_text(robot, &shown));
    head.pair("solver", r.solver.clone());
    head.pair("choice", r.choice.clone());
    head.pair(
        "cost",
        match r.cost {
            CostKind::J1 => {
                "J1 = Σ wᵢ·|Δqᵢ| between configurations [rad]; durations synchronised within the speed limits"
                    .to_string()
            }
            CostKind::Energy => format!(
                "mechanical energy ∫ Σ|τᵢ·q̇ᵢ| dt [J] of each synchronised point-to-point move (Newton–Euler with gravity, {} samples per leg)",
                ENERGY_INTERVALS_PER_LEG + 1
            ),
            CostKind::PositiveWork => format!(
                "positive work ∫ Σ max(τᵢ·q̇ᵢ, 0) dt [J] of each synchronised point-to-point move, braking free (Newton–Euler with gravity, {} samples per leg)",
                ENERGY_INTERVALS_PER_LEG + 1
            ),
        },
    );
    let reachable = r.points.len() - r.unreachable.len();
    head.pair("points", format!("{} ({reachable} reachable, {} unreachable)", r.points.len(), r.unreachable.len()));
    head.write(out, "")?;
    if !r.unreachable.is_empty() {
        writeln!(out, "unreachable (skipped):")?;
        for p in r.points.iter().filter(|p| p.reason.is_some()) {
            writeln!(
                out,
                "  point {} at {} m: {}",
                p.index,
                fixeds(&p.xyz_m, 3),
                p.reason.clone().unwrap_or_default()
            )?;
        }
    }
    writeln!(out, "plan over every reachable point ({}):", r.plan.method)?;
    write_plan(out, r.task, &r.plan, &r.points)?;
    if let (Some(b), Some(p)) = (r.budget_s, &r.within_budget) {
        writeln!(
            out,
            "within the budget of {} s: {} of {reachable} point(s) ({}):",
            fixed(b, 3),
            p.legs.len(),
            p.method
        )?;
        write_plan(out, r.task, p, &r.points)?;
    }
    Ok(())
}
