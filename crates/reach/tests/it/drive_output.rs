//! Schedule outputs: CSV rows, coil tables, step/direction events, JSON and G-code (parsed
//! line by line against a small grammar written here).

use std::collections::HashSet;

use reach::drive::output::{GcodeDialect, coil_table_csv, gcode, step_dir_events, step_dir_text, step_rows, to_csv};
use reach::drive::{DriveError, axes, point_to_point, schedule_trajectory};
use reach::model::presets;
use reach::motion::JointSample;

fn planar3_move() -> reach::drive::PointToPoint {
    let robot = presets::get("planar3").unwrap();
    let axes = axes(&robot).unwrap();
    // φ = (100, 400, 200) steps in 0.8 s (seed 000, D8).
    let to = [3.6_f64.to_radians(), (-14.4_f64).to_radians(), (-7.2_f64).to_radians()];
    point_to_point(&axes, &[0.0; 3], &to, None, 0.0).unwrap()
}

#[test]
fn csv_has_one_row_per_step_in_time_order_with_coil_states() {
    let plan = planar3_move();
    let csv = to_csv(&plan.schedule);
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("t_s,joint,name,dir,index,position,coils"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 700);
    let times: Vec<f64> = rows.iter().map(|r| r[0].parse().unwrap()).collect();
    assert!(times.windows(2).all(|w| w[0] <= w[1]));
    // First row: joint 2 (fastest, 500 Hz) at 2 ms, moving backwards to −1. Unipolar wave
    // drive: counter −1 is the last state of Table 1, line b2 = 0001.
    assert_eq!(rows[0], ["0.002000000", "2", "B", "-1", "1", "-1", "0001"]);
    // Each joint's rows count its steps.
    for (joint, count) in [("1", 100), ("2", 400), ("3", 200)] {
        assert_eq!(rows.iter().filter(|r| r[1] == joint).count(), count);
    }
    let structured = step_rows(&plan.schedule);
    assert_eq!(structured.len(), 700);
    assert_eq!(structured.last().unwrap().t_s, 0.8);
}

#[test]
fn coil_table_follows_table_1_backwards_for_a_negative_move() {
    let plan = planar3_move();
    let table = coil_table_csv(&plan.schedule).unwrap();
    let joint2: Vec<&str> =
        table.lines().skip(1).filter(|l| l.split(',').nth(1) == Some("2")).map(|l| &l[l.len() - 7..]).collect();
    // Start state a1 (counter 0), then reverse order: b2, a2, b1, a1, b2 …
    assert_eq!(&joint2[..6], ["1,0,0,0", "0,0,0,1", "0,0,1,0", "0,1,0,0", "1,0,0,0", "0,0,0,1"]);
    // A microstepping driver has no coil table.
    let robot = reach::Robot::from_toml_str(
        "name = \"m\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\n[[joints]]\nname = \"j\"\na = 1\n\
         drive = { steps_per_rev = 200, microstepping = 16, max_step_rate = 20000, wiring = \"bipolar\" }\n",
    )
    .unwrap();
    let ax = axes(&robot).unwrap();
    let p = point_to_point(&ax, &[0.0], &[0.1], None, 0.0).unwrap();
    assert!(matches!(coil_table_csv(&p.schedule), Err(DriveError::NoCoilTable { joint: 1, microstepping: 16, .. })));
}

#[test]
fn step_dir_events_set_direction_before_pulses() {
    let robot = presets::get("planar3").unwrap();
    let axes = axes(&robot).unwrap();
    let k = axes[0].steps_per_unit;
    // Joint 1: 3 steps forward, then 5 back (to −2).
    let samples = vec![
        JointSample::of(&robot, 0.0, vec![0.0, 0.0, 0.0]),
        JointSample::of(&robot, 0.1, vec![3.0 / k, 0.0, 0.0]),
        JointSample::of(&robot, 0.2, vec![-2.0 / k, 0.0, 0.0]),
    ];
    let schedule = schedule_trajectory(&axes, &samples).unwrap();
    let events = step_dir_events(&schedule);
    let kinds: Vec<String> = events
        .iter()
        .map(|e| match e.dir {
            Some(d) => format!("DIR{d:+}"),
            None => "STEP".into(),
        })
        .collect();
    let mut expected = vec!["DIR+1".to_string()];
    expected.extend(std::iter::repeat_n("STEP".to_string(), 3));
    expected.push("DIR-1".into());
    expected.extend(std::iter::repeat_n("STEP".to_string(), 5));
    assert_eq!(kinds, expected);
    // Steps at the half-step crossings: 0.5/3 of the first 0.1 s, …
    assert!((events[1].t_s - 0.1 * 0.5 / 3.0).abs() < 1e-12);
    let text = step_dir_text(&schedule);
    assert_eq!(text.lines().nth(1), Some("16667 1 DIR +"));
    assert_eq!(text.lines().count(), 1 + 10);
}

#[test]
fn schedules_serialise_to_json() {
    let plan = planar3_move();
    let value = serde_json::to_value(step_rows(&plan.schedule)).unwrap();
    let rows = value.as_array().unwrap();
    assert_eq!(rows.len(), 700);
    assert_eq!(rows[0]["joint"], 2);
    assert_eq!(rows[0]["coils"], "0001");
    let whole = serde_json::to_value(&plan).unwrap();
    assert_eq!(whole["duration"], 0.8);
    assert_eq!(whole["schedule"]["joints"][1]["end_position"], -400);
}

