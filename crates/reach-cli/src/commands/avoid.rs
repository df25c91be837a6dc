//! `reach avoid` — seed 000's planar detour around point obstacles
//! (`reach::jobs::world::avoid`; `--json` prints its report).

use std::io::Write;

use clap::Args;
use reach::decide::detour_choice::DetourCriterion;
use reach::jobs::world::{AvoidChoice, AvoidReport, AvoidRequest, avoid_run};
use reach::world::detour::DetourOutcome;

use crate::error::CliError;
use crate::numbers::{parse_exact, parse_finite, parse_list};
use crate::output::{Table, fixed, verdict_exit, write_json};
use crate::pose_arg::joints_arg;
use crate::robot_arg::RobotArgs;

/// Arguments of `reach avoid`.
#[derive(Debug, Clone, Args)]
pub struct AvoidArgs {
    /// The robot: a planar three-link arm (`planar3`).
    #[command(flatten)]
    pub robot: RobotArgs,

    /// Current gripper position x,y [m]; the start configuration is the thesis's
    /// minimum-change choice from the home pose (or give --from).
    #[arg(
        long,
        value_name = "X,Y",
        allow_hyphen_values = true,
        conflicts_with = "from",
        required_unless_present = "from"
    )]
    pub from_xy: Option<String>,

    /// Start joint values q1,q2,q3 (degrees, radians with --rad) instead of --from-xy.
    #[arg(long, value_name = "Q1,Q2,Q3", allow_hyphen_values = true)]
    pub from: Option<String>,

    /// --from is in radians instead of degrees.
    #[arg(long)]
    pub rad: bool,

    /// Target gripper position x,y [m].
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    pub to_xy: String,

    /// A point obstacle x,y [m] (repeatable).
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true, conflicts_with = "sensor")]
    pub obstacle: Vec<String>,

    /// Range readings instead of --obstacle (as `reach sense`): the obstacle they locate is
    /// detoured, grown by its uncertainty radius.
    #[command(flatten)]
    pub sensors: crate::commands::sense::SensorArgs,

    /// IK scan step, degrees (thesis: 0.01).
    #[arg(long, default_value = "0.01", value_name = "DEG")]
    pub step: String,

    /// Use the thesis's literal obstacle test (k < 1, fixed order) instead of the robust one.
    #[arg(long)]
    pub literal_test: bool,

    /// Use the printed waypoint formulas (Table 6) instead of the perpendicular construction.
    #[arg(long)]
    pub printed_waypoints: bool,

    /// Plan both sides of the obstacle (base side, the thesis's, and far side) and rank the
    /// ones that succeed with this method: topsis, vikor or weighted-sum. One feasible side is
    /// reported as the only candidate.
    #[arg(long, value_name = "METHOD", conflicts_with = "printed_waypoints")]
    pub choose: Option<String>,

    /// With --choose: criteria from s (Σ S of the legs, less), clearance (more), path_length
    /// (gripper polyline, less); default all three.
    #[arg(long, value_name = "C1,..", requires = "choose")]
    pub criteria: Option<String>,

    /// With --choose: one weight per criterion (default equal).
    #[arg(long, value_name = "W1,..", allow_hyphen_values = true, requires = "choose")]
    pub weights: Option<String>,

    /// Print the report as JSON (docs/schemas/avoid.report.schema.json).
    #[arg(long)]
    pub json: bool,

    /// Drawings of the arm poses: --svg FILE, --png FILE, --png-width PX.
    #[command(flatten)]
    pub draw: crate::plot::DrawArgs,
}

fn xy(option: &str, text: &str) -> Result<[f64; 2], CliError> {
    let v = parse_exact(option, text, 2, "x,y in metres")?;
    Ok([v[0], v[1]])
}

impl AvoidArgs {
    /// The library request.
    ///
    /// # Errors
    /// [`CliError::BadInput`] for malformed numbers or lists.
    pub fn request(&self) -> Result<AvoidRequest, CliError> {
        Ok(AvoidRequest {
            start: self.from.as_deref().map(|t| joints_arg("--from", t, self.rad)).transpose()?,
            from_xy_m: self.from_xy.as_deref().map(|t| xy("--from-xy", t)).transpose()?,
            to_xy_m: xy("--to-xy", &self.to_xy)?,
            obstacles_xy_m: self.obstacle.iter().map(|o| xy("--obstacle", o)).collect::<Result<_, _>>()?,
            step_deg: parse_finite("--step", &self.step)?,
            literal_test: self.literal_test,
            printed_waypoints: self.printed_waypoints,
            sense: self.sensors.request()?,
            choose: self
                .choose
                .as_ref()
                .map(|method| -> Result<AvoidChoice, CliError> {
                    Ok(AvoidChoice {
                        method: method.clone(),
                        criteria: self
                            .criteria
                            .as_deref()
                            .map(|t| t.split(',').map(|c| c.trim().to_string()).collect()),
                        weights: self.weights.as_deref().map(|t| parse_list("--weights", t)).transpose()?,
                    })
                })
                .transpose()?,
        })
    }
}

