//! Schedule outputs as plain values and strings (no I/O): step rows for CSV and JSON, coil
//! tables, step/direction events and G-code.

use std::fmt::Write as _;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::{DriveError, StepSchedule};
use crate::model::JointKind;

/// One step of one joint, for CSV/JSON output.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct StepRow {
    /// Time of the pulse, s.
    pub t_s: f64,
    /// 1-based joint number.
    pub joint: usize,
    /// Joint name.
    pub name: String,
    /// Motor direction, +1 or −1.
    pub dir: i8,
    /// 1-based number of this step within the joint's schedule.
    pub index: usize,
    /// Step counter after the step.
    pub position: i64,
    /// Coil lines a1 b1 a2 b2 after the step as `0`/`1` (`None` without a coil table).
    pub coils: Option<String>,
}

/// Every step of every joint, ordered by time (then joint number).
#[must_use]
pub fn step_rows(schedule: &StepSchedule) -> Vec<StepRow> {
    let mut rows = Vec::with_capacity(schedule.step_count());
    for j in &schedule.joints {
        for (k, s) in j.steps.iter().enumerate() {
            rows.push(StepRow {
                t_s: s.t,
                joint: j.axis.joint,
                name: j.axis.name.clone(),
                dir: s.dir,
                index: k + 1,
                position: s.position,
                coils: j.axis.coils.map(|c| c.state_at(s.position).bits()),
            });
        }
    }
    rows.sort_by(|a, b| a.t_s.total_cmp(&b.t_s).then(a.joint.cmp(&b.joint)));
    rows
}

/// The schedule as CSV: header `t_s,joint,name,dir,index,position,coils`, one line per step
/// in time order; `coils` is empty for joints without a coil table.
#[must_use]
pub fn to_csv(schedule: &StepSchedule) -> String {
    let rows = step_rows(schedule);
    let mut out = String::with_capacity(48 * (rows.len() + 1));
    out.push_str("t_s,joint,name,dir,index,position,coils\n");
    for r in rows {
        let _ = writeln!(
            out,
            "{:.9},{},{},{},{},{},{}",
            r.t_s,
            r.joint,
            csv_field(&r.name),
            r.dir,
            r.index,
            r.position,
            r.coils.unwrap_or_default()
        );
    }
    out
}

fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n']) { format!("\"{}\"", text.replace('"', "\"\"")) } else { text.to_string() }
}

/// The coil table: for each step, the state of lines a1 b1 a2 b2 of that joint's motor.
/// CSV header `t_s,joint,position,a1,b1,a2,b2`; the first lines give every joint's start state
/// at the start time.
///
/// # Errors
/// [`DriveError::NoCoilTable`] naming the first joint whose driver microsteps.
pub fn coil_table_csv(schedule: &StepSchedule) -> Result<String, DriveError> {
    for j in &schedule.joints {
        if j.axis.coils.is_none() {
            return Err(DriveError::NoCoilTable {
                joint: j.axis.joint,
                name: j.axis.name.clone(),
                microstepping: j.axis.microstepping,
            });
        }
    }
    let mut out = String::from("t_s,joint,position,a1,b1,a2,b2\n");
    let line = |out: &mut String, t: f64, joint: usize, position: i64, lines: [bool; 4]| {
        let b = lines.map(u8::from);
        let _ = writeln!(out, "{t:.9},{joint},{position},{},{},{},{}", b[0], b[1], b[2], b[3]);
    };
    for j in &schedule.joints {
        if let Some(c) = j.axis.coils {
            line(&mut out, schedule.start_time, j.axis.joint, j.start_position, c.state_at(j.start_position).lines);
        }
    }
    for r in step_rows(schedule) {
        let j = &schedule.joints[r.joint - 1];
        if let Some(c) = j.axis.coils {
            line(&mut out, r.t_s, r.joint, r.position, c.state_at(r.position).lines);
        }
    }
    Ok(out)
}

