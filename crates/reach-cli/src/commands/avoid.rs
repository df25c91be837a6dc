//! `reach avoid` — seed 000's planar detour around point obstacles.

use std::io::Write;

use clap::Args;
use reach::decide::Method;
use reach::decide::detour_choice::{DetourCriterion, DetourRanking, choose_detour};
use reach::ik::planar::PlanarRedundant;
use reach::world::detour::{DetourOptions, DetourOutcome, SweepTest, WaypointRule, plan_detour};
use serde::Serialize;

use crate::error::CliError;
use crate::numbers::parse_finite;
use crate::output::{Table, fixed, write_json};
use crate::robot_arg::RobotArgs;

/// Arguments of `reach avoid`.
#[derive(Debug, Clone, Args)]
pub struct AvoidArgs {
    /// The robot: a planar three-link arm (`planar3`).
    #[command(flatten)]
    pub robot: RobotArgs,

    /// Current gripper position x,y [m]; the start configuration is the thesis's
    /// minimum-change choice from the home pose (or give --start).
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    pub from: Option<String>,

    /// Start joint values q1,q2,q3 [deg] instead of --from.
    #[arg(long, value_name = "Q1,Q2,Q3", allow_hyphen_values = true)]
    pub start: Option<String>,

    /// Target gripper position x,y [m].
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    pub to: String,

    /// A point obstacle x,y [m] (repeatable).
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    pub obstacle: Vec<String>,

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

    /// Print JSON.
    #[arg(long)]
    pub json: bool,

    /// Drawings of the arm poses: --svg FILE, --png FILE, --png-width PX.
    #[command(flatten)]
    pub draw: crate::plot::DrawArgs,
}

/// One side of the obstacle in the `--choose` output.
#[derive(Debug, Serialize)]
struct SideJson {
    side: &'static str,
    outcome: DetourOutcome,
    /// Criterion values (empty when the side failed).
    values: Vec<f64>,
    /// The method's score when two sides were ranked.
    score: Option<f64>,
    chosen: bool,
}

#[derive(Debug, Serialize)]
struct AvoidJson {
    robot: String,
    outcome: DetourOutcome,
    blocked: bool,
    start_deg: [f64; 3],
    waypoints_m: Vec<[f64; 2]>,
    configurations_deg: Vec<[f64; 3]>,
    leg_s_deg: Vec<f64>,
    min_clearance_m: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    criteria: Option<Vec<String>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    sides: Option<Vec<SideJson>>,
}

