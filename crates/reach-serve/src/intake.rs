//! A job's way in: the JSON body → a library [`Request`] (with the one shorthand the service
//! adds) → the library's plan and report → the verdict whether it may move the arm.

use reach::Robot;
use reach::jobs::motion::{ChoiceSpec, IntervalChoice, ProfileName};
use reach::jobs::{Joints, MoveRequest, Report, Request};
use reach::motion::tracking::Decision;
use serde::{Deserialize, Serialize};
use serde_json::Value;

use crate::error::ApiError;

/// The kinds of job the service runs.
pub const ACCEPTED_KINDS: [&str; 6] = ["move", "plan", "path", "approach", "tasks", "avoid"];

/// The issue's shorthand for a joint-space move, read like `reach move`'s options:
/// `{"kind": "move", "from_deg": [...], "to_deg": [...], "duration_s": 6}`. Without
/// `from_deg` the move starts wherever the arm is when the job starts.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct MoveShorthand {
    #[allow(dead_code, reason = "the tag, checked before")]
    kind: String,
    #[serde(default)]
    name: String,
    #[serde(default)]
    from_deg: Option<Vec<f64>>,
    to_deg: Vec<f64>,
    #[serde(default)]
    duration_s: Option<f64>,
    #[serde(default)]
    profile: Option<ProfileName>,
    #[serde(default)]
    dt_s: Option<f64>,
}

impl MoveShorthand {
    /// The library's request for the same move.
    fn request(self) -> MoveRequest {
        let from = self.from_deg.unwrap_or_else(|| vec![0.0; self.to_deg.len()]);
        let mut r = MoveRequest::joints(Joints::Deg(from), Joints::Deg(self.to_deg));
        r.name = self.name;
        r.duration_s = self.duration_s;
        r.profile = self.profile;
        r.dt_s = self.dt_s;
        r
    }
}

/// A job as submitted.
#[derive(Debug, Clone, PartialEq)]
pub struct Submission {
    /// The library request.
    pub request: Request,
    /// A move that starts wherever the arm is when the job starts (the shorthand without
    /// `from_deg`): its `from` is filled in by [`start_here`] before planning.
    pub from_current: bool,
}

/// Reads a job body: a library request (`reach::jobs::Request`, tagged by `kind`), or the move
/// shorthand (`from_deg`/`to_deg`), which is converted here and nowhere else.
///
/// # Errors
/// 400 for text that is not JSON, a missing or unaccepted `kind`, or a request the library's
/// types reject (the message is serde's, naming the field).
pub fn parse_request(body: &[u8]) -> Result<Submission, ApiError> {
    let value: Value =
        serde_json::from_slice(body).map_err(|e| ApiError::bad_request(format!("the body is not JSON: {e}")))?;
    let Some(kind) = value.get("kind").and_then(Value::as_str).map(str::to_string) else {
        return Err(ApiError::bad_request(format!(
            "a job needs a \"kind\" ({}); see GET /openapi.json",
            ACCEPTED_KINDS.join(", ")
        )));
    };
    if !ACCEPTED_KINDS.contains(&kind.as_str()) {
        return Err(ApiError::bad_request(format!(
            "the service does not run jobs of kind `{kind}` (it runs {}); use `reach {kind}` for it",
            ACCEPTED_KINDS.join(", ")
        )));
    }
    if kind == "move" && (value.get("from_deg").is_some() || value.get("to_deg").is_some()) {
        let short: MoveShorthand =
            serde_json::from_value(value).map_err(|e| ApiError::bad_request(format!("move job: {e}")))?;
        let from_current = short.from_deg.is_none();
        return Ok(Submission { request: Request::Move(short.request()), from_current });
    }
    let request = serde_json::from_value(value).map_err(|e| ApiError::bad_request(format!("{kind} job: {e}")))?;
    Ok(Submission { request, from_current: false })
}

/// A move that starts at `q_deg` (the arm's position): sets the request's `from`.
#[must_use]
pub fn start_here(request: &Request, q_deg: &[f64]) -> Request {
    let mut request = request.clone();
    if let Request::Move(m) = &mut request {
        m.from = reach::jobs::motion::End::Joints(Joints::Deg(q_deg.to_vec()));
    }
    request
}

/// The kind of a request, as in its JSON tag.
#[must_use]
pub fn kind_of(request: &Request) -> String {
    serde_json::to_value(request).ok().and_then(|v| v["kind"].as_str().map(str::to_string)).unwrap_or_default()
}

/// Plans a request with the library.
///
/// # Errors
/// 400 with the library's message for bad input (wrong joint count, NaN, unknown field value).
pub fn plan(robot: &Robot, request: &Request) -> Result<Report, ApiError> {
    reach::jobs::run(robot, request).map_err(|e| ApiError::bad_request(e.to_string()))
}

