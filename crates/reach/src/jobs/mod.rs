//! The application layer: one request and one report per workflow, and a pure `run`.
//!
//! Every front end — the `reach` command line, the control service, the Python package, the
//! viewer — runs a workflow by building its request, calling the library, and rendering the
//! report; none of them computes anything of its own. A command's `--json` output *is* its
//! report serialised, and the same request gives the same report from every front end.
//!
//! * [`Request`] (internally tagged by `"kind"`: `{"kind": "fk", "q": {"deg": [...]}}`) and
//!   [`Report`] list every workflow; [`Job`] pairs a request with its robot ([`RobotInput`]:
//!   a preset, or the text of a TOML/URDF description — files are read by the front ends,
//!   parsed here).
//! * [`run`] runs a request on a loaded robot; [`Job::run`] loads the robot first.
//! * Units: see [`input`]. Requests carry joint values in the unit they were typed in;
//!   reports carry `q_deg` (revolute degrees, prismatic metres) and SI where both are useful;
//!   messages quote values in the units of the request.
//! * Every request and report type derives [`schemars::JsonSchema`]; [`schemas`] lists them,
//!   and the generated JSON Schemas are kept in `docs/schemas/` (a test checks they are
//!   current).

pub mod drive;
pub mod dynamics;
pub mod ik;
pub mod input;
pub mod joint_trajectory;
pub mod kinematics;
pub mod model;
pub mod motion;
pub mod planar_scan;
pub mod retime;
pub mod tasks;
pub mod view;
pub mod world;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

pub use drive::{DriveReport, DriveRequest};
pub use dynamics::{DynamicsReport, DynamicsRequest};
pub use ik::{IkReport, IkRequest, IkScanReport, IkScanRequest};
pub use input::{AngleUnit, Joints, LoadedRobot, Pose, PoseReport, RobotInput};
pub use joint_trajectory::JointTrajectory;
pub use kinematics::{FkReport, FkRequest, JacobianReport, JacobianRequest};
pub use model::{ModelReport, ModelRequest, PresetEntry};
pub use motion::{MoveReport, MoveRequest, PlanReport, PlanRequest};
pub use planar_scan::{PlanarScanReport, PlanarScanRequest};
pub use retime::{RetimeReport, RetimeRequest};
pub use tasks::{TasksReport, TasksRequest};
pub use view::{ViewReport, ViewRequest};
pub use world::{
    ApproachReport, ApproachRequest, AvoidReport, AvoidRequest, CheckReport, CheckRequest, CspaceReport, CspaceRequest,
    PathReport, PathRequest, SenseReport, SenseRequest,
};

use crate::Robot;
use crate::error::Result;

/// A workflow's request (the robot is given beside it, see [`Job`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case")]
#[allow(
    clippy::large_enum_variant,
    reason = "a request is built once per job; boxing would only complicate its construction"
)]
pub enum Request {
    /// The robot's parsed model.
    Model(ModelRequest),
    /// Forward kinematics.
    Fk(FkRequest),
    /// The Jacobian and its measures.
    Jacobian(JacobianRequest),
    /// Rigid-body dynamics at one state: inverse-dynamics and gravity torques, mass matrix.
    Dynamics(DynamicsRequest),
    /// One motion in joint or tool space.
    Move(MoveRequest),
    /// Every motion of a task file.
    Plan(PlanRequest),
    /// Inverse kinematics: every solution of a target and the choice among them.
    Ik(IkRequest),
    /// Seed 000's table of configurations of a planar 3-link arm.
    IkScan(IkScanRequest),
    /// Seed 000's scan and minimum-change choice for a planar arm of 3 to 6 links.
    PlanarScan(PlanarScanRequest),
    /// Collisions and clearances of one configuration in a scene.
    Check(CheckRequest),
    /// Seed 000's planar detour around point obstacles.
    Avoid(AvoidRequest),
    /// Seed 000's obstacle located from ultrasonic range readings.
    Sense(SenseRequest),
    /// Seed 004's configuration-space grid (and fitted region).
    Cspace(CspaceRequest),
    /// A collision-free, timed joint-space path through a scene.
    Path(PathRequest),
    /// Seed 004: a motion to a goal that keeps a safe distance from the obstacles.
    Approach(ApproachRequest),
    /// Seed 001's collection and visiting tasks (sequencing, budgets).
    Tasks(TasksRequest),
    /// Stepper step schedules (and G-code, coil tables, step/direction events) for a motion.
    Drive(DriveRequest),
    /// Everything the 3-D viewer draws: states with frames and axes, scene, events, IK ghosts.
    View(ViewRequest),
    /// The time-optimal motion through joint waypoints under velocity and acceleration limits.
    Retime(RetimeRequest),
}