fn outcome_text(o: &DetourOutcome) -> String {
    match o {
        DetourOutcome::Direct => "direct: no obstacle in the way".into(),
        DetourOutcome::Detour { obstacle } => format!("detour around obstacle {}", obstacle + 1),
        DetourOutcome::TargetUnreachable => "target outside the workspace (L < r < 3L)".into(),
        DetourOutcome::ObstacleTooClose { obstacle } => {
            format!("blocked: obstacle {} is within the detour radius of the start or target", obstacle + 1)
        }
        DetourOutcome::WaypointUnreachable { waypoint, obstacle } => {
            format!("no detour: waypoint K{waypoint} around obstacle {} is out of reach", obstacle + 1)
        }
        DetourOutcome::LegBlocked { leg, obstacle } => {
            format!("no detour: leg {leg} is blocked by obstacle {}", obstacle + 1)
        }
    }
}

/// Plans the move and prints it; exit status 3 (after the report) when the target is
/// unreachable or no detour exists.
///
/// # Errors
/// [`CliError::BadInput`] for bad arguments or a robot that is not a planar 3-link arm;
/// [`CliError::NoSolution`] when no motion was found.
pub fn run(args: &AvoidArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let loaded = args.robot.load()?;
    let robot = &loaded.robot;
    let request = args.request()?;
    args.draw.check_files()?;
    let run = avoid_run(robot, &request).map_err(|e| {
        crate::commands::sense::sensor_error(
            e,
            &[
                ("start", "--from"),
                ("from_xy_m", "--from-xy"),
                ("to_xy_m", "--to-xy"),
                ("obstacles_xy_m", "--obstacle"),
                ("step_deg", "--step"),
                ("choose.criteria", "--criteria"),
                ("choose.weights", "--weights"),
                ("choose", "--choose"),
                ("sense", "--sensor"),
            ],
        )
    })?;
    let report = &run.report;
    if args.draw.any() {
        let title = format!("{}: {}", robot.name(), outcome_text(&report.outcome));
        args.draw.write(&crate::plot::drawings::detour(
            &title,
            &run.arm,
            &run.start,
            &run.plan,
            &run.obstacles,
            run.circle_radius_m,
            run.obstacle_radius_m,
        ))?;
    }
    if args.json {
        write_json(out, report)?;
    } else {
        write_text(report, out)?;
    }
    verdict_exit(out, report.failed().then(|| outcome_text(&report.outcome)))
}

fn write_text(report: &AvoidReport, out: &mut dyn Write) -> Result<(), CliError> {
    let deg3 = |q: &[f64; 3]| q.map(|v| fixed(v, 6)).join(", ");
    let mut head = Table::key_value();
    head.pair("robot", report.robot.clone());
    head.pair("outcome", outcome_text(&report.outcome));
    head.pair("direct move blocked", report.blocked.to_string());
    head.pair("start q [deg]", deg3(&report.start_deg));
    if let Some(s) = &report.sensed {
        head.pair(
            "sensed obstacle",
            format!(
                "({}, {}) m, grown by its uncertainty {} m",
                fixed(s.obstacle_m[0], 6),
                fixed(s.obstacle_m[1], 6),
                s.uncertainty_m.map_or("-".into(), |u| fixed(u, 6))
            ),
        );
    }
    head.pair(
        "min clearance",
        report.closest.map_or("-".into(), |c| {
            format!(
                "{} m (certified ≥ {} m): link {} to obstacle {} at {} % of leg {}",
                fixed(c.clearance_m, 6),
                fixed(c.lower_bound_m, 6),
                c.link,
                c.obstacle + 1,
                fixed(100.0 * c.at, 1),
                c.leg
            )
        }),
    );
    head.write(out, "")?;
    for (i, w) in report.waypoints_m.iter().enumerate() {
        let q = report.configurations_deg.get(i).map_or("-".into(), deg3);
        let s = report.leg_s_deg.get(i).map_or("-".into(), |s| fixed(*s, 6));
        writeln!(out, "  -> ({}, {}) m   q = [{q}] deg   S = {s} deg", fixed(w[0], 6), fixed(w[1], 6))?;
    }
    let (Some(sides), Some(names)) = (&report.sides, &report.criteria) else { return Ok(()) };
    let ok = sides.iter().filter(|s| !s.values.is_empty()).count();
    let note = match ok {
        0 => "no side succeeds".to_string(),
        1 => "one feasible candidate: nothing to rank".to_string(),
        _ => format!("ranked by --choose over {}", names.join(", ")),
    };
    writeln!(out, "sides of the obstacle ({note}):")?;
    for side in sides {
        let values = if side.values.is_empty() {
            "-".to_string()
        } else {
            names
                .iter()
                .zip(&side.values)
                .map(|(n, v)| {
                    let unit = DetourCriterion::parse(n).map_or(String::new(), |c| c.describe().unit);
                    format!("{n} {} {unit}", fixed(*v, 6))
                })
                .collect::<Vec<_>>()
                .join(", ")
        };
        let score = side.score.map_or(String::new(), |s| format!(", score {}", fixed(s, 4)));
        let mark = if side.chosen { "*" } else { " " };
        writeln!(out, "  {mark} {:<9}  {}  [{values}{score}]", side.side, outcome_text(&side.outcome))?;
    }
    Ok(())
}
