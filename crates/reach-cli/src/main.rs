//! `reach` — the command line of the reach robot kinematics toolkit.
//!
//! `main` parses the arguments ([`cli`]), runs one command ([`commands`]) with a buffered
//! stdout, and turns errors into one line on stderr and an exit status ([`error`]).
//! Reusable pieces for later commands: [`robot_arg`] (the `ROBOT` argument and loading),
//! [`numbers`] (joint values, units, finiteness), [`output`] (formatting, JSON, tables).
// The doc comments of the options are clap's help texts, where `[m]` and `[deg]` are units,
// not links.
#![allow(rustdoc::broken_intra_doc_links)]

mod argv;
mod cli;
mod commands;
mod error;
mod interrupt;
mod numbers;
mod output;
mod plot;
mod pose_arg;
mod robot_arg;

use std::io::{BufWriter, Write};

use clap::{CommandFactory, Parser};

use crate::cli::{Cli, Command};
use crate::error::{CliError, EXIT_INTERNAL, EXIT_OK, one_line};

fn main() {
    install_panic_hook();
    interrupt::install();
    let args = argv::protect_hyphen_values(&Cli::command(), std::env::args_os().collect());
    let cli = Cli::parse_from(args); // usage errors: clap prints them and exits with status 2
    let stdout = std::io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    // Work stopped by Ctrl-C reports the interruption, whatever it returned; for `serve`,
    // Ctrl-C is the normal way to end it.
    let serving = matches!(cli.command, Command::Serve(_));
    let result = run(&cli.command, &mut out)
        .and_then(|()| if serving { Ok(()) } else { interrupt::check() })
        .or_else(|e| interrupt::check().and(Err(e)))
        .and_then(|()| out.flush().map_err(CliError::from));
    let code = match result {
        Ok(()) => EXIT_OK,
        Err(e) => {
            // Drop buffered output without writing it: an error leaves stdout empty.
            let _ = out.into_parts();
            if !e.is_broken_pipe() {
                let _ = writeln!(std::io::stderr(), "error: {}", one_line(&e.to_string()));
            }
            e.exit_code()
        }
    };
    std::process::exit(code);
}

/// Runs one command, writing its output to `out`.
fn run(command: &Command, out: &mut dyn Write) -> Result<(), CliError> {
    match command {
        Command::Robots(args) => commands::robots::run(args, out),
        Command::Robot(sub) => commands::robot_show::run(sub, out),
        Command::Fk(args) => commands::fk::run(args, out),
        Command::Jacobian(args) => commands::jacobian::run(args, out),
        Command::Dynamics(args) => commands::dynamics::run(args, out),
        Command::Ik(args) => commands::ik::run(args, out),
        Command::Demo(args) => commands::demo::run(args, out),
        Command::Drive(args) => commands::drive::run(args, out),
        Command::Check(args) => commands::check::run(args, out),
        Command::Avoid(args) => commands::avoid::run(args, out),
        Command::Sense(args) => commands::sense::run(args, out),
        Command::Cspace(args) => commands::cspace::run(args, out),
        Command::Move(args) => commands::move_cmd::run(args, out),
        Command::Plan(args) => commands::plan::run_plan(args, out),
        Command::Tasks(args) => commands::tasks::run(args, out),
        Command::Path(args) => commands::path::run(args, out),
        Command::Approach(args) => commands::approach::run(args, out),
        Command::Retime(args) => commands::retime::run(args, out),
        Command::Serve(args) => commands::serve::run(args, out),
        Command::Job(args) => commands::job::run(args, out),
        Command::View(args) => commands::view::run(args, out),
    }
}

/// A panic is a bug: report it as one line and exit with status 1, without a backtrace.
fn install_panic_hook() {
    std::panic::set_hook(Box::new(|info| {
        let message = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| (*s).to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown panic".into());
        let place = info.location().map(|l| format!(" at {}:{}", l.file(), l.line())).unwrap_or_default();
        let _ =
            writeln!(std::io::stderr(), "error: internal error: {}{place} (please report this)", one_line(&message));
        std::process::exit(EXIT_INTERNAL);
    }));
}