/// A workflow's report, tagged by `"kind"` like its request.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Report {
    /// The robot's parsed model.
    Model(ModelReport),
    /// Forward kinematics.
    Fk(FkReport),
    /// The Jacobian and its measures.
    Jacobian(JacobianReport),
    /// Torques and the mass matrix at one state.
    Dynamics(DynamicsReport),
    /// One motion in joint or tool space.
    Move(MoveReport),
    /// Every motion of a task file.
    Plan(PlanReport),
    /// Inverse kinematics.
    Ik(IkReport),
    /// Seed 000's table of configurations.
    IkScan(IkScanReport),
    /// Seed 000's minimum-change choice for a planar arm of 3 to 6 links.
    PlanarScan(PlanarScanReport),
    /// Collisions and clearances of one configuration in a scene.
    Check(CheckReport),
    /// Seed 000's planar detour around point obstacles.
    Avoid(AvoidReport),
    /// Seed 000's obstacle located from ultrasonic range readings.
    Sense(SenseReport),
    /// Seed 004's configuration-space grid (and fitted region).
    Cspace(CspaceReport),
    /// A collision-free, timed joint-space path through a scene.
    Path(PathReport),
    /// Seed 004's motion that keeps a safe distance from the obstacles.
    Approach(ApproachReport),
    /// Seed 001's collection and visiting tasks (sequencing, budgets).
    Tasks(TasksReport),
    /// Stepper step schedules for a motion.
    Drive(DriveReport),
    /// Everything the 3-D viewer draws.
    View(ViewReport),
    /// The timed motion.
    Retime(RetimeReport),
}

/// A request together with its robot.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Job {
    /// The robot.
    pub robot: RobotInput,
    /// The workflow and its parameters.
    pub request: Request,
}

impl Job {
    /// Loads the robot and runs the request.
    ///
    /// # Errors
    /// As [`RobotInput::load`] and [`run`].
    pub fn run(&self) -> Result<Report> {
        run(&self.robot.load()?.robot, &self.request)
    }
}

/// Runs one request on `robot`. Pure: no file, terminal or network I/O.
///
/// # Errors
/// [`crate::Error`] for bad input, naming the request field. "No solution" and "infeasible"
/// are not errors: they are in the report.
pub fn run(robot: &Robot, request: &Request) -> Result<Report> {
    Ok(match request {
        Request::Model(r) => Report::Model(model::model(robot, r)?),
        Request::Fk(r) => Report::Fk(kinematics::fk(robot, r)?),
        Request::Jacobian(r) => Report::Jacobian(kinematics::jacobian(robot, r)?),
        Request::Dynamics(r) => Report::Dynamics(dynamics::dynamics(robot, r)?),
        Request::Move(r) => Report::Move(motion::move_motion(robot, r)?),
        Request::Plan(r) => Report::Plan(motion::plan(robot, r)?),
        Request::Ik(r) => Report::Ik(ik::ik(robot, r)?),
        Request::IkScan(r) => Report::IkScan(ik::ik_scan(robot, r)?),
        Request::PlanarScan(r) => Report::PlanarScan(planar_scan::planar_scan(robot, r)?),
        Request::Check(r) => Report::Check(world::check(robot, r)?),
        Request::Avoid(r) => Report::Avoid(world::avoid(robot, r)?),
        Request::Sense(r) => Report::Sense(world::sense(robot, r)?),
        Request::Cspace(r) => Report::Cspace(world::cspace(robot, r)?),
        Request::Path(r) => Report::Path(world::path(robot, r)?),
        Request::Approach(r) => Report::Approach(world::approach(robot, r)?),
        Request::Tasks(r) => Report::Tasks(tasks::tasks(robot, r)?),
        Request::Drive(r) => Report::Drive(drive::drive(robot, r)?),
        Request::View(r) => Report::View(view::view(robot, r)?),
        Request::Retime(r) => Report::Retime(retime::retime(robot, r)?),
    })
}

