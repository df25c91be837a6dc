//! Regression tests for issue 35 ("a newcomer's first day"), one test per point, named after it.

use crate::common::{fails, json, nums};

/// Point 3: joint values take commas or blanks everywhere, also as one positional argument.
#[test]
fn point3_joint_values_take_commas_or_blanks_in_one_argument() {
    let separate = json(&["fk", "ur5", "10", "-80", "100", "-110", "10", "0", "--json"]);
    for q in ["10,-80,100,-110,10,0", "10 -80 100 -110 10 0", "10, -80, 100, -110, 10, 0"] {
        let joined = json(&["fk", "ur5", q, "--json"]);
        assert_eq!(joined, separate, "reach fk ur5 {q:?}");
    }
    // A list starting with a minus sign, and lists mixed with separate values.
    let negative = json(&["fk", "ur5", "-10,-80,100", "-110", "10 0", "--json"]);
    assert_eq!(nums(&negative["q_deg"]), [-10.0, -80.0, 100.0, -110.0, 10.0, 0.0]);
    // Every command with positional joint values shares the rule.
    json(&["jacobian", "ur5", "10,-80,100,-110,10,0", "--json"]);
    json(&["check", "ur5", "examples/ur5_ball.toml", "10 -80 100 -110 10 0", "--json"]);
    // Errors still name the joint, counted across arguments.
    fails(&["fk", "ur5", "10,-80", "100,abc,10,0"], 2, &["joint 4", "\"abc\""]);
    fails(&["fk", "ur5", "10,-80,100,-110,10"], 2, &["6 joints", "got 5"]);
}
