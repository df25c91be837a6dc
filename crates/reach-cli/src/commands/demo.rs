//! `reach demo` — a short tour of what `reach` computes, as a list of sections.
//!
//! Each section is a title and a function writing its body; later capabilities (IK,
//! motion, drives) add their section to [`SECTIONS`].

use std::io::Write;

use clap::Args;

use crate::error::CliError;
use crate::numbers::q_text;
use crate::output::write_pose;
use crate::robot_arg::load_preset;

/// Arguments of `reach demo`.
#[derive(Debug, Clone, Args)]
pub struct DemoArgs {}

/// One part of the demo.
pub struct Section {
    /// Heading printed above the section.
    pub title: &'static str,
    /// Writes the section's body.
    pub run: fn(&mut dyn Write) -> Result<(), CliError>,
}

/// The demo's sections, in order.
pub const SECTIONS: &[Section] = &[
    Section { title: "Forward kinematics of every preset at its home pose", run: fk_at_home },
    Section { title: "Inverse kinematics: every solution, with branch labels", run: crate::commands::ik::demo },
    Section {
        title: "Seed 001: joint-space vs tool-space motion (J1, J2)",
        run: crate::commands::move_render::demo_seed001,
    },
    Section {
        title: "Seed 003: tracking a weld in both configurations",
        run: crate::commands::move_render::demo_seed003,
    },
];

/// Runs every section.
///
/// # Errors
/// [`CliError::Output`] when writing fails; [`CliError::Internal`] if a preset breaks.
pub fn run(_args: &DemoArgs, out: &mut dyn Write) -> Result<(), CliError> {
    writeln!(out, "reach demo — robot manipulator kinematics")?;
    writeln!(out, "Units: metres and degrees; rpy means R = Rz(yaw)·Ry(pitch)·Rx(roll); quaternions are w x y z.")?;
    for (i, section) in SECTIONS.iter().enumerate() {
        writeln!(out)?;
        let heading = format!("{}. {}", i + 1, section.title);
        writeln!(out, "{heading}")?;
        writeln!(out, "{}", "=".repeat(heading.chars().count()))?;
        (section.run)(out)?;
    }
    Ok(())
}

/// Section 1: the tool pose of each preset at `Robot::home()`.
fn fk_at_home(out: &mut dyn Write) -> Result<(), CliError> {
    for name in reach::model::presets::names() {
        let robot = load_preset(name)?.robot;
        let fk =
            reach::jobs::kinematics::fk(&robot, &reach::jobs::FkRequest { q: reach::jobs::Joints::Rad(robot.home()) })?;
        writeln!(out)?;
        writeln!(out, "{name} — {} ({} joints)", robot.description(), robot.dof())?;
        writeln!(out, "  {:<12}  {}", "home q", q_text(&robot, &fk.q_deg))?;
        write_pose(out, &fk.pose, "  ")?;
    }
    Ok(())
}