/// The JSON Schema of every request and report, by file name (`fk.request`, `fk.report`, …,
/// `job` for [`Job`], and `joint_trajectory` for the ROS message of `reach retime --ros`,
/// [`JointTrajectory`]), as kept in `docs/schemas/<name>.schema.json`.
#[must_use]
pub fn schemas() -> Vec<(&'static str, serde_json::Value)> {
    fn of<T: JsonSchema>() -> serde_json::Value {
        schemars::schema_for!(T).to_value()
    }
    vec![
        ("job", of::<Job>()),
        ("model.request", of::<ModelRequest>()),
        ("model.report", of::<ModelReport>()),
        ("presets.report", of::<Vec<PresetEntry>>()),
        ("fk.request", of::<FkRequest>()),
        ("fk.report", of::<FkReport>()),
        ("jacobian.request", of::<JacobianRequest>()),
        ("jacobian.report", of::<JacobianReport>()),
        ("move.request", of::<MoveRequest>()),
        ("move.report", of::<MoveReport>()),
        ("plan.request", of::<PlanRequest>()),
        ("plan.report", of::<PlanReport>()),
        ("ik.request", of::<IkRequest>()),
        ("ik.report", of::<IkReport>()),
        ("ik_scan.request", of::<IkScanRequest>()),
        ("ik_scan.report", of::<IkScanReport>()),
        ("planar_scan.request", of::<PlanarScanRequest>()),
        ("planar_scan.report", of::<PlanarScanReport>()),
        ("check.request", of::<CheckRequest>()),
        ("check.report", of::<CheckReport>()),
        ("avoid.request", of::<AvoidRequest>()),
        ("avoid.report", of::<AvoidReport>()),
        ("sense.request", of::<SenseRequest>()),
        ("sense.report", of::<SenseReport>()),
        ("cspace.request", of::<CspaceRequest>()),
        ("cspace.report", of::<CspaceReport>()),
        ("path.request", of::<PathRequest>()),
        ("path.report", of::<PathReport>()),
        ("approach.request", of::<ApproachRequest>()),
        ("approach.report", of::<ApproachReport>()),
        ("tasks.request", of::<TasksRequest>()),
        ("tasks.report", of::<TasksReport>()),
        ("drive.request", of::<DriveRequest>()),
        ("drive.report", of::<DriveReport>()),
        ("dynamics.request", of::<dynamics::DynamicsRequest>()),
        ("dynamics.report", of::<dynamics::DynamicsReport>()),
        ("view.request", of::<ViewRequest>()),
        ("view.report", of::<ViewReport>()),
        ("retime.request", of::<RetimeRequest>()),
        ("retime.report", of::<RetimeReport>()),
        ("joint_trajectory", of::<JointTrajectory>()),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `docs/schemas/` holds exactly the generated schemas. `REACH_BLESS_SCHEMAS=1 cargo test -p
    /// reach schemas_in_docs_are_current` rewrites them after a change to a request or report.
    #[test]
    fn schemas_in_docs_are_current() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/schemas");
        let bless = std::env::var_os("REACH_BLESS_SCHEMAS").is_some();
        let mut stale = Vec::new();
        for (name, schema) in schemas() {
            let path = dir.join(format!("{name}.schema.json"));
            let text = serde_json::to_string_pretty(&schema).unwrap() + "\n";
            if bless {
                std::fs::create_dir_all(&dir).unwrap();
                std::fs::write(&path, &text).unwrap();
            } else if std::fs::read_to_string(&path).ok().as_deref() != Some(text.as_str()) {
                stale.push(name);
            }
        }
        assert!(
            stale.is_empty(),
            "stale schemas in docs/schemas: {stale:?}; run REACH_BLESS_SCHEMAS=1 cargo test -p reach schemas_in_docs_are_current"
        );
    }

    #[test]
    fn a_job_round_trips_through_json() {
        let job: Job = serde_json::from_str(
            r#"{"robot": {"preset": "ur5"}, "request": {"kind": "fk", "q": {"deg": [0, -90, 90, 0, 90, 0]}}}"#,
        )
        .unwrap();
        let Report::Fk(report) = job.run().unwrap() else { panic!("not an fk report") };
        assert_eq!(report.q_deg, vec![0.0, -90.0, 90.0, 0.0, 90.0, 0.0]);
        let unknown = serde_json::from_str::<Job>(
            r#"{"robot": {"preset": "ur5"}, "request": {"kind": "fk", "q": {"deg": [0]}, "extra": 1}}"#,
        );
        assert!(unknown.is_err(), "unknown fields are rejected");
    }
}
