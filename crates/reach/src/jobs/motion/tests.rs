use super::*;
use crate::error::Error;
use crate::jobs::input::Joints;
use crate::model::presets;

/// A planar arm whose first joint turns without limits (continuous) and whose second is bounded.
const CONTINUOUS: &str = r#"
name = "continuous2"
convention = "dh"
length_unit = "m"
angle_unit = "deg"

[[joints]]
name = "spin"
a = 1.0

[[joints]]
name = "elbow"
a = 1.0
limits = [-170, 170]
"#;

fn request(from: Vec<f64>, to: Vec<f64>) -> MoveRequest {
    MoveRequest { duration_s: Some(4.0), ..MoveRequest::joints(Joints::Deg(from), Joints::Deg(to)) }
}

/// A continuous joint from 170° to −170° takes the short way (+20°), and J1 = J2 = that short
/// difference: the samples, J1 and J2 use one rule.
#[test]
fn continuous_joint_takes_the_short_way_and_j1_equals_j2() {
    let robot = crate::Robot::from_toml_str_with_units(CONTINUOUS).unwrap().0;
    let report = move_motion(
        &robot,
        &MoveRequest { joint_weights: Some(vec![1.0, 1.0]), ..request(vec![170.0, 10.0], vec![-170.0, 10.0]) },
    )
    .unwrap();
    let short = 20f64.to_radians();
    assert!((report.effort.j1 - short).abs() < 1e-12, "J1 = {}", report.effort.j1);
    assert!((report.effort.j2 - short).abs() < 1e-9, "J2 = {}", report.effort.j2);
    let last = report.samples.last().unwrap().q_deg[0];
    assert!((last - 190.0).abs() < 1e-9, "the joint goes on past 180°: ends at {last}");
    assert!(report.samples.iter().all(|s| s.qd_deg_s[0] >= 0.0), "monotone: never turns back");
    assert!(report.feasible);
}

/// A bounded joint (UR5's ±360°) from 170° to −170° turns the literal 340°; J1 says so too.
#[test]
fn bounded_joint_reports_the_literal_difference() {
    let robot = presets::get("ur5").unwrap();
    let report = move_motion(
        &robot,
        &request(vec![170.0, -90.0, 90.0, 0.0, 90.0, 0.0], vec![-170.0, -90.0, 90.0, 0.0, 90.0, 0.0]),
    )
    .unwrap();
    let w = report.effort.weights[0];
    assert!((report.effort.j1 - w * 340f64.to_radians()).abs() < 1e-12, "J1 = {}", report.effort.j1);
    assert!((report.effort.j1 - report.effort.j2).abs() < 1e-9, "{:?}", report.effort);
}

