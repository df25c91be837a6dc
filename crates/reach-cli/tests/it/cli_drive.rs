//! End-to-end tests of `reach drive`: outputs checked against values derived from the drive
//! data (planar3: 27.78 steps/deg, 500 Hz; seed 000 D8 move φ = (100, 400, 200) in 0.8 s),
//! and the error paths (exit 2 for bad input, 3 for motor limits).

use reach::jobs::drive::{DriveMotion, DriveProgram, DriveRequest, PointToPointRequest};
use reach::jobs::{Job, Joints, Request, RobotInput};

use crate::common::{assert_report, fails, ok, temp_file};

/// Seed 000's D8 move, joint values blank-separated in one argument.
const D8: [&str; 6] = ["drive", "planar3", "--from", "0 0 0", "--to", "3.6 -14.4 -7.2"];

fn d8(extra: &[&str]) -> Vec<String> {
    D8.iter().chain(extra).map(|s| s.to_string()).collect()
}

fn run_vec(args: &[String]) -> String {
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    ok(&refs)
}

#[test]
fn summary_of_the_seed_000_synchronised_move() {
    let text = run_vec(&d8(&[]));
    assert!(text.contains("0.0000 .. 0.8000 s"), "{text}");
    assert!(text.contains("steps       700") || text.contains("700"), "{text}");
    // Rates ω = (125, 500, 250) Hz.
    for rate in ["125.0", "500.0", "250.0"] {
        assert!(text.contains(rate), "{rate} in {text}");
    }
}

#[test]
fn json_csv_events_and_coils() {
    let args = d8(&["--format", "json"]);
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    let request = DriveRequest {
        motion: DriveMotion::PointToPoint(PointToPointRequest {
            from: Joints::Deg(vec![0.0; 3]),
            to: Joints::Deg(vec![3.6, -14.4, -7.2]),
            duration_s: None,
        }),
        program: None,
    };
    let job = Job { robot: RobotInput::Preset("planar3".into()), request: Request::Drive(request.clone()) };
    let v = assert_report(&refs, &job, "drive.report");
    assert_eq!(v["motion"], "point_to_point");
    assert_eq!(v["duration_s"], 0.8);
    let ends: Vec<i64> = v["joints"].as_array().unwrap().iter().map(|j| j["end_position"].as_i64().unwrap()).collect();
    assert_eq!(ends, [100, -400, -200]);
    assert_eq!(v["steps"].as_array().unwrap().len(), 700);
    assert_eq!(v["check"]["within_one_step"], true);
    // 3.6°, −14.4°, −7.2° are whole steps (100, −400, −200): no rounding of the target.
    assert!(v["target_grid_error"]["tool_position_error"].as_f64().unwrap() < 1e-12);
    let csv = run_vec(&d8(&["--format", "csv"]));
    assert_eq!(csv.lines().count(), 701);
    assert!(csv.starts_with("t_s,joint,name,dir,index,position,coils\n0.002000000,2,B,-1,1,-1,0001\n"), "{csv}");
    let events = run_vec(&d8(&["--format", "events"]));
    assert_eq!(events.lines().filter(|l| l.ends_with("STEP")).count(), 700);
    assert_eq!(events.lines().filter(|l| l.contains("DIR")).count(), 3);
    let coils = run_vec(&d8(&["--format", "coils"]));
    assert_eq!(coils.lines().count(), 1 + 3 + 700);
    // A service asks for the program in the request: the same text as the command line.
    let gcode =
        DriveRequest { program: Some(DriveProgram::Gcode(reach::drive::output::GcodeDialect::Marlin)), ..request };
    let program = reach::jobs::drive::drive(&reach::model::presets::get("planar3").unwrap(), &gcode).unwrap().program;
    assert_eq!(program.as_deref(), Some(run_vec(&d8(&["--format", "gcode", "--dialect", "marlin"])).as_str()));
}

