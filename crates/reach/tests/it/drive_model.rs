//! Drive data in the robot file: parsing, unit conversion, validation errors naming the joint
//! and the field, and the presets that carry drives.

use std::f64::consts::TAU;

use reach::Robot;
use reach::drive::{DriveError, axes};
use reach::model::{StepMode, Wiring, presets};

fn robot(drive: &str) -> Result<Robot, reach::ModelError> {
    Robot::from_toml_str(&format!(
        "name = \"t\"\nlength_unit = \"mm\"\nangle_unit = \"deg\"\n\
         [[joints]]\nname = \"shoulder\"\na = 100\n\
         [[joints]]\nname = \"slide\"\nkind = \"prismatic\"\nlimits = [0, 300]\n{drive}\n"
    ))
}

const PRISMATIC_OK: &str =
    "[joints.drive]\nsteps_per_rev = 200\nmicrostepping = 8\nlead = 8\nmax_step_rate = 4000\nwiring = \"bipolar\"";

#[test]
fn parses_drive_tables_and_converts_units() {
    let r = robot(PRISMATIC_OK).unwrap();
    assert!(r.drives()[0].is_none());
    let d = r.drives()[1].unwrap();
    assert_eq!((d.steps_per_rev, d.microstepping, d.direction, d.home_steps), (200, 8, 1, 0));
    assert_eq!(d.gear_ratio, 1.0);
    assert!((d.lead.unwrap() - 0.008).abs() < 1e-15, "lead in metres");
    // 1600 pulses per 8 mm = 200 000 steps per metre.
    let k = d.steps_per_unit(reach::model::JointKind::Prismatic).unwrap();
    assert!((k - 200_000.0).abs() < 1e-6);
    assert_eq!(d.coil_mode(), None, "microstepping 8 has no coil table");
    // Missing drive on joint 1 is named by the drive module.
    assert_eq!(axes(&r).unwrap_err(), DriveError::MissingDrive { joint: 1, name: "shoulder".into() });
    let msg = axes(&r).unwrap_err().to_string();
    assert!(msg.contains("joint 1 (shoulder)") && msg.contains("[joints.drive]"), "{msg}");
}

#[test]
fn inline_drive_form_and_revolute_steps_per_radian() {
    let r = Robot::from_toml_str(
        "name = \"t\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\n[[joints]]\na = 1\n\
         drive = { steps_per_rev = 400, gear_ratio = 3.6, direction = -1, max_step_rate = 1000, \
         max_acceleration = 5000, wiring = \"unipolar\", mode = \"full\", home_steps = 12 }\n",
    )
    .unwrap();
    let d = r.drives()[0].unwrap();
    // 400 × 3.6 = 1440 steps per joint revolution = 4 per degree.
    let k = d.steps_per_unit(reach::model::JointKind::Revolute).unwrap();
    assert!((k - 1440.0 / TAU).abs() < 1e-9);
    assert_eq!(d.coil_mode(), Some(StepMode::Full));
    assert_eq!(d.wiring, Wiring::Unipolar);
    let ax = &axes(&r).unwrap()[0];
    // direction −1, home 0 at counter 12: q = +10° → 12 − 40 = −28.
    assert_eq!(ax.quantise(10f64.to_radians()), -28);
    assert!((ax.joint_value(-28) - 10f64.to_radians()).abs() < 1e-12);
}

#[test]
fn default_coil_modes_follow_the_seed_pairing() {
    let mk = |micro: u32, wiring: &str| {
        let r = Robot::from_toml_str(&format!(
            "name = \"t\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\n[[joints]]\na = 1\n[joints.drive]\n\
             steps_per_rev = 200\nmicrostepping = {micro}\nmax_step_rate = 500\nwiring = \"{wiring}\"\n"
        ))
        .unwrap();
        r.drives()[0].unwrap().coil_mode()
    };
    assert_eq!(mk(1, "unipolar"), Some(StepMode::Wave)); // Table 1
    assert_eq!(mk(1, "bipolar"), Some(StepMode::Full)); // Table 2
    assert_eq!(mk(2, "bipolar"), Some(StepMode::Half));
    assert_eq!(mk(16, "bipolar"), None);
}