#[test]
fn bad_fields_are_named() {
    let robot = presets::get("ur5").unwrap();
    let base = request(vec![0.0; 6], vec![10.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    let field = |r: &MoveRequest| match move_motion(&robot, r).unwrap_err() {
        Error::Request { field, .. } => field,
        other => panic!("{other}"),
    };
    assert_eq!(field(&MoveRequest { duration_s: Some(0.0), ..base.clone() }), "duration_s");
    assert_eq!(field(&MoveRequest { dt_s: Some(-1.0), ..base.clone() }), "dt_s");
    assert_eq!(field(&MoveRequest { speed_m_s: Some(1.0), ..base.clone() }), "speed_m_s");
    assert_eq!(field(&MoveRequest { joint_weights: Some(vec![1.0]), ..base.clone() }), "joint_weights");
    assert_eq!(field(&request(vec![0.0; 3], vec![0.0; 6])), "from");
}

#[test]
fn a_move_request_round_trips_through_json() {
    let text = r#"{"from": {"joints": {"deg": [0, 0, 0, 0, 0, 0]}},
        "to": {"pose": {"xyz_m": [0.4, 0.1, 0.3], "rpy_deg": [180, 0, 0]}},
        "space": "tool", "duration_s": 2}"#;
    let r: MoveRequest = serde_json::from_str(text).unwrap();
    assert_eq!(r.space, Space::Tool);
    assert!(matches!(r.to, End::Pose(_)));
    let back: MoveRequest = serde_json::from_value(serde_json::to_value(&r).unwrap()).unwrap();
    assert_eq!(back, r);
    assert!(serde_json::from_str::<MoveRequest>(&text.replace("duration_s", "duration")).is_err());
}

#[test]
fn task_file_errors_give_line_and_column_or_name_the_motion() {
    let robot = presets::get("planar3").unwrap();
    let bad =
        PlanRequest { task: "robot = \"planar3\"\n[[motion]]\nfrom = [0, 0, 0]\nspeeed = 1\n".into(), scene: None };
    match plan(&robot, &bad).unwrap_err() {
        Error::File { message, .. } => assert!(message.starts_with("line 4, column 1:"), "{message}"),
        other => panic!("{other}"),
    }
    let nodur = PlanRequest {
        task:
            "robot = \"planar3\"\n[[motion]]\nname = \"m\"\nfrom = [10, -20, -30]\nto = [20, -20, -30]\nduration = -1\n"
                .into(),
        scene: None,
    };
    assert_eq!(plan(&robot, &nodur).unwrap_err().to_string(), "motion `m`: duration: must be > 0, got -1");
    let ok = PlanRequest {
        task:
            "robot = \"planar3\"\n[defaults]\nduration = 2.0\n[[motion]]\nfrom = [10, -20, -30]\nto = [20, -20, -30]\n"
                .into(),
        scene: None,
    };
    let report = plan(&robot, &ok).unwrap();
    assert_eq!(report.motions.len(), 1);
    assert_eq!(report.motions[0].name, "motion 1");
    assert!((report.motions[0].duration_s - 2.0).abs() < 1e-12);
}

/// The weld of seed 003 (notes 003 §5), ends given with `rpy_deg` or `rpy_rad`.
fn weld(unit: crate::jobs::input::AngleUnit) -> MoveRequest {
    use crate::jobs::input::{AngleUnit, Pose};
    let rpy = [0.0, -41.86854343693031f64, -50.19442890773481];
    let pose = |xyz_m: [f64; 3]| match unit {
        AngleUnit::Deg => Pose::xyz_rpy_deg(xyz_m, rpy),
        AngleUnit::Rad => Pose { xyz_m: Some(xyz_m), rpy_rad: Some(rpy.map(f64::to_radians)), ..Pose::default() },
    };
    MoveRequest {
        from: End::Pose(pose([0.05, 0.74, 0.07])),
        to: End::Pose(pose([0.5, 0.2, 0.7])),
        space: Space::Tool,
        speed_m_s: Some(0.001),
        dt_s: Some(10.0),
        ..MoveRequest::joints(Joints::Deg(Vec::new()), Joints::Deg(Vec::new()))
    }
}

/// The event text follows the request's angle unit; the typed detail is the same SI data
/// either way: θ4 of −β leaves [−175°, 150°] on s ∈ (0.618, 0.882) m (notes 003 §5.5).
#[test]
fn event_text_in_the_request_unit_and_typed_detail() {
    use crate::jobs::input::AngleUnit;
    use crate::motion::tracking::EventDetail;
    let robot = presets::get("welder6r").unwrap();
    assert_eq!(weld(AngleUnit::Rad).angle_unit(), AngleUnit::Rad);
    assert_eq!(weld(AngleUnit::Deg).angle_unit(), AngleUnit::Deg);
    let by_deg = move_motion(&robot, &weld(AngleUnit::Deg)).unwrap();
    let by_rad = move_motion(&robot, &weld(AngleUnit::Rad)).unwrap();
    let k7 = |r: &MoveReport| r.events.iter().find(|e| e.code == "K7").cloned().expect("a K7 event");
    let (deg, rad) = (k7(&by_deg), k7(&by_rad));
    assert!(deg.message.contains("[-175.00, 150.00] deg"), "{}", deg.message);
    assert!(rad.message.contains("[-3.0543, 2.6180] rad"), "{}", rad.message);
    let EventDetail::JointLimit { joint, lower, upper, s_start, s_end, .. } = deg.detail else {
        panic!("K7 is a joint limit: {:?}", deg.detail)
    };
    assert_eq!(joint, 3);
    assert!((lower - (-175f64).to_radians()).abs() < 1e-12 && (upper - 150f64.to_radians()).abs() < 1e-12);
    assert!((s_start - 0.6181).abs() < 1e-3 && (s_end - 0.8822).abs() < 1e-3, "{s_start} {s_end}");
    assert!(matches!(rad.detail, EventDetail::JointLimit { joint: 3, .. }));
}
