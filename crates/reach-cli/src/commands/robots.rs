//! `reach robots` — the preset robots.

use std::io::Write;

use clap::Args;

use crate::error::CliError;
use crate::output::{Align, Table, write_json};

/// Arguments of `reach robots`.
#[derive(Debug, Clone, Args)]
pub struct RobotsArgs {
    /// Print JSON: `[{"name", "dof", "convention", "description"}]`
    /// (docs/schemas/presets.report.schema.json).
    #[arg(long)]
    pub json: bool,
}

/// Lists every preset with its number of joints and one-line description.
///
/// # Errors
/// [`CliError::Output`] when writing fails; [`CliError::Internal`] if a preset does not parse.
pub fn run(args: &RobotsArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let presets = reach::jobs::model::preset_list()?;
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
        table.row(vec![p.name, p.dof.to_string(), p.convention.as_str().to_string(), p.description]);
    }
    table.write(out, "")
}
