//! `reach approach` — seed 004's motion synthesis next to forbidden zones
//! (`reach::jobs::world::approach`): joint increments to a goal that keep a safe distance
//! from the obstacles; a deadlock is handed over to the planner. `--json` prints its report.

use std::io::Write;

use clap::Args;
use reach::jobs::world::approach::ApproachTiming;
use reach::jobs::world::{ApproachReport, ApproachRequest, FastRegionRequest, approach_with_cancel};

use crate::commands::path::{Ends, SceneMotionArgs, optimal_law_text};
use crate::commands::retime::LimitScaleArgs;
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

    /// How the motion is timed: `optimal` (TOPP-RA along the samples, and the planner's path
    /// after a handover, under the joints' velocity and acceleration limits — their own or
    /// their stepper drives' — proven between samples, with the corners blended, see --blend)
    /// or `none` (the samples only). Default: optimal when every joint has both limits.
    #[arg(long, value_enum, value_name = "LAW")]
    pub timing: Option<ApproachTimingArg>,

    /// Optimal timing: how far the motion may pass from each sample, cutting the corners with
    /// parabolic blends (joint-space distance in radians, metres for prismatic joints; default
    /// 0.1; 0 rests at every sample). The blended path is proven to keep the safe distance; a
    /// blend that is not is tightened.
    #[arg(long, value_name = "TOL", allow_hyphen_values = true)]
    pub blend: Option<String>,

    /// --max-velocity-scale, --max-acceleration-scale (optimal timing).
    #[command(flatten)]
    pub scales: LimitScaleArgs,

    /// Print the report as JSON (docs/schemas/approach.report.schema.json).
    #[arg(long)]
    pub json: bool,
}

/// How `reach approach` times its motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ApproachTimingArg {
    /// Time-optimal under the velocity and acceleration limits.
    Optimal,
    /// Not timed.
    None,
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
        let (max_velocity_scale, max_acceleration_scale) = self.scales.parse()?;
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
            timing: self.timing.map(|t| match t {
                ApproachTimingArg::Optimal => ApproachTiming::Optimal,
                ApproachTimingArg::None => ApproachTiming::None,
            }),
            max_velocity_scale,
            max_acceleration_scale,
            blend_tolerance: self.blend.as_deref().map(|b| parse_finite("--blend", b)).transpose()?,
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
        let [velocity, acceleration] = LimitScaleArgs::FLAGS;
        let fixed = [
            ("safe_distance_m", "--safe-distance"),
            ("max_step_deg", "--max-step"),
            ("fast_region", "--fast-region"),
            ("blend_tolerance", "--blend"),
            ("timing", "--timing"),
            velocity,
            acceleration,
        ];
        args.motion.error(e, &fixed)
    })?;
    if args.json {
        write_json(out, &report)?;
    } else {
        write_report(out, &args.motion.scene, &report)?;
    }
    let reason = if report.failed() {
        Some(format!("goal not reached ({:?}): {}", report.outcome, report.reason.as_deref().unwrap_or_default()))
    } else if report.collision_free == Some(false) {
        Some("the timed motion is not proven to keep the safe distance".to_string())
    } else {
        None
    };
    verdict_exit(out, reason)
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
    if let Some(duration) = r.duration_s {
        let law = optimal_law_text(
            r.max_velocity_scale,
            r.max_acceleration_scale,
            r.blend_tolerance,
            r.worst_velocity_ratio.as_deref(),
            r.worst_acceleration_ratio.as_deref(),
            "samples",
        );
        head.pair("duration", format!("{} s ({law})", fixed(duration, 3)));
    }
    if let Some(p) = &r.swept {
        head.pair(
            "swept check",
            format!(
                "{} (links grown by the safe distance)",
                crate::commands::check::swept_text(&p.swept, Some(p.segment))
            ),
        );
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