/// One event on a step/direction interface.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StepDirEvent {
    /// Time, s.
    pub t_s: f64,
    /// 1-based joint number.
    pub joint: usize,
    /// `Some(dir)`: set the DIR line to +1 or −1 (issued before the pulse at the same
    /// instant; the driver's direction set-up time, typically ≤ 1 µs, is the firmware's
    /// concern). `None`: one STEP pulse.
    pub dir: Option<i8>,
}

/// The step/direction event stream: a DIR event for every joint at the start and whenever its
/// direction changes, then the STEP pulses, merged in time order.
#[must_use]
pub fn step_dir_events(schedule: &StepSchedule) -> Vec<StepDirEvent> {
    let mut events = Vec::with_capacity(schedule.step_count() + schedule.joints.len());
    for j in &schedule.joints {
        let mut dir = 0i8;
        for s in &j.steps {
            if s.dir != dir {
                dir = s.dir;
                events.push(StepDirEvent { t_s: s.t, joint: j.axis.joint, dir: Some(dir) });
            }
            events.push(StepDirEvent { t_s: s.t, joint: j.axis.joint, dir: None });
        }
    }
    // Stable: a DIR event stays before the pulse it precedes.
    events.sort_by(|a, b| a.t_s.total_cmp(&b.t_s).then(a.joint.cmp(&b.joint)));
    events
}

/// The event stream as text, one event per line: `t_us joint STEP` or `t_us joint DIR +`/`-`,
/// times in whole microseconds from the schedule start.
#[must_use]
pub fn step_dir_text(schedule: &StepSchedule) -> String {
    let mut out = String::from("# t_us joint event\n");
    for e in step_dir_events(schedule) {
        let us = ((e.t_s - schedule.start_time) * 1e6).round() as i64;
        match e.dir {
            Some(d) => {
                let _ = writeln!(out, "{us} {} DIR {}", e.joint, if d > 0 { '+' } else { '-' });
            }
            None => {
                let _ = writeln!(out, "{us} {} STEP", e.joint);
            }
        }
    }
    out
}

/// Which firmware reads the G-code (they differ in the dwell parameter).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum GcodeDialect {
    /// GRBL / grblHAL: `G4 P<seconds>`.
    Grbl,
    /// Marlin: `G4 P<milliseconds>`.
    Marlin,
}

/// Axis letters for joints 1 to 6.
pub const AXIS_LETTERS: [char; 6] = ['X', 'Y', 'Z', 'A', 'B', 'C'];

