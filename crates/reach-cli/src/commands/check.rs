//! `reach check` — collisions and clearances of one configuration in a scene.

use std::io::Write;

use clap::Args;
use reach::world::{CollisionChecker, Report, Scene, Verdict};

use crate::error::CliError;
use crate::numbers::{JointArgs, q_text};
use crate::output::{Align, Table, fixed, write_json};
use crate::robot_arg::RobotArgs;

/// Arguments of `reach check`.
#[derive(Debug, Clone, Args)]
pub struct CheckArgs {
    /// The robot.
    #[command(flatten)]
    pub robot: RobotArgs,

    /// Scene file (TOML: obstacles, tool zone, touching policy).
    #[arg(value_name = "SCENE")]
    pub scene: String,

    /// The joint values.
    #[command(flatten)]
    pub joints: JointArgs,

    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Reads and parses a scene file; errors are bad input naming the file.
///
/// # Errors
/// [`CliError::BadInput`] when the file cannot be read or parsed.
pub fn load_scene(path: &str) -> Result<Scene, CliError> {
    let text =
        std::fs::read_to_string(path).map_err(|e| CliError::bad_input(format!("cannot read scene `{path}`: {e}")))?;
    Scene::from_toml_str(&text).map_err(|e| CliError::bad_input(format!("{path}: {e}")))
}

fn verdict_text(v: &Verdict, scene: &Scene) -> String {
    match v {
        Verdict::Free => "free".into(),
        Verdict::OutsideZone { zone } => format!("tool outside zone `{}`", scene.tool_zone[*zone].name),
        Verdict::SelfCollision { link_a, link_b } => format!("self-collision: links {link_a} and {link_b}"),
        Verdict::Obstacle { link, obstacle } => {
            format!("collision: link {link} with `{}`", scene.obstacles[*obstacle].name)
        }
    }
}

/// Checks the configuration and prints the report (exit status 0 whatever the verdict;
/// the verdict is in the output).
///
/// # Errors
/// [`CliError::BadInput`] for a bad robot, scene or joint values; [`CliError::Output`].
pub fn run(args: &CheckArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let loaded = args.robot.load()?;
    let robot = &loaded.robot;
    let scene = load_scene(&args.scene)?;
    let values = args.joints.resolve(robot)?;
    let mut checker = CollisionChecker::new(robot, &scene);
    let report: Report = checker.report(&values.si).map_err(|e| CliError::bad_input(e.to_string()))?;
    if args.json {
        return write_json(out, &report);
    }
    let mut head = Table::key_value();
    head.pair("robot", robot.name().to_string());
    head.pair("q", q_text(robot, &values.deg));
    head.pair("verdict", verdict_text(&report.verdict, &scene));
    let mm = |v: Option<f64>| v.map_or("-".to_string(), |c| format!("{} m", fixed(c, 6)));
    head.pair("min obstacle clearance", mm(report.min_obstacle_clearance_m));
    head.pair("min self clearance", mm(report.min_self_clearance_m));
    head.write(out, "")?;
    if !report.tool_zone.is_empty() {
        writeln!(out, "tool zone (signed distance, negative = inside):")?;
        let mut t = Table::new(&[("zone", Align::Left), ("distance [m]", Align::Right), ("inside", Align::Left)]);
        for z in &report.tool_zone {
            t.row(vec![z.zone.clone(), fixed(z.signed_distance_m, 6), z.inside.to_string()]);
        }
        t.write(out, "  ")?;
    }
    if !report.links.is_empty() {
        writeln!(out, "link clearances (negative = penetration):")?;
        let mut t = Table::new(&[
            ("link", Align::Right),
            ("obstacle", Align::Left),
            ("clearance [m]", Align::Right),
            ("colliding", Align::Left),
        ]);
        for l in &report.links {
            t.row(vec![l.link.to_string(), l.obstacle.clone(), fixed(l.clearance_m, 6), l.colliding.to_string()]);
        }
        t.write(out, "  ")?;
    }
    if !report.self_pairs.is_empty() {
        writeln!(out, "non-adjacent link pairs:")?;
        let mut t = Table::new(&[("links", Align::Left), ("clearance [m]", Align::Right), ("colliding", Align::Left)]);
        for p in &report.self_pairs {
            t.row(vec![format!("{}-{}", p.link_a, p.link_b), fixed(p.clearance_m, 6), p.colliding.to_string()]);
        }
        t.write(out, "  ")?;
    }
    Ok(())
}