/// One G-code word: a letter and a number.
fn word(token: &str) -> Option<(char, f64)> {
    let mut chars = token.chars();
    let letter = chars.next()?;
    let number: f64 = chars.as_str().parse().ok()?;
    (letter.is_ascii_uppercase() && number.is_finite()).then_some((letter, number))
}

/// The grammar: blank lines, `;` comments, `G21`, `G90`, `G94`, `G4 P<t>` (t > 0) and
/// `G1 <axis value>… F<feed>` with known, distinct axes and a positive feed. Returns the
/// G1 moves as (axis → value, feed).
fn parse_gcode(text: &str, axes: &str) -> Vec<(Vec<(char, f64)>, f64)> {
    let mut moves = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with(';') {
            continue;
        }
        let tokens: Vec<&str> = line.split_whitespace().collect();
        match tokens[0] {
            "G21" | "G90" | "G94" => assert_eq!(tokens.len(), 1, "line {n}: {line}"),
            "G4" => {
                assert_eq!(tokens.len(), 2, "line {n}: {line}");
                let (p, t) = word(tokens[1]).unwrap_or_else(|| panic!("line {n}: {line}"));
                assert!(p == 'P' && t > 0.0, "line {n}: {line}");
            }
            "G1" => {
                let mut seen = HashSet::new();
                let mut coords = Vec::new();
                let mut feed = None;
                for t in &tokens[1..] {
                    let (letter, value) = word(t).unwrap_or_else(|| panic!("line {n}: bad word {t}"));
                    if letter == 'F' {
                        assert!(feed.is_none() && value > 0.0, "line {n}: feed {value}");
                        feed = Some(value);
                    } else {
                        assert!(axes.contains(letter), "line {n}: unknown axis {letter}");
                        assert!(seen.insert(letter), "line {n}: axis {letter} twice");
                        coords.push((letter, value));
                    }
                }
                assert!(!coords.is_empty(), "line {n}: G1 without axes");
                moves.push((coords, feed.unwrap_or_else(|| panic!("line {n}: G1 without feed"))));
            }
            other => panic!("line {n}: unexpected command {other}: {line}"),
        }
    }
    moves
}

#[test]
fn gcode_parses_and_reaches_the_schedule_end_on_time() {
    let plan = planar3_move();
    let times: Vec<f64> = (0..=16).map(|i| 0.05 * i as f64).collect();
    let text = gcode(&plan.schedule, &times, GcodeDialect::Grbl, "planar3").unwrap();
    assert!(text.contains("\nG21\nG90\n"));
    assert!(text.contains("$100=27.777778"), "GRBL steps per degree");
    let moves = parse_gcode(&text, "XYZ");
    assert_eq!(moves.len(), 16);
    // Last positions: 3.6°, −14.4°, −7.2° (step counters 100, −400, −200 at 27.78/deg).
    let mut last = std::collections::HashMap::new();
    let mut total_time = 0.0;
    let mut prev = [0.0f64; 3];
    for (coords, feed) in &moves {
        let mut next = prev;
        for (letter, value) in coords {
            last.insert(*letter, *value);
            next["XYZ".find(*letter).unwrap()] = *value;
        }
        let dist = prev.iter().zip(&next).map(|(a, b)| (b - a) * (b - a)).sum::<f64>().sqrt();
        total_time += 60.0 * dist / feed;
        prev = next;
    }
    assert!((last[&'X'] - 3.6).abs() < 1e-6 && (last[&'Y'] + 14.4).abs() < 1e-6 && (last[&'Z'] + 7.2).abs() < 1e-6);
    assert!((total_time - 0.8).abs() < 1e-5, "feeds reproduce the 0.8 s schedule: {total_time}");
}

#[test]
fn gcode_dwells_and_marlin_settings() {
    let robot = presets::get("log-loader").unwrap();
    let axes = axes(&robot).unwrap();
    let plan = point_to_point(&axes, &[0.0; 3], &[0.1, 0.0, 0.0], None, 0.0).unwrap();
    let mut times = vec![-1.0];
    times.extend((0..=10).map(|i| plan.duration * i as f64 / 10.0));
    let text = gcode(&plan.schedule, &times, GcodeDialect::Marlin, "log-loader").unwrap();
    assert!(text.contains("M92 X33.333333 Y33.333333 Z33.333333"), "{text}");
    assert!(text.contains("\nG4 P1000\n"), "one-second dwell in ms: {text}");
    assert_eq!(parse_gcode(&text, "XYZ").len(), 10);
    // Seven joints have no seventh axis letter.
    let seven = reach::Robot::from_toml_str(&format!(
        "name = \"s\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\n{}",
        "[[joints]]\na = 1\ndrive = { steps_per_rev = 200, max_step_rate = 500, wiring = \"bipolar\" }\n".repeat(7)
    ))
    .unwrap();
    let ax7 = reach::drive::axes(&seven).unwrap();
    let p7 = point_to_point(&ax7, &[0.0; 7], &[0.1; 7], None, 0.0).unwrap();
    assert_eq!(gcode(&p7.schedule, &[0.0, 1.0], GcodeDialect::Grbl, "s").unwrap_err(), DriveError::TooManyAxes(7));
}