/// G-code for a GRBL- or Marlin-driven arm that follows `schedule` through the waypoints at
/// `times`.
///
/// # Behavior
/// Joint *i* is axis number *i* of `X Y Z A B C`; one axis unit is one joint **degree** (revolute) or one
/// **millimetre** (prismatic), so the firmware is set up with steps per degree (the header
/// lists the values: GRBL `$100…`, Marlin `M92`). Each waypoint is the position the motors hold
/// at that time (the schedule's step counters, printed with 6 decimals so that the firmware
/// rounds back to the same step), and each `G1` has the feed rate that covers the move in
/// its time interval: `F = 60·‖Δ‖/Δt` in units/min (`G94`, Euclidean over all axes). An
/// interval without motion becomes a dwell `G4`. The header is `G21` (mm) and `G90`
/// (absolute); the arm must stand at the first waypoint (given in a comment).
///
/// # Errors
/// [`DriveError::TooManyAxes`] for more than six joints; [`DriveError::Trajectory`] for fewer
/// than two times or times not increasing.
pub fn gcode(
    schedule: &StepSchedule,
    times: &[f64],
    dialect: GcodeDialect,
    robot_name: &str,
) -> Result<String, DriveError> {
    let n = schedule.joints.len();
    if n > AXIS_LETTERS.len() {
        return Err(DriveError::TooManyAxes(n));
    }
    if times.len() < 2 || times.iter().any(|t| !t.is_finite()) || times.windows(2).any(|w| w[1] <= w[0]) {
        return Err(DriveError::Trajectory("G-code needs at least two finite, increasing waypoint times".into()));
    }
    let unit = |kind: JointKind| match kind {
        JointKind::Revolute => ("deg", 180.0 / std::f64::consts::PI),
        JointKind::Prismatic => ("mm", 1000.0),
    };
    let mut out = String::new();
    let _ = writeln!(out, "; reach drive: {robot_name}, {n} joints, {:.4} s", times[times.len() - 1] - times[0]);
    let _ = writeln!(out, "; 1 axis unit = 1 joint degree (revolute) or 1 mm (prismatic)");
    for j in &schedule.joints {
        let (u, scale) = unit(j.axis.kind);
        let per_unit = j.axis.steps_per_unit / scale;
        let letter = AXIS_LETTERS[j.axis.joint - 1];
        let _ = writeln!(
            out,
            "; {letter} = joint {} ({}): {per_unit:.6} steps/{u}, max {:.4} {u}/min{}{}",
            j.axis.joint,
            j.axis.name,
            60.0 * j.axis.max_step_rate / per_unit,
            j.axis.max_acceleration.map_or(String::new(), |a| format!(", accel {:.4} {u}/s^2", a / per_unit)),
            if j.axis.direction < 0 { ", direction inverted" } else { "" },
        );
    }
    let setting = |grbl: usize| {
        schedule
            .joints
            .iter()
            .map(|j| {
                let per_unit = j.axis.steps_per_unit / unit(j.axis.kind).1;
                match (dialect, grbl) {
                    (GcodeDialect::Grbl, _) => format!("${}={per_unit:.6}", grbl + j.axis.joint - 1),
                    (GcodeDialect::Marlin, _) => format!("{}{per_unit:.6}", AXIS_LETTERS[j.axis.joint - 1]),
                }
            })
            .collect::<Vec<_>>()
            .join(" ")
    };
    match dialect {
        GcodeDialect::Grbl => {
            let _ = writeln!(out, "; GRBL steps per unit: {}", setting(100));
        }
        GcodeDialect::Marlin => {
            let _ = writeln!(out, "; Marlin steps per unit: M92 {}", setting(0));
        }
    }
    let position = |t: f64| -> Vec<f64> {
        schedule
            .joints
            .iter()
            .map(|j| {
                let q = j.axis.joint_value(j.position_at(t));
                unit(j.axis.kind).1 * q
            })
            .collect()
    };
    let axes_text = |p: &[f64]| {
        p.iter().enumerate().map(|(i, v)| format!("{}{}", AXIS_LETTERS[i], fmt6(*v))).collect::<Vec<_>>().join(" ")
    };
    let mut prev = position(times[0]);
    let _ = writeln!(out, "; start: {}", axes_text(&prev));
    out.push_str("G21\nG90\nG94\n");
    let mut dwell = 0.0;
    let flush_dwell = |out: &mut String, dwell: &mut f64| {
        if *dwell > 0.0 {
            match dialect {
                GcodeDialect::Grbl => {
                    let _ = writeln!(out, "G4 P{:.3}", *dwell);
                }
                GcodeDialect::Marlin => {
                    let _ = writeln!(out, "G4 P{:.0}", (*dwell * 1000.0).round().max(1.0));
                }
            }
            *dwell = 0.0;
        }
    };
    for w in times.windows(2) {
        let next = position(w[1]);
        let dt = w[1] - w[0];
        let dist = prev.iter().zip(&next).map(|(a, b)| (b - a) * (b - a)).sum::<f64>().sqrt();
        if dist == 0.0 {
            dwell += dt;
            continue;
        }
        flush_dwell(&mut out, &mut dwell);
        let changed: Vec<String> = next
            .iter()
            .enumerate()
            .filter(|(i, v)| **v != prev[*i])
            .map(|(i, v)| format!("{}{}", AXIS_LETTERS[i], fmt6(*v)))
            .collect();
        let _ = writeln!(out, "G1 {} F{}", changed.join(" "), fmt6(60.0 * dist / dt));
        prev = next;
    }
    flush_dwell(&mut out, &mut dwell);
    Ok(out)
}

/// Six decimals without trailing zeros (`-0` printed as `0`).
fn fmt6(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".to_string() } else { s.to_string() }
}
