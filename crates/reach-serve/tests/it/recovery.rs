//! `Db::open` on a database left by a crash with a job in each status: the queue is paused
//! whenever a job was left not ended (queued included: a start never moves the arm by
//! itself), and the job's message says why.

use reach_serve::db::{Db, JobStatus};
use serde_json::json;

use crate::common::scratch;

const ROBOT: &str = r#"{"preset": "ur5"}"#;

/// Opens the state of `dir` (two joints).
fn open(dir: &std::path::Path) -> Db {
    let names = vec!["a".to_string(), "b".to_string()];
    Db::open(dir, ROBOT, &names, &[0, 0], None).expect("the state opens").0
}

#[test]
fn a_job_not_ended_at_the_crash_pauses_the_queue_on_restart() {
    // (status at the crash, status after the restart, paused after the restart)
    let cases = [
        (JobStatus::Queued, JobStatus::Queued, true),
        (JobStatus::Planning, JobStatus::Queued, true),
        (JobStatus::WaitingOperator, JobStatus::WaitingOperator, true),
        (JobStatus::Executing, JobStatus::Interrupted, true),
        (JobStatus::Done, JobStatus::Done, false),
        (JobStatus::Refused, JobStatus::Refused, false),
        (JobStatus::Stopped, JobStatus::Stopped, false),
    ];
    for (at_crash, after, paused) in cases {
        let dir = scratch(&format!("recovery-{}", at_crash.as_str()));
        let db = open(&dir);
        let behind = db.insert_job("move", &json!({}), true, JobStatus::Done, None, None).unwrap();
        let id = db.insert_job("move", &json!({}), true, at_crash, None, None).unwrap();
        // A job queued behind it, unless the job ended (then nothing is left in the queue).
        let queued = (!at_crash.is_final())
            .then(|| db.insert_job("move", &json!({}), true, JobStatus::Queued, None, None).unwrap());
        assert!(!db.paused().unwrap());
        drop(db); // the crash

        let db = open(&dir);
        let job = db.job(id).unwrap().unwrap();
        assert_eq!(job.status, after, "{at_crash:?}: {job:?}");
        assert_eq!(db.paused().unwrap(), paused, "{at_crash:?} pauses the queue: {paused}");
        if paused {
            let message = job.message.unwrap_or_default();
            assert!(message.contains("the service stopped") && message.contains("POST /resume"), "{message}");
        }
        if let Some(queued) = queued {
            assert_eq!(db.job(queued).unwrap().unwrap().status, JobStatus::Queued);
        }
        assert_eq!(db.job(behind).unwrap().unwrap().status, JobStatus::Done);
        // A second restart finds nothing more to recover: the pause stays as it was.
        drop(db);
        assert_eq!(open(&dir).paused().unwrap(), paused);
    }
}
