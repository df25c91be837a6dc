//! Ctrl-C: the first one sets the process's [`reach::Cancel`] flag, which the long library
//! loops look at (numeric IK, the path planner, the configuration-space grid); the command
//! then ends with `error: interrupted` and exit status 130 ([`crate::error::EXIT_INTERRUPTED`]).
//! A second Ctrl-C ends the process at once (for work that does not look at the flag).

use std::io::Write;
use std::sync::OnceLock;

use crate::error::{CliError, EXIT_INTERRUPTED};

static CANCEL: OnceLock<reach::Cancel> = OnceLock::new();

/// The process's cancellation flag (shared by every clone).
pub fn cancel() -> &'static reach::Cancel {
    CANCEL.get_or_init(reach::Cancel::new)
}

/// Installs the Ctrl-C handler. A failure to install it (no signal support) leaves Ctrl-C
/// with its default effect, which ends the process: nothing to report.
pub fn install() {
    let flag = cancel().clone();
    let _ = ctrlc::set_handler(move || {
        if flag.is_cancelled() {
            let _ = writeln!(std::io::stderr(), "error: interrupted");
            std::process::exit(EXIT_INTERRUPTED);
        }
        flag.cancel();
    });
}

/// `Err(CliError::Interrupted)` once Ctrl-C was pressed.
///
/// # Errors
/// [`CliError::Interrupted`] after Ctrl-C.
pub fn check() -> Result<(), CliError> {
    if cancel().is_cancelled() { Err(CliError::Interrupted) } else { Ok(()) }
}
