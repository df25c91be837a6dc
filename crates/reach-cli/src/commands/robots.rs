//! `reach robots` — the preset robots.

use std::io::Write;

use clap::Args;
use serde::Serialize;

use crate::error::CliError;
use crate::output::{Align, Table, write_json};
use crate::robot_arg::load_preset;

/// Arguments of `reach robots`.
#[derive(Debug, Clone, Args)]
pub struct RobotsArgs {
    /// Print JSON: `[{"name", "dof", "convention", "description"}]`.
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
struct PresetJson {
    name: String,
    dof: usize,
    convention: &'static str,
    description: String,
}

/// Lists every preset with its number of joints and one-line description.
///
/// # Errors
/// [`CliError::Output`] when writing fails; [`CliError::Internal`] if a preset does not parse.
pub fn run(args: &RobotsArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let presets = reach::model::presets::names()
        .into_iter()
        .map(|name| {
            let robot = load_preset(name)?.robot;
            Ok(PresetJson {
                name: name.to_string(),
                dof: robot.dof(),
                convention: robot.convention().as_str(),
                description: robot.description().to_string(),
            })
        })
        .collect::<Result<Vec<_>, CliError>>()?;
    if args.json {
        return write_json(out, &presets);
    }
    let mut table = Table::new(&[
        ("NAME", Align::Left),
        ("DOF", Align::Right),
        ("CONV", Align::Left),
        ("DESCRIPTION", Align::Left),
    ]);
    for p in presets {
        table.row(vec![p.name, p.dof.to_string(), p.convention.to_string(), p.description]);
    }
    table.write(out, "")
}