#[test]
fn gcode_to_a_file_and_comma_lists() {
    let path = temp_file("move.gcode", "");
    let args = [
        "drive",
        "planar3",
        "--from",
        "0,0,0",
        "--to",
        "90,-45,-30",
        "--format",
        "gcode",
        "-o",
        path.to_str().unwrap(),
    ];
    let note = ok(&args);
    assert!(note.starts_with("wrote ") && note.contains("move.gcode"), "{note}");
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("G21\nG90\n"));
    let last = text.lines().rev().find(|l| l.starts_with("G1")).unwrap();
    // 90° = 2500 steps exactly; −45° = −1250; −30° = −833.33 → −833 steps = −29.988°.
    assert!(last.contains("X90") && last.contains("Y-45") && last.contains("Z-29.988"), "{last}");
    for line in text.lines().filter(|l| l.starts_with("G1")) {
        let feed: f64 = line.split_whitespace().find_map(|w| w.strip_prefix('F')).unwrap().parse().unwrap();
        assert!(feed > 0.0);
    }
}

#[test]
fn motion_files() {
    // 2 s linear move of joint 1 by 18° = 500 steps: 250 Hz.
    let good = temp_file("m.json", r#"{"samples": [{"t_s": 0, "q_deg": [0, 0, 0]}, {"t_s": 2, "q_deg": [18, 0, 0]}]}"#);
    let v: serde_json::Value =
        serde_json::from_str(&ok(&["drive", "planar3", good.to_str().unwrap(), "--format", "json"])).unwrap();
    assert_eq!(v["joints"][0]["end_position"], 500);
    assert!((v["joints"][0]["max_rate_hz"].as_f64().unwrap() - 250.0).abs() < 1e-6);
    // Too fast: 18° in 0.5 s = 1000 Hz → exit 3 naming joint 1 and a 1 s duration.
    let fast =
        temp_file("f.json", r#"{"samples": [{"t_s": 0, "q_deg": [0, 0, 0]}, {"t_s": 0.5, "q_deg": [18, 0, 0]}]}"#);
    fails(&["drive", "planar3", fast.to_str().unwrap()], 3, &["joint 1 (O)", "1.0000 s"]);
    let broken = temp_file("b.json", r#"{"samples": [{"t_s": 0}]}"#);
    fails(&["drive", "planar3", broken.to_str().unwrap()], 2, &["motion file"]);
}

#[test]
fn task_files() {
    // Two joint-space moves of 2 s each, the second starting where the first ends: one
    // trajectory of 4 s; joint 1 goes 0 → 18° → 0 (500 steps out, 500 back: zero net steps).
    let task = temp_file(
        "task.toml",
        "robot = \"planar3\"\n[defaults]\nduration = 2.0\ndt = 0.05\n\
         [[motion]]\nfrom = [0, 0, 0]\nto = [18, -9, 0]\n\
         [[motion]]\nfrom = [18, -9, 0]\nto = [0, 0, 0]\n",
    );
    let v: serde_json::Value =
        serde_json::from_str(&ok(&["drive", "planar3", task.to_str().unwrap(), "--format", "json"])).unwrap();
    assert!((v["duration_s"].as_f64().unwrap() - 4.0).abs() < 1e-9, "{}", v["duration_s"]);
    assert_eq!(v["joints"][0]["end_position"], 0);
    assert_eq!(v["joints"][0]["steps"], 1000);
    assert_eq!(v["joints"][1]["steps"], 500);
    assert!(v["joints"][0]["max_deviation_steps"].as_f64().unwrap() <= 1.0);
    // A motion that does not start where the previous one ended cannot be driven.
    let gap = temp_file(
        "gap.toml",
        "robot = \"planar3\"\n[defaults]\nduration = 2.0\n\
         [[motion]]\nfrom = [0, 0, 0]\nto = [18, 0, 0]\n\
         [[motion]]\nfrom = [0, 0, 0]\nto = [9, 0, 0]\n",
    );
    fails(&["drive", "planar3", gap.to_str().unwrap()], 2, &["motion 2", "joint 1", "cannot jump"]);
    // The task names another robot.
    let other = temp_file("other.toml", "robot = \"log-loader\"\n[[motion]]\nfrom = [0, 0, 0]\nto = [9, 0, 0]\n");
    fails(&["drive", "planar3", other.to_str().unwrap()], 2, &["log-loader", "planar3"]);
    // Too fast for the motors: exit 3 from the schedule check.
    let fast =
        temp_file("fast.toml", "robot = \"planar3\"\n[[motion]]\nfrom = [0, 0, 0]\nto = [90, 0, 0]\nduration = 0.5\n");
    fails(&["drive", "planar3", fast.to_str().unwrap()], 3, &["joint 1"]);
}

#[test]
fn bad_input() {
    fails(&["drive", "planar3", "--from", "0,0", "--to", "1,0,0"], 2, &["--from", "3 joints"]);
    fails(&["drive", "planar3", "--from", "0,0,0", "--to", "1,x,0"], 2, &["--to joint 2"]);
    fails(&["drive", "planar3", "--from", "0,0,0", "--to", "90,0,0", "--duration", "1"], 3, &["too short", "joint 1"]);
    fails(&["drive", "planar3"], 2, &["--from"]);
    // A negative value may lead the list (here it is outside joint 1's range [0°, 180°]).
    fails(
        &["drive", "planar3", "--from", "-10,-20,-30", "--to", "9,-20,-30"],
        2,
        &["--from", "-10 deg", "[0, 180] deg"],
    );
    // A microstepping drive has no coil table.
    let robot = temp_file(
        "m.toml",
        "name = \"m\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\n[[joints]]\nname = \"j\"\na = 1\n\
         drive = { steps_per_rev = 200, microstepping = 16, max_step_rate = 20000, wiring = \"bipolar\" }\n",
    );
    fails(
        &["drive", robot.to_str().unwrap(), "--from", "0", "--to", "10", "--format", "coils"],
        2,
        &["microstepping 16"],
    );
}

#[test]
fn joint_limits_are_checked_before_anything_is_written() {
    // planar3's joint 1 ranges over [0°, 180°]: 270° is refused, naming the joint, the value and
    // the limit in the unit typed (degrees, or radians with --rad), and no G-code file is made.
    let path = temp_file("refused.gcode", "");
    std::fs::remove_file(&path).unwrap();
    let args = ["drive", "planar3", "--from", "0,0,0", "--to", "270,0,0", "--format", "gcode", "-o"];
    let mut args = args.to_vec();
    args.push(path.to_str().unwrap());
    fails(&args, 2, &["--to", "joint 1", "270 deg", "[0, 180] deg"]);
    assert!(!path.exists());
    fails(&["drive", "planar3", "--rad", "--from", "0,0,0", "--to", "4.5,0,0"], 2, &["--to", "4.5 rad"]);
    // A value far outside any range is refused the same way (it used to overflow).
    fails(&["drive", "planar3", "--from", "0,0,0", "--to", "1e308,-45,-30"], 2, &["--to", "joint 1"]);
    // A sampled motion that leaves the range names the sample.
    let motion =
        temp_file("out.json", r#"{"samples": [{"t_s": 0, "q_deg": [170, 0, 0]}, {"t_s": 20, "q_deg": [190, 0, 0]}]}"#);
    fails(&["drive", "planar3", motion.to_str().unwrap()], 2, &["sample 1", "190 deg"]);
}

#[test]
fn a_joint_without_limits_cannot_ask_for_unbounded_steps() {
    // A joint with no range: 1e12 degrees would take ~3e13 steps; refused before allocating.
    let robot = temp_file(
        "free.toml",
        "name = \"free\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\n[[joints]]\nname = \"j\"\na = 1\n\
         drive = { steps_per_rev = 200, max_step_rate = 500, wiring = \"bipolar\" }\n",
    );
    fails(&["drive", robot.to_str().unwrap(), "--from", "0", "--to", "1e12"], 2, &["joint 1", "motor steps"]);
}

#[test]
fn a_joint_faster_than_its_speed_limit_is_refused() {
    // One joint limited to 30 deg/s driven by a motor that could step much faster: 90° in
    // 1 s is refused naming the joint, its speed and its limit in degrees per second; in 3 s
    // (30 deg/s) it is driven.
    let robot = temp_file(
        "slow.toml",
        "name = \"slow\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\n[[joints]]\nname = \"j\"\na = 1\n\
         max_velocity = 30\n\
         drive = { steps_per_rev = 200, max_step_rate = 20000, wiring = \"bipolar\" }\n",
    );
    let path = robot.to_str().unwrap();
    fails(
        &["drive", path, "--from", "0", "--to", "90", "--duration", "1", "--format", "gcode"],
        2,
        &["joint 1 `j`", "deg/s", "above its limit of 30 deg/s"],
    );
    ok(&["drive", path, "--from", "0", "--to", "90", "--duration", "3.2"]);
}
