//! `reach robot show` — the parsed model of a robot.

use std::io::Write;

use clap::{Args, Subcommand};
use nalgebra::Isometry3;
use reach::model::{Convention, FileUnits, Joint, JointGeometry, JointKind};

use crate::error::CliError;
use reach::jobs::ModelRequest;

use crate::output::{Align, Table, num, nums, rpy_deg, rpy_rad, write_json};
use crate::robot_arg::{LoadedRobot, RobotArgs};

/// Subcommands of `reach robot`.
#[derive(Debug, Clone, Subcommand)]
pub enum RobotCommand {
    /// Print a robot's parsed model: DH table (in the file's units) or URDF joints.
    #[command(
        long_about = "Print a robot's parsed model.\n\n\
            DH/MDH robots are shown as a table in the units of their description file \
            (presets are TOML files, e.g. varan4 is in mm and deg); URDF robots as joint \
            origins (xyz in m, rpy in deg) and axes. With --json, the model report \
            (docs/schemas/model.report.schema.json), every number SI (metres, radians, rad/s \
            or m/s): {\"name\", \"description\", \"convention\", \"joints\": [{\"name\", \
            \"kind\", \"a_m\", \"alpha_rad\", \"d_m\", \"theta_offset_rad\", \"limits\": [lo, hi] \
            or null, \"max_velocity\", \"max_acceleration\", \"max_jerk\", \"home\", \"flip\"}], \"base\": 4x4, \"tool\": 4x4} (URDF \
            joints carry \"origin\": 4x4 and \"axis\": [x, y, z] instead of a/alpha/d/theta). \
            Matrices are row-major.",
        after_help = "Examples:\n  \
            reach robot show puma560\n  \
            reach robot show varan4 --json\n  \
            reach robot show arm.urdf --base base_link --tip tool0"
    )]
    Show(ShowArgs),
}

/// Arguments of `reach robot show`.
#[derive(Debug, Clone, Args)]
pub struct ShowArgs {
    /// The robot.
    #[command(flatten)]
    pub robot: RobotArgs,

    /// Print JSON in SI units instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// Runs a `reach robot …` subcommand.
///
/// # Errors
/// [`CliError::BadInput`] for a robot that cannot be loaded; [`CliError::Output`].
pub fn run(command: &RobotCommand, out: &mut dyn Write) -> Result<(), CliError> {
    match command {
        RobotCommand::Show(args) => show(args, out),
    }
}

fn show(args: &ShowArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let loaded = args.robot.load()?;
    if args.json {
        write_json(out, &reach::jobs::model::model(&loaded.robot, &ModelRequest {})?)
    } else {
        write_human(&loaded, out)
    }
}

/// Display units: the file's (TOML) or metres and degrees (URDF).
struct Units {
    /// Metres per display length unit.
    length: f64,
    /// `m` or `mm`.
    length_name: &'static str,
    /// Radians per display angle unit.
    angle: f64,
    /// `deg` or `rad`.
    angle_name: &'static str,
}

impl Units {
    fn of(file: Option<FileUnits>) -> Self {
        let file = file.unwrap_or_default();
        Units {
            length: file.length.to_si(),
            length_name: file.length.as_str(),
            angle: file.angle.to_si(),
            angle_name: file.angle.as_str(),
        }
    }

    fn length_text(&self, si: f64) -> String {
        num(si / self.length)
    }

    fn angle_text(&self, si: f64) -> String {
        num(si / self.angle)
    }

    /// Scale and unit name of a joint variable.
    fn var(&self, kind: JointKind) -> (f64, &'static str) {
        match kind {
            JointKind::Revolute => (self.angle, self.angle_name),
            JointKind::Prismatic => (self.length, self.length_name),
        }
    }

    fn transform(&self, t: &Isometry3<f64>) -> String {
        let xyz: Vec<f64> = t.translation.vector.iter().map(|v| v / self.length).collect();
        let rpy: Vec<f64> = rpy_rad(&t.rotation).iter().map(|r| r / self.angle).collect();
        format!("xyz [{}] {}   rpy [{}] {}", self.length_name, nums(&xyz), self.angle_name, nums(&rpy))
    }
}

fn convention_line(convention: Convention) -> &'static str {
    match convention {
        Convention::Dh => "dh — standard Denavit–Hartenberg, A = Rz(θ)·Tz(d)·Tx(a)·Rx(α), θ = q + theta",
        Convention::Mdh => {
            "mdh — modified (Craig) DH, A = Rx(α)·Tx(a)·Rz(θ)·Tz(d), θ = q + theta; a and alpha belong to the link before the joint"
        }
        Convention::Urdf => "urdf — joint = fixed origin, then motion about/along the axis",
    }
}

