//! Cooperative cancellation of long computations ([`Cancel`]).
//!
//! A front end that lets its user interrupt work (the CLI's Ctrl-C) hands a [`Cancel`] to
//! the few long loops that look at it — the numeric IK solver's starts and iterations
//! ([`crate::ik::IkOptions::cancel`]), the path planner's iterations (through the same IK
//! options of [`crate::world::planner::PlanOptions::ik`]) and the configuration-space grid
//! ([`crate::world::cspace::classify_grid_with_cancel`]) — and sets it from elsewhere
//! (another thread, a signal handler). A cancelled solve or plan ends as if its time budget
//! were spent; a cancelled grid returns [`crate::world::WorldError::Cancelled`]. The front end
//! then reports the interruption itself.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// A cancellation flag: cheap to clone (clones share the flag), `Default` is a flag nobody
/// can set (never cancelled, no allocation).
///
/// # Example
/// ```
/// let cancel = reach::Cancel::new();
/// let seen_by_worker = cancel.clone();
/// assert!(!seen_by_worker.is_cancelled());
/// cancel.cancel();
/// assert!(seen_by_worker.is_cancelled());
/// assert!(!reach::Cancel::default().is_cancelled());
/// ```
#[derive(Debug, Clone, Default)]
pub struct Cancel(Option<Arc<AtomicBool>>);

impl Cancel {
    /// A new flag, not set.
    #[must_use]
    pub fn new() -> Self {
        Cancel(Some(Arc::new(AtomicBool::new(false))))
    }

    /// Sets the flag: every clone sees it from now on (a flag made by `Default` ignores it).
    pub fn cancel(&self) {
        if let Some(flag) = &self.0 {
            flag.store(true, Ordering::Relaxed);
        }
    }

    /// Whether the flag is set (one relaxed atomic load: cheap enough for inner loops).
    #[must_use]
    pub fn is_cancelled(&self) -> bool {
        self.0.as_ref().is_some_and(|flag| flag.load(Ordering::Relaxed))
    }
}

impl PartialEq for Cancel {
    /// Two flags are equal when they are the same flag (or neither can be set).
    fn eq(&self, other: &Self) -> bool {
        match (&self.0, &other.0) {
            (None, None) => true,
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            _ => false,
        }
    }
}
