//! Progress bars (indicatif) on stderr for long runs.
//!
//! A bar is shown only when stdout **and** stderr are terminals and the command does not
//! print JSON; otherwise [`Progress`] does nothing, so piped and scripted output is unchanged.

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A progress bar that may be hidden.
#[derive(Debug)]
pub struct Progress {
    bar: Option<ProgressBar>,
}

impl Progress {
    /// A bar over `total` units of work, labelled `message`; hidden in JSON mode or when
    /// stdout or stderr is not a terminal.
    #[must_use]
    pub fn new(total: u64, message: &str, json: bool) -> Self {
        let show = !json && std::io::stdout().is_terminal() && std::io::stderr().is_terminal();
        Self::with_visibility(total, message, show)
    }

    /// A bar shown or hidden as told (for tests and callers that decide themselves).
    #[must_use]
    pub fn with_visibility(total: u64, message: &str, show: bool) -> Self {
        if !show {
            return Progress { bar: None };
        }
        let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
        let style = ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} ({percent}%, eta {eta})")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> ");
        bar.set_style(style);
        bar.set_message(message.to_string());
        Progress { bar: Some(bar) }
    }

    /// Sets the amount of work done (callable from several threads).
    pub fn set(&self, done: u64) {
        if let Some(bar) = &self.bar {
            bar.set_position(done);
        }
    }

    /// Removes the bar from the terminal.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.finish();
    }
}
