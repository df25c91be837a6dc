//! `reach approach` — seed 004's motion synthesis next to forbidden zones
//! (`reach::jobs::world::approach`): joint increments to a goal that keep a safe distance
//! from the obstacles; a deadlock is handed over to the planner. `--json` prints its report.

use std::io::Write;

use clap::Args;
use reach::jobs::world::{ApproachReport, ApproachRequest, FastRegionRequest, approach_with_cancel};

use crate::commands::path::{Ends, SceneMotionArgs};
use crate::error::CliError;
use crate::numbers::parse_finite;
use crate::output::{Table, fixed, fixeds, verdict_exit, write_json};

/// Arguments of `reach approach`.
#[derive(Debug, Clone, Args)]
pub struct ApproachArgs {
    /// The robot, the scene, --from, and --to or a goal tool pose (--to-xyz alone is a
    /// position goal: redundant arms, varan4, planar3).
    #[command(flatten)]
    pub motion: SceneMotionArgs,

    /// Safe distance from every obstacle, metres.
    #[arg(long, default_value = "0.05", value_name = "M", allow_hyphen_values = true)]
    pub safe_distance: String,

    /// Largest increment, joint-space norm in degrees.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub max_step: Option<String>,

    /// Do not hand a deadlock over to the planner.
    #[arg(long)]
    pub no_handover: bool,

    /// Fit seed 004's R-function region (15° grid over the last three joints, the others held
    /// at --from) and use it as a fast first test of the candidate increments.
    #[arg(long)]
    pub fast_region: bool,

    /// Print the report as JSON (docs/schemas/approach.report.schema.json).
    #[arg(long)]
    pub json: bool,
}

impl ApproachArgs {
    /// The library request (the scene file read).
    ///
    /// # Errors
    /// [`CliError::BadInput`] for an unreadable scene, malformed numbers, both or neither of
    /// `--to` and `--to-pose`.
    pub fn request(&self) -> Result<ApproachRequest, CliError> {
        let Ends { scene, from, to, to_pose } = self.motion.ends()?;
        let defaults = ApproachRequest::new(scene, from);
        Ok(ApproachRequest {
            to,
            to_pose,
            safe_distance_m: parse_finite("--safe-distance", &self.safe_distance)?,
            max_step_deg: match &self.max_step {
                Some(s) => parse_finite("--max-step", s)?,
                None => defaults.max_step_deg,
            },
            handover: !self.no_handover,
            fast_region: self.fast_region.then(FastRegionRequest::default),
            ..defaults
        })
    }
}

/// Synthesises the motion and prints the report.
///
/// # Errors
/// [`CliError::BadInput`] for bad arguments, robot or scene, a start closer than the safe
/// distance; [`CliError::NoSolution`] (after the report) when the goal is not reached
/// (deadlock or unreachable).
pub fn run(args: &ApproachArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let robot = args.motion.robot.load()?.robot;
    let request = args.request()?;
    let report = approach_with_cancel(&robot, &request, crate::interrupt::cancel()).map_err(|e| {
        let fixed =
            [("safe_distance_m", "--safe-distance"), ("max_step_deg", "--max-step"), ("fast_region", "--fast-region")];
        args.motion.error(e, &fixed)
    })?;
    if args.json {
        write_json(out, &report)?;
    } else {
        write_report(out, &args.motion.scene, &report)?;
    }
    let reason =
        || format!("goal not reached ({:?}): {}", report.outcome, report.reason.as_deref().unwrap_or_default());
    verdict_exit(out, report.failed().then(reason))
}

fn write_report(out: &mut dyn Write, scene: &str, r: &ApproachReport) -> Result<(), CliError> {
    let mut head = Table::key_value();
    head.pair("robot", r.robot.clone());
    head.pair("scene", scene.to_string());
    let outcome = serde_json::to_value(r.outcome).ok().and_then(|v| v.as_str().map(str::to_string)).unwrap_or_default();
    head.pair("outcome", outcome);
    if let Some(reason) = &r.reason {
        head.pair("reason", reason.clone());
    }
    head.pair("samples", r.samples.to_string());
    head.pair("safe distance", format!("{} m", fixed(r.safe_distance_m, 4)));
    if let Some(m) = r.min_margin_m {
        let at = r.closest.as_deref().unwrap_or("");
        head.pair(
            "min margin",
            format!("{} m beyond the safe distance, proven over the whole motion ({at})", fixed(m, 4)),
        );
    }
    if let Some(e) = r.position_error_m {
        head.pair("position error", format!("{} m", fixed(e, 6)));
    }
    if let Some(e) = r.orientation_error_deg {
        head.pair("orientation error", format!("{} deg", fixed(e, 4)));
    }
    if let Some(e) = r.joint_error_deg {
        head.pair("joint error", format!("{} deg", fixed(e, 6)));
    }
    let s = &r.stats;
    head.pair(
        "candidates",
        format!(
            "{} ({} dropped by the fitted region, {} exact swept checks)",
            s.candidates, s.fast_rejected, s.exact_sweeps
        ),
    );
    if let Some(h) = &r.handover {
        let text = if h.found {
            format!("planner found a path ({} waypoints)", h.waypoints_deg.len())
        } else {
            format!("planner found no path: {}", h.reason.as_deref().unwrap_or(""))
        };
        head.pair("handed over", text);
    }
    head.write(out, "")?;
    if let Some(last) = r.motion_deg.last() {
        writeln!(out, "end [deg]: {}", fixeds(last, 3))?;
    }
    if let Some(h) = r.handover.as_ref().filter(|h| h.found) {
        writeln!(out, "planner waypoints [deg]:")?;
        for (k, w) in h.waypoints_deg.iter().enumerate() {
            writeln!(out, "  {:>2}  {}", k + 1, fixeds(w, 3))?;
        }
    }
    Ok(())
}