fn write_human(loaded: &LoadedRobot, out: &mut dyn Write) -> Result<(), CliError> {
    let robot = &loaded.robot;
    let u = Units::of(loaded.units);
    let mut head = Table::key_value();
    head.pair("name", robot.name());
    if !robot.description().is_empty() {
        head.pair("description", robot.description());
    }
    head.pair("source", loaded.source.to_string());
    head.pair("convention", convention_line(robot.convention()));
    let units = match loaded.units {
        Some(_) => format!("lengths in {}, angles in {} (as in the file)", u.length_name, u.angle_name),
        None => "lengths in m, angles in deg".to_string(),
    };
    head.pair("units", units);
    head.pair("joints", robot.dof().to_string());
    head.write(out, "")?;
    writeln!(out)?;

    let joint_common = |j: &Joint| -> [String; 4] {
        let (scale, unit) = u.var(j.kind);
        let limits = if j.limits.lower.is_finite() || j.limits.upper.is_finite() {
            format!("{} .. {} {unit}", num(j.limits.lower / scale), num(j.limits.upper / scale))
        } else {
            "unlimited".into()
        };
        let home = format!("{} {unit}", num(j.home / scale));
        let vel = j.max_velocity.map_or_else(|| "-".into(), |v| format!("{} {unit}/s", num(v / scale)));
        let flip = if j.flip { "yes" } else { "no" }.to_string();
        [limits, home, vel, flip]
    };
    let has_links = !robot.links().is_empty();
    let radius_header = format!("radius [{}]", u.length_name);
    if robot.convention() == Convention::Urdf {
        let mut table = Table::new(&[
            ("#", Align::Right),
            ("name", Align::Left),
            ("kind", Align::Left),
            ("origin xyz [m]", Align::Left),
            ("origin rpy [deg]", Align::Left),
            ("axis", Align::Left),
            ("limits", Align::Left),
            ("home", Align::Left),
            ("max velocity", Align::Left),
            ("flip", Align::Left),
        ]);
        for (i, j) in robot.joints().iter().enumerate() {
            let (xyz, rpy, axis) = match &j.geometry {
                JointGeometry::Axis { origin, axis } => {
                    let xyz: Vec<f64> = origin.translation.vector.iter().copied().collect();
                    (nums(&xyz), nums(&rpy_deg(&origin.rotation)), nums(&[axis.x, axis.y, axis.z]))
                }
                JointGeometry::Dh(_) => ("-".into(), "-".into(), "-".into()),
            };
            let [limits, home, vel, flip] = joint_common(j);
            table.row(vec![
                (i + 1).to_string(),
                j.name.clone(),
                j.kind.as_str().into(),
                xyz,
                rpy,
                axis,
                limits,
                home,
                vel,
                flip,
            ]);
        }
        table.write(out, "")?;
    } else {
        let a_h = format!("a [{}]", u.length_name);
        let alpha_h = format!("alpha [{}]", u.angle_name);
        let d_h = format!("d [{}]", u.length_name);
        let theta_h = format!("theta [{}]", u.angle_name);
        let mut columns = vec![
            ("#", Align::Right),
            ("name", Align::Left),
            ("kind", Align::Left),
            (a_h.as_str(), Align::Right),
            (alpha_h.as_str(), Align::Right),
            (d_h.as_str(), Align::Right),
            (theta_h.as_str(), Align::Right),
            ("limits", Align::Left),
            ("home", Align::Left),
            ("max velocity", Align::Left),
            ("flip", Align::Left),
        ];
        if has_links {
            columns.push((radius_header.as_str(), Align::Right));
        }
        let mut table = Table::new(&columns);
        for (i, j) in robot.joints().iter().enumerate() {
            let (a, alpha, d, theta) = match &j.geometry {
                JointGeometry::Dh(p) => {
                    (u.length_text(p.a), u.angle_text(p.alpha), u.length_text(p.d), u.angle_text(p.theta_offset))
                }
                JointGeometry::Axis { .. } => ("-".into(), "-".into(), "-".into(), "-".into()),
            };
            let [limits, home, vel, flip] = joint_common(j);
            let mut row = vec![
                (i + 1).to_string(),
                j.name.clone(),
                j.kind.as_str().into(),
                a,
                alpha,
                d,
                theta,
                limits,
                home,
                vel,
                flip,
            ];
            if let Some(link) = robot.links().get(i) {
                row.push(u.length_text(link.radius));
            }
            table.row(row);
        }
        table.write(out, "")?;
    }
    if robot.joints().iter().any(|j| j.max_acceleration.is_some() || j.max_jerk.is_some()) {
        writeln!(out)?;
        let mut table = Table::new(&[
            ("#", Align::Right),
            ("name", Align::Left),
            ("max acceleration", Align::Left),
            ("max jerk", Align::Left),
        ]);
        for (i, j) in robot.joints().iter().enumerate() {
            let (scale, unit) = u.var(j.kind);
            let shown = |v: Option<f64>, power: &str| {
                v.map_or_else(|| "-".into(), |v| format!("{} {unit}/s{power}", num(v / scale)))
            };
            table.row(vec![
                (i + 1).to_string(),
                j.name.clone(),
                shown(j.max_acceleration, "²"),
                shown(j.max_jerk, "³"),
            ]);
        }
        table.write(out, "")?;
    }
    writeln!(out)?;
    writeln!(out, "base  {}", u.transform(robot.base()))?;
    writeln!(out, "tool  {}", u.transform(robot.tool()))?;
    if robot.has_dynamics() {
        // Mass properties in SI units, centre of mass in each joint's link frame.
        writeln!(out, "dynamics (SI; gravity {} m/s²):", nums(robot.gravity().as_slice()))?;
        for (j, b) in robot.joints().iter().zip(robot.inertials()) {
            let i = &b.inertia;
            writeln!(
                out,
                "  {}: mass {} kg, com {} m, inertia [ixx iyy izz ixy ixz iyz] {} kg·m²",
                j.name,
                num(b.mass),
                nums(b.com.as_slice()),
                nums(&[i[(0, 0)], i[(1, 1)], i[(2, 2)], i[(0, 1)], i[(0, 2)], i[(1, 2)]])
            )?;
        }
    }
    Ok(())
}