fn pair(label: &str, text: &str) -> Result<[f64; 2], CliError> {
    let parts: Vec<&str> = text.split(',').collect();
    if parts.len() != 2 {
        return Err(CliError::bad_input(format!("{label}: expected x,y, got `{text}`")));
    }
    Ok([parse_finite(label, parts[0].trim())?, parse_finite(label, parts[1].trim())?])
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
    let arm = PlanarRedundant::from_robot(robot).map_err(|e| CliError::bad_input(e.to_string()))?;
    let step = parse_finite("--step", &args.step)?;
    if step <= 0.0 {
        return Err(CliError::bad_input(format!("--step must be positive, got {step}")));
    }
    let target = pair("--to", &args.to)?;
    let obstacles = args.obstacle.iter().map(|o| pair("--obstacle", o)).collect::<Result<Vec<_>, _>>()?;
    let start: [f64; 3] = match (&args.start, &args.from) {
        (Some(s), None) => {
            let v: Vec<&str> = s.split(',').collect();
            if v.len() != 3 {
                return Err(CliError::bad_input(format!("--start: expected q1,q2,q3, got `{s}`")));
            }
            let mut q = [0.0; 3];
            for (i, t) in v.iter().enumerate() {
                q[i] = parse_finite("--start", t.trim())?.to_radians();
            }
            q
        }
        (None, Some(f)) => {
            let k = pair("--from", f)?;
            let home = robot.home();
            let plan = plan_detour(
                &arm,
                &[home[0], home[1], home[2]],
                k,
                &[],
                &DetourOptions { step: step.to_radians(), ..DetourOptions::default() },
            )
            .map_err(|e| CliError::bad_input(e.to_string()))?;
            *plan
                .configurations
                .first()
                .ok_or_else(|| CliError::bad_input(format!("--from {f}: outside the workspace")))?
        }
        _ => return Err(CliError::bad_input("give exactly one of --from and --start")),
    };
    let options = DetourOptions {
        step: step.to_radians(),
        sweep_test: if args.literal_test { SweepTest::PaperLiteral } else { SweepTest::Robust },
        waypoints: if args.printed_waypoints { WaypointRule::PaperPrinted } else { WaypointRule::Perpendicular },
        ..DetourOptions::default()
    };
    args.draw.check_files()?;
    let (plan, sides, names) = match &args.choose {
        None => (
            plan_detour(&arm, &start, target, &obstacles, &options).map_err(|e| CliError::bad_input(e.to_string()))?,
            None,
            None,
        ),
        Some(method) => {
            let method = Method::parse(method).ok_or_else(|| {
                CliError::bad_input(format!("--choose: unknown method `{method}` (known: topsis, vikor, weighted-sum)"))
            })?;
            let names: Vec<String> = args
                .criteria
                .as_deref()
                .unwrap_or("s,clearance,path_length")
                .split(',')
                .map(|t| t.trim().into())
                .collect();
            let criteria = names
                .iter()
                .map(|n| {
                    DetourCriterion::parse(n).ok_or_else(|| {
                        CliError::bad_input(format!(
                            "--criteria: unknown criterion `{n}` (known: s, clearance, path_length)"
                        ))
                    })
                })
                .collect::<Result<Vec<_>, _>>()?;
            let weights = match &args.weights {
                Some(t) => t.split(',').map(|w| parse_finite("--weights", w.trim())).collect::<Result<Vec<_>, _>>()?,
                None => vec![1.0; criteria.len()],
            };
            let ranking = DetourRanking { criteria: &criteria, weights: &weights, method };
            let choice = choose_detour(&arm, &start, target, &obstacles, &options, &ranking)
                .map_err(|e| CliError::bad_input(format!("--choose: {e}")))?;
            let score = |i: usize| {
                let r = choice.ranking.as_ref()?;
                let row = choice.successful.iter().position(|&k| k == i)?;
                r.candidate(row).map(|c| c.score)
            };
            let sides = choice
                .candidates
                .iter()
                .enumerate()
                .map(|(i, c)| SideJson {
                    side: c.side,
                    outcome: c.plan.outcome,
                    values: c.values.clone(),
                    score: score(i),
                    chosen: choice.chosen == Some(i),
                })
                .collect();
            let shown = choice.chosen.unwrap_or(0);
            (choice.candidates[shown].plan.clone(), Some(sides), Some(names))
        }
    };
    if args.draw.any() {
        let title = format!("{}: {}", robot.name(), outcome_text(&plan.outcome));
        let radius = options.circle_radius(&arm);
        args.draw.write(&crate::plot::drawings::detour(&title, &arm, &start, &plan, &obstacles, radius))?;
    }
    let deg3 = |q: &[f64; 3]| q.map(f64::to_degrees);
    let failed = !matches!(plan.outcome, DetourOutcome::Direct | DetourOutcome::Detour { .. });
    if args.json {
        write_json(
            out,
            &AvoidJson {
                robot: robot.name().to_string(),
                outcome: plan.outcome,
                blocked: plan.blocked,
                start_deg: deg3(&start),
                waypoints_m: plan.waypoints.clone(),
                configurations_deg: plan.configurations.iter().map(deg3).collect(),
                leg_s_deg: plan.leg_s.iter().map(|s| s.to_degrees()).collect(),
                min_clearance_m: plan.min_clearance,
                criteria: names.clone(),
                sides,
            },
        )?;
    } else {
        let mut head = Table::key_value();
        head.pair("robot", robot.name().to_string());
        head.pair("outcome", outcome_text(&plan.outcome));
        head.pair("direct move blocked", plan.blocked.to_string());
        head.pair("start q [deg]", deg3(&start).map(|v| fixed(v, 6)).join(", "));
        head.pair("min clearance", plan.min_clearance.map_or("-".into(), |c| format!("{} m", fixed(c, 6))));
        head.write(out, "")?;
        for (i, w) in plan.waypoints.iter().enumerate() {
            let q = plan.configurations.get(i).map_or("-".into(), |q| deg3(q).map(|v| fixed(v, 6)).join(", "));
            let s = plan.leg_s.get(i).map_or("-".into(), |s| fixed(s.to_degrees(), 6));
            writeln!(out, "  -> ({}, {}) m   q = [{q}] deg   S = {s} deg", fixed(w[0], 6), fixed(w[1], 6))?;
        }
        if let (Some(sides), Some(names)) = (&sides, &names) {
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
        }
    }
    if failed {
        out.flush()?;
        return Err(CliError::NoSolution(outcome_text(&plan.outcome)));
    }
    Ok(())
}