fn err(drive: &str) -> String {
    robot(drive).unwrap_err().to_string()
}

#[test]
fn bad_drive_values_name_the_joint_and_field() {
    let base = |field: &str| PRISMATIC_OK.replace("lead = 8", &format!("lead = 8\n{field}"));
    let cases: &[(String, &str)] = &[
        (PRISMATIC_OK.replace("steps_per_rev = 200", "steps_per_rev = 0"), "drive.steps_per_rev"),
        (PRISMATIC_OK.replace("microstepping = 8", "microstepping = 0"), "drive.microstepping"),
        (PRISMATIC_OK.replace("microstepping = 8", "microstepping = 512"), "drive.microstepping"),
        (base("gear_ratio = 0"), "drive.gear_ratio"),
        (base("gear_ratio = -2"), "drive.gear_ratio"),
        (base("gear_ratio = nan"), "drive.gear_ratio"),
        (PRISMATIC_OK.replace("lead = 8", "lead = 0"), "drive.lead"),
        (PRISMATIC_OK.replace("lead = 8\n", ""), "drive.lead"),
        (PRISMATIC_OK.replace("max_step_rate = 4000", "max_step_rate = 0"), "drive.max_step_rate"),
        (PRISMATIC_OK.replace("max_step_rate = 4000", "max_step_rate = inf"), "drive.max_step_rate"),
        (base("max_acceleration = -1"), "drive.max_acceleration"),
        (base("direction = 2"), "drive.direction"),
        (base("mode = \"wave\""), "drive.mode"),
    ];
    for (drive, field) in cases {
        let message = err(drive);
        assert!(message.contains("joint 2 (slide)") && message.contains(field), "{field}: {message}");
    }
    // A revolute joint with a lead.
    let r = Robot::from_toml_str(
        "name = \"t\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\n[[joints]]\nname = \"j\"\na = 1\n\
         drive = { steps_per_rev = 200, lead = 2, max_step_rate = 500, wiring = \"bipolar\" }\n",
    )
    .unwrap_err()
    .to_string();
    assert!(r.contains("joint 1 (j)") && r.contains("drive.lead"), "{r}");
}

#[test]
fn unknown_or_missing_drive_fields_are_parse_errors_with_a_line() {
    let typo = err(&PRISMATIC_OK.replace("wiring", "wirng"));
    assert!(typo.contains("line") && typo.contains("wirng"), "{typo}");
    let missing = err(&PRISMATIC_OK.replace("max_step_rate = 4000\n", ""));
    assert!(missing.contains("max_step_rate"), "{missing}");
    let wiring = err(&PRISMATIC_OK.replace("\"bipolar\"", "\"tripolar\""));
    assert!(wiring.contains("tripolar") || wiring.contains("unipolar"), "{wiring}");
}

#[test]
fn presets_with_drives() {
    let planar3 = presets::get("planar3").unwrap();
    let ax = axes(&planar3).unwrap();
    for a in &ax {
        assert_eq!(a.max_step_rate, 500.0); // seed 000, P2011 eq. (8)
        assert!(a.max_acceleration.is_none());
        // 200 × 50 steps per revolution = 27.78 per degree.
        assert!((a.steps_per_unit * std::f64::consts::PI / 180.0 - 10_000.0 / 360.0).abs() < 1e-9);
    }
    let loader = presets::get("log-loader").unwrap();
    assert_eq!(axes(&loader).unwrap().len(), 3);
    // A preset without drives reports its first joint.
    let err = axes(&presets::get("puma560").unwrap()).unwrap_err();
    assert!(matches!(err, DriveError::MissingDrive { joint: 1, .. }), "{err}");
    // Drives survive a change of tool or base.
    let moved = planar3.with_tool(nalgebra::Isometry3::translation(0.1, 0.0, 0.0)).unwrap();
    assert_eq!(moved.drives(), planar3.drives());
}