/// Refuses a report too large to store ([`crate::service::MAX_REPORT_BYTES`] of JSON), counted
/// as it is written, without building the text.
///
/// # Errors
/// 400 saying how to make it smaller.
pub fn require_storable(report: &Report) -> Result<(), ApiError> {
    /// Counts bytes; fails once past the limit (so a huge report is not written out).
    struct Counter(usize);
    impl std::io::Write for Counter {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            self.0 += buf.len();
            if self.0 > crate::service::MAX_REPORT_BYTES {
                return Err(std::io::Error::other("too large"));
            }
            Ok(buf.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }
    let mut counter = Counter(0);
    if serde_json::to_writer(&mut counter, report).is_err() {
        let limit = crate::service::MAX_REPORT_BYTES;
        return Err(ApiError::bad_request(format!(
            "the job's report is larger than the {} MiB the service stores per job; sample the motion more coarsely (a larger `dt_s`) or split it",
            limit >> 20
        )));
    }
    Ok(())
}

/// Why a planned job may not move the arm (`None`: it may), from the report alone.
#[must_use]
pub fn refusal(report: &Report) -> Option<String> {
    let reasons = |r: &[String]| if r.is_empty() { "infeasible".to_string() } else { r.join("; ") };
    match report {
        Report::Move(m) if !m.feasible => Some(reasons(&m.reasons)),
        Report::Plan(p) => {
            p.motions.iter().find(|m| !m.feasible).map(|m| format!("motion `{}`: {}", m.name, reasons(&m.reasons)))
        }
        Report::Path(p) if !p.found => Some(p.reason.clone().unwrap_or_else(|| "no path found".into())),
        Report::Path(p) if p.collision_free == Some(false) => {
            Some("the timed path is not proven clear of the scene".into())
        }
        Report::Approach(a) if !a.arrives() => {
            Some(format!("the goal is not reached: {}", a.reason.as_deref().unwrap_or("no motion to it")))
        }
        Report::Approach(a) if a.collision_free == Some(false) => {
            Some("the timed motion is not proven to keep the safe distance".into())
        }
        Report::Tasks(t) if t.plan.is_none() => Some("no plan visits the task's points".into()),
        _ => None,
    }
}

/// One interval of a planned move where the operator may choose the configuration (seed
/// 003's dialogue: several are feasible there).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Question {
    /// The interval, 1-based (what `POST /jobs/{id}/choose` names).
    pub interval: usize,
    /// Its start, seconds into the motion.
    pub start_s: f64,
    /// Its end, seconds.
    pub end_s: f64,
    /// The feasible configurations (labels to answer with).
    pub alternatives: Vec<String>,
    /// The configuration realised without an answer (the default, or the first feasible).
    pub proposed: Option<String>,
}

/// The questions a planned job leaves to the operator: the intervals of a tool-space move
/// with several feasible configurations, when the request gives no criterion (`choose`) and
/// the operator has not chosen there yet. Empty for other jobs (a plan job's intervals are
/// decided by its task file's `[choose]`, else by the default configuration).
#[must_use]
pub fn questions(request: &Request, report: &Report) -> Vec<Question> {
    let (Request::Move(m), Report::Move(r)) = (request, report) else { return Vec::new() };
    if m.choose.is_some() || !r.feasible {
        return Vec::new();
    }
    r.intervals
        .iter()
        .enumerate()
        .filter(|(_, iv)| iv.alternatives.len() > 1 && iv.decision != Some(Decision::Operator))
        .map(|(k, iv)| Question {
            interval: k + 1,
            start_s: iv.start_s,
            end_s: iv.end_s,
            alternatives: iv.alternatives.clone(),
            proposed: iv.configuration.clone(),
        })
        .collect()
}

/// A move with the operator's `choices` added (replacing earlier ones for the same
/// intervals).
#[must_use]
pub fn with_choices(request: &Request, choices: &[IntervalChoice]) -> Request {
    let mut request = request.clone();
    if let Request::Move(m) = &mut request {
        m.choices.retain(|old| choices.iter().all(|new| new.interval != old.interval));
        m.choices.extend(choices.iter().cloned());
        m.choices.sort_by_key(|c| c.interval);
    }
    request
}

/// A move whose intervals are chosen by `criterion` (the service's answer when the operator
/// does not answer in time).
#[must_use]
pub fn with_criterion(request: &Request, criterion: &ChoiceSpec) -> Request {
    let mut request = request.clone();
    if let Request::Move(m) = &mut request {
        m.choose = Some(criterion.clone());
    }
    request
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_move_shorthand_is_the_library_move_request() {
        let short =
            parse_request(br#"{"kind": "move", "from_deg": [0, -90], "to_deg": [90, -60], "duration_s": 6}"#).unwrap();
        let library = parse_request(
            br#"{"kind": "move", "from": {"joints": {"deg": [0, -90]}}, "to": {"joints": {"deg": [90, -60]}}, "duration_s": 6}"#,
        )
        .unwrap();
        assert_eq!(short, library);
        assert!(!short.from_current);
        let here = parse_request(br#"{"kind": "move", "to_deg": [90, -60]}"#).unwrap();
        assert!(here.from_current);
        let Request::Move(m) = start_here(&here.request, &[1.0, 2.0]) else { panic!("a move") };
        assert_eq!(m.from, reach::jobs::motion::End::Joints(Joints::Deg(vec![1.0, 2.0])));
    }

    #[test]
    fn unknown_fields_and_kinds_are_named() {
        let e = parse_request(br#"{"kind": "move", "to_deg": [1], "speed": 3}"#).unwrap_err();
        assert!(e.message.contains("speed"), "{}", e.message);
        let e = parse_request(br#"{"kind": "drive"}"#).unwrap_err();
        assert!(e.message.contains("kind `drive`"), "{}", e.message);
    }
}
