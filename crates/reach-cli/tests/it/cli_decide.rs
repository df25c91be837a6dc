//! End-to-end tests of the decision features: `reach ik --choose` (rankings that explain
//! themselves; different criteria and methods choose different solutions for the same pose)
//! and `reach tasks` (visiting against brute force, collection and budgets, unreachable
//! points skipped), and their bad input (exit 2, empty stdout) and exit 3.

use crate::common;

use serde_json::Value;

use crate::common::{fails, json, num, nums, ok, reach, temp_file};

const UR5_POSE: &str = "-1,0,0,0.4,0,1,0,-0.2,0,0,-1,0.3,0,0,0,1";
const UR5_FROM: &str = "0,-90,90,-90,-90,0";

fn chosen_branch(report: &Value) -> String {
    let i = report["chosen"].as_u64().unwrap() as usize;
    report["solutions"][i]["branch"].as_str().unwrap().to_string()
}

#[test]
fn choose_ranks_the_solutions_within_limits_and_explains_the_ranking() {
    let criteria = "change,limits,manipulability,sigma_min";
    let args = |method: &str| -> Vec<String> {
        let mut a: Vec<String> =
            ["ik", "ur5", "--matrix", UR5_POSE, "--from", UR5_FROM, "--choose", method, "--criteria", criteria]
                .map(String::from)
                .to_vec();
        if method != "pareto" {
            a.extend(["--weights".into(), "0.25,0.25,0.25,0.25".into()]);
        }
        a.push("--json".into());
        a
    };
    let run = |method: &str| {
        let a = args(method);
        json(&a.iter().map(String::as_str).collect::<Vec<_>>())
    };
    let topsis = run("topsis");
    let ranking = &topsis["ranking"];
    let ranked = ranking["ranked"].as_array().unwrap();
    let feasible: Vec<usize> = (0..topsis["solutions"].as_array().unwrap().len())
        .filter(|&i| topsis["solutions"][i]["within_limits"] == true)
        .collect();
    assert_eq!(ranked.len(), feasible.len());
    assert_eq!(ranked[0]["solution"], topsis["chosen"]);
    let weights: Vec<f64> =
        ranking["criteria"].as_array().unwrap().iter().map(|c| c["weight"].as_f64().unwrap()).collect();
    assert!((weights.iter().sum::<f64>() - 1.0).abs() < 1e-12 && (weights[0] - 0.25).abs() < 1e-12);
    let from: Vec<f64> = UR5_FROM.split(',').map(|v| v.parse().unwrap()).collect();
    let mut previous = f64::INFINITY;
    for (k, e) in ranked.iter().enumerate() {
        assert_eq!(e["rank"].as_u64().unwrap() as usize, k + 1);
        let score = e["score"].as_f64().unwrap();
        assert!((0.0..=1.0).contains(&score) && score <= previous, "closeness sorted: {ranking}");
        previous = score;
        // The `change` value is Σ |qᵢ − fromᵢ| (joint weights 1) of that solution, each
        // difference by the one joint-difference rule: UR5's joints are bounded (±360°), so
        // literal, as a joint-space motion travels it.
        let q = nums(&topsis["solutions"][e["solution"].as_u64().unwrap() as usize]["q_deg"]);
        let change: f64 = q.iter().zip(&from).map(|(a, b)| (a - b).to_radians().abs()).sum();
        assert!((nums(&e["values"])[0] - change).abs() < 1e-9, "{e}");
        assert_eq!(nums(&e["normalised"]).len(), 4);
    }
    // Another method picks another solution for the same pose, weights and criteria.
    let vikor = run("vikor");
    assert_ne!(chosen_branch(&topsis), chosen_branch(&vikor), "TOPSIS and VIKOR agree: {vikor}");
    assert_eq!(vikor["ranking"]["ranked"][0]["solution"], vikor["chosen"]);
    // docs/choosing.md: there VIKOR's choice (#3) passes both acceptance conditions on its own.
    let acceptance = &vikor["ranking"]["vikor"];
    assert_eq!(
        (&acceptance["acceptable_advantage"], &acceptance["acceptable_stability"]),
        (&Value::Bool(true), &Value::Bool(true))
    );
    assert_eq!(acceptance["compromise"], Value::Array(vec![vikor["chosen"].clone()]));
    assert_eq!(vikor["chosen"], 2);
    // Pareto: the chosen one is non-dominated and has the least change among those.
    let pareto = run("pareto");
    let pr = pareto["ranking"]["ranked"].as_array().unwrap();
    assert_eq!(pr[0]["pareto_optimal"], true);
    let front_change = |e: &Value| nums(&e["values"])[0];
    assert!(pr.iter().filter(|e| e["pareto_optimal"] == true).all(|e| front_change(e) >= front_change(&pr[0])));
    // The human-readable table names its columns and the score.
    let text = ok(&[
        "ik",
        "ur5",
        "--matrix",
        UR5_POSE,
        "--from",
        UR5_FROM,
        "--choose",
        "topsis",
        "--criteria",
        criteria,
        "--weights",
        "0.25,0.25,0.25,0.25",
    ]);
    for needle in ["ranking (--choose topsis", "change↓ [rad]", "change norm", "manipulability↑", "closeness", "pareto"]
    {
        assert!(text.contains(needle), "{needle}: {text}");
    }
}

#[test]
fn different_criteria_choose_different_solutions_for_the_same_pose() {
    // PUMA 560, the README example: least joint change and largest limit margin disagree.
    let base = ["ik", "puma560", "--xyz", "0.5,-0.2,0.3", "--rpy", "180,0,0", "--choose", "topsis", "--json"];
    let by = |criteria: &str| {
        let mut a = base.to_vec();
        a.extend(["--criteria", criteria]);
        json(&a)
    };
    let change = by("change");
    let limits = by("limits");
    assert_ne!(chosen_branch(&change), chosen_branch(&limits));
    // `change` alone agrees with the default closest-solution rule.
    let closest = json(&["ik", "puma560", "--xyz", "0.5,-0.2,0.3", "--rpy", "180,0,0", "--json"]);
    let q = |r: &Value| nums(&r["solutions"][r["chosen"].as_u64().unwrap() as usize]["q_deg"]);
    assert!(q(&change).iter().zip(q(&closest)).all(|(a, b)| (a - b).abs() < 1e-9));
}

#[test]
fn vikor_reports_its_acceptance_conditions_and_the_compromise_set() {
    // PUMA 560, the README pose, change/limits/manipulability: two solutions within limits, one
    // best on change (Q = 0), the other on limits and manipulability (Q = 0.5). With m = 2,
    // DQ = 1/(m − 1) = 1, so C1 (Q(a″) − Q(a′) ≥ DQ) fails and both form the compromise set;
    // C2 holds (Q = 0 means best by S and by R).
    let args = ["ik", "puma560", "--xyz", "0.5,-0.2,0.3", "--rpy", "180,0,0", "--choose", "vikor"];
    let with = |extra: &[&'static str]| [args.as_slice(), extra].concat();
    let r = json(&with(&["--criteria", "change,limits,manipulability", "--weights", "0.5,0.3,0.2", "--json"]));
    let ranked = r["ranking"]["ranked"].as_array().unwrap();
    assert_eq!(ranked.len(), 2, "{r}");
    let q: Vec<f64> = ranked.iter().map(|e| e["score"].as_f64().unwrap()).collect();
    assert!(q[0].abs() < 1e-12 && (q[1] - 0.5).abs() < 1e-12, "{q:?}");
    let v = &r["ranking"]["vikor"];
    assert_eq!(v["dq"].as_f64(), Some(1.0), "{v}");
    assert_eq!((&v["acceptable_advantage"], &v["acceptable_stability"]), (&Value::Bool(false), &Value::Bool(true)));
    let set: Vec<&Value> = ranked.iter().map(|e| &e["solution"]).collect();
    assert_eq!(v["compromise"].as_array().unwrap().iter().collect::<Vec<_>>(), set, "{v}");
    let text = ok(&with(&["--criteria", "change,limits,manipulability", "--weights", "0.5,0.3,0.2"]));
    let numbers: Vec<String> = ranked.iter().map(|e| format!("#{}", e["solution"].as_u64().unwrap() + 1)).collect();
    let line = format!(
        "C1 advantage (ΔQ ≥ DQ = 1.000) fails, C2 stability (also best by S or R) holds → compromise set {}",
        numbers.join(", ")
    );
    assert!(text.contains(&line), "{line}: {text}");
    // Other methods print no VIKOR line and no `vikor` object.
    let topsis = json(&["ik", "puma560", "--xyz", "0.5,-0.2,0.3", "--rpy", "180,0,0", "--choose", "topsis", "--json"]);
    assert!(topsis["ranking"].get("vikor").is_none());
}

#[test]
fn choose_bad_input_exits_2() {
    let pose = ["ik", "ur5", "--matrix", UR5_POSE];
    let with = |extra: &[&'static str]| {
        let mut a = pose.to_vec();
        a.extend_from_slice(extra);
        a
    };
    fails(&with(&["--choose", "electre"]), 2, &["--choose", "unknown method `electre`", "topsis"]);
    fails(&with(&["--choose", "topsis", "--criteria", "change,rigidity"]), 2, &["unknown criterion `rigidity`"]);
    fails(
        &with(&["--choose", "topsis", "--criteria", "change,limits", "--weights", "1,2,3"]),
        2,
        &["--weights", "expected 2 weights", "got 3"],
    );
    fails(
        &with(&["--choose", "vikor", "--criteria", "change,limits", "--weights", "1,-1"]),
        2,
        &["--weights value 2 (limits)", "negative"],
    );
    fails(
        &with(&["--choose", "topsis", "--criteria", "change,limits", "--weights", "0,0"]),
        2,
        &["all weights are zero"],
    );
    fails(&with(&["--choose", "topsis", "--criteria", "change,change"]), 2, &["given twice"]);
    fails(&with(&["--choose", "pareto", "--weights", "1,1,1"]), 2, &["pareto", "no weights"]);
    fails(&with(&["--choose", "topsis", "--weights", "1,nan,1"]), 2, &["--weights value 2"]);
    // log-loader stretched along x: every solution has a joint at a limit, so the limit margin
    // is 0 for all of them: an all-zero column cannot discriminate.
    fails(
        &["ik", "log-loader", "--xyz", "2,0,0", "--choose", "topsis", "--criteria", "change,limits"],
        2,
        &["criterion 'limits'", "all-zero column"],
    );
    // Empty candidate set: no solution within limits → the ik exit status 3, report on stdout.
    let run = reach(&["ik", "ur5", "--xyz", "3,0,0", "--choose", "topsis"]);
    assert_eq!(run.code, 3, "{}", run.stderr);
}

// ---------------------------------------------------------------------------------------
// reach tasks

const SEED001: [f64; 6] = [1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0, 1.0 / 18.0, 1.0 / 18.0, 1.0 / 18.0];

/// J1 between two ur5 configurations in degrees. ur5's joints are bounded (±360°), so the one
/// joint-difference rule (`Robot::joint_difference`) takes the literal difference — what the
/// joint-space move travels, as the leg durations do.
fn j1_deg(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).zip(SEED001).map(|((x, y), w)| w * (y - x).to_radians().abs()).sum()
}

fn permutations(items: &mut Vec<usize>, k: usize, visit: &mut dyn FnMut(&[usize])) {
    if k == items.len() {
        visit(items);
        return;
    }
    for i in k..items.len() {
        items.swap(k, i);
        permutations(items, k + 1, visit);
        items.swap(k, i);
    }
}

#[test]
fn visiting_is_optimal_against_brute_force_and_skips_unreachable_points() {
    let r = json(&["tasks", "ur5", "visiting", "examples/tasks_visiting.toml", "--budget", "6", "--json"]);
    assert_eq!(r["unreachable"], serde_json::json!([7]));
    assert!(r["points"][6]["reason"].as_str().unwrap().contains("out of reach"));
    let plan = &r["plan"];
    assert_eq!(plan["exact"], true);
    let order: Vec<usize> = plan["order"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap() as usize).collect();
    let mut sorted = order.clone();
    sorted.sort_unstable();
    assert_eq!(sorted, vec![1, 2, 3, 4, 5, 6, 8, 9]);
    // Brute force over the 8! tours with J1 recomputed from the printed configurations.
    let q = |n: usize| if n == 0 { nums(&r["node0_q_deg"]) } else { nums(&r["points"][n - 1]["q_deg"]) };
    let configs: Vec<Vec<f64>> = (0..=9).map(|n| if n == 7 { vec![] } else { q(n) }).collect();
    let tour = |o: &[usize]| -> f64 {
        let mut prev = 0;
        o.iter()
            .map(|&j| {
                let c = j1_deg(&configs[prev], &configs[j]);
                prev = j;
                c
            })
            .sum()
    };
    let mut best = f64::INFINITY;
    permutations(&mut sorted, 0, &mut |o| best = best.min(tour(o)));
    let total = plan["total_j1_rad"].as_f64().unwrap();
    assert!((total - best).abs() < 1e-6 * best, "plan {total} vs brute force {best}");
    assert!((tour(&order) - total).abs() < 1e-6 * total);
    let legs: f64 = plan["legs"].as_array().unwrap().iter().map(|l| l["j1_rad"].as_f64().unwrap()).sum();
    assert!((legs - total).abs() < 1e-9);
    // Budget: fewer points, within the budget; a larger budget never fits fewer.
    let within = &r["within_budget"];
    let count = within["order"].as_array().unwrap().len();
    assert!(count < 8 && count > 0);
    assert!(within["total_duration_s"].as_f64().unwrap() <= 6.0);
    let larger = json(&["tasks", "ur5", "visiting", "examples/tasks_visiting.toml", "--budget", "9", "--json"]);
    assert!(larger["within_budget"]["order"].as_array().unwrap().len() >= count);
    let text = ok(&["tasks", "ur5", "visiting", "examples/tasks_visiting.toml", "--budget", "6"]);
    for needle in ["unreachable (skipped)", "point 7", "exact: Held–Karp", "within the budget of 6.000 s"] {
        assert!(text.contains(needle), "{needle}: {text}");
    }
}

#[test]
fn more_than_twelve_targets_use_the_heuristic_and_say_so() {
    let points: Vec<String> = (0..14)
        .map(|k| {
            let a = f64::from(k) * 0.4;
            format!("[{:.4}, {:.4}, 0.1]", 0.45 * a.cos(), 0.45 * a.sin())
        })
        .collect();
    let file = temp_file("ring.toml", &format!("orientation = [180, 0, 0]\ntargets = [{}]\n", points.join(", ")));
    let r = json(&["tasks", "ur5", "visiting", file.to_str().unwrap(), "--json"]);
    assert_eq!(r["plan"]["exact"], false);
    assert!(r["plan"]["method"].as_str().unwrap().starts_with("heuristic"));
    assert_eq!(r["plan"]["order"].as_array().unwrap().len(), 14);
}

#[test]
fn collection_trips_and_budget() {
    let r = json(&["tasks", "ur5", "collection", "examples/tasks_collection.toml", "--budget", "8", "--json"]);
    assert_eq!(r["unreachable"], serde_json::json!([5]));
    let node0 = nums(&r["node0_q_deg"]);
    let plan = &r["plan"];
    // Each trip's J1 is there and back between the container and the object's configuration.
    for leg in plan["legs"].as_array().unwrap() {
        let q = nums(&r["points"][leg["point"].as_u64().unwrap() as usize - 1]["q_deg"]);
        assert!((leg["j1_rad"].as_f64().unwrap() - 2.0 * j1_deg(&node0, &q)).abs() < 1e-9);
    }
    assert_eq!(plan["legs"].as_array().unwrap().len(), 6);
    // Budget: the shortest trips, as many as fit.
    let mut trips: Vec<f64> =
        plan["legs"].as_array().unwrap().iter().map(|l| l["duration_s"].as_f64().unwrap()).collect();
    trips.sort_by(f64::total_cmp);
    let within = &r["within_budget"];
    let taken = within["legs"].as_array().unwrap().len();
    let shortest: f64 = trips[..taken].iter().sum();
    assert!((within["total_duration_s"].as_f64().unwrap() - shortest).abs() < 1e-9);
    assert!(shortest <= 8.0 && (taken == trips.len() || shortest + trips[taken] > 8.0), "{trips:?} {taken}");
    assert!(r["choice"].as_str().unwrap().contains("topsis"));
}

#[test]
fn tasks_bad_input_and_infeasible() {
    let none = temp_file("none.toml", "targets = [[3, 0, 0], [0, 4, 0]]\n");
    fails(
        &["tasks", "ur5", "visiting", none.to_str().unwrap()],
        2,
        &["no point of `targets` is reachable", "1 (", "2 ("],
    );
    let empty = temp_file("empty.toml", "targets = []\n");
    fails(&["tasks", "ur5", "visiting", empty.to_str().unwrap()], 2, &["`targets` is empty"]);
    let far = temp_file("far.toml", "container = [3, 0, 0]\nobjects = [[0.4, 0, 0.1]]\n");
    fails(&["tasks", "ur5", "collection", far.to_str().unwrap()], 3, &["container is unreachable"]);
    let weights = temp_file(
        "weights.toml",
        "targets = [[0.4, 0, 0.1]]\n[choose]\nmethod = \"topsis\"\ncriteria = [\"change\", \"limits\"]\nweights = [1.0]\n",
    );
    fails(&["tasks", "ur5", "visiting", weights.to_str().unwrap()], 2, &["[choose] weights", "expected 2 weights"]);
    let negative = temp_file(
        "negative.toml",
        "targets = [[0.4, 0, 0.1]]\n[choose]\nmethod = \"vikor\"\ncriteria = [\"change\", \"limits\"]\nweights = [1.0, -2.0]\n",
    );
    fails(&["tasks", "ur5", "visiting", negative.to_str().unwrap()], 2, &["[choose] weights[2]", "negative"]);
    let unknown =
        temp_file("unknown.toml", "targets = [[0.4, 0, 0.1]]\n[choose]\nmethod = \"topsis\"\ncriteria = [\"luck\"]\n");
    fails(&["tasks", "ur5", "visiting", unknown.to_str().unwrap()], 2, &["unknown criterion `luck`"]);
    let key = temp_file("key.toml", "targets = [[0.4, 0, 0.1]]\nspeed = 3\n");
    fails(&["tasks", "ur5", "visiting", key.to_str().unwrap()], 2, &["speed"]);
    let wrong = temp_file("wrong.toml", "targets = [[0.4, 0]]\n");
    fails(&["tasks", "ur5", "visiting", wrong.to_str().unwrap()], 2, &["targets[1]", "got 2"]);
    let kind = temp_file("kind.toml", "targets = [[0.4, 0, 0.1]]\n");
    fails(&["tasks", "ur5", "collection", kind.to_str().unwrap()], 2, &["`targets` belong to visiting"]);
    let ok_file = temp_file("ok.toml", "targets = [[0.4, 0, 0.1]]\n");
    fails(&["tasks", "ur5", "visiting", ok_file.to_str().unwrap(), "--budget", "-1"], 2, &["--budget"]);
    // puma560 has no speed limits: a budget needs max_velocity in the file.
    fails(&["tasks", "puma560", "visiting", ok_file.to_str().unwrap(), "--budget", "5"], 2, &["max_velocity"]);
    fails(&["tasks", "ur5", "visiting", "/nonexistent/task.toml"], 2, &["/nonexistent/task.toml"]);
}

// ---------------------------------------------------------------------------------------
// reach plan: [choose] per path interval

fn interval_choices(r: &Value) -> Vec<(String, String)> {
    r["motions"][0]["intervals"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| (i["configuration"].as_str().unwrap_or("").to_string(), i["decision"].as_str().unwrap().to_string()))
        .collect()
}

#[test]
fn plan_choose_ranks_the_configurations_of_each_interval() {
    let example = std::fs::read_to_string(format!("{}/examples/choose_tracking.toml", common::REPO_ROOT)).unwrap();
    let chosen = json(&["plan", "examples/choose_tracking.toml", "--json"]);
    assert_eq!(interval_choices(&chosen), vec![("shoulder=w config=−β wrist=e5".into(), "criterion".into())]);
    // Without [choose] the default configuration is realised.
    let start = example.find("\n[choose]").unwrap();
    let end = example.find("[[motion]]").unwrap();
    let plain = temp_file("plain.toml", &format!("{}{}", &example[..start], &example[end..]));
    let r = json(&["plan", plain.to_str().unwrap(), "--json"]);
    assert_eq!(interval_choices(&r), vec![("shoulder=w config=+β wrist=e5".into(), "default".into())]);
    // Another criterion (J2, less joint motion) chooses the other configuration.
    let j2 = temp_file(
        "j2.toml",
        &example
            .replace("criteria = [\"limits\", \"manipulability\"]", "criteria = [\"j2\"]")
            .replace("weights = [0.5, 0.5]", ""),
    );
    let r = json(&["plan", j2.to_str().unwrap(), "--json"]);
    assert_eq!(interval_choices(&r), vec![("shoulder=w config=+β wrist=e5".into(), "criterion".into())]);
    // A requirement no configuration meets (limit margin >= 0.45): the default is realised (K14).
    let strict = temp_file(
        "strict.toml",
        &example.replace("weights = [0.5, 0.5]", "weights = [0.5, 0.5]\nrequire = { limits = 0.45 }"),
    );
    let r = json(&["plan", strict.to_str().unwrap(), "--json"]);
    assert_eq!(interval_choices(&r), vec![("shoulder=w config=+β wrist=e5".into(), "criterion_rejected".into())]);
    assert!(r["motions"][0]["events"].as_array().unwrap().iter().any(|e| e["code"] == "K14"));
    // A requirement one configuration meets (limit margin >= 0.2) keeps the ranking's choice.
    let loose = temp_file(
        "loose.toml",
        &example.replace("weights = [0.5, 0.5]", "weights = [0.5, 0.5]\nrequire = { limits = 0.2 }"),
    );
    let r = json(&["plan", loose.to_str().unwrap(), "--json"]);
    assert_eq!(interval_choices(&r)[0].1, "criterion");
    // Bad [choose]: unknown criterion, weight count, clearance without a scene, requirement
    // on a criterion not listed.
    let not_listed =
        temp_file("req.toml", &example.replace("weights = [0.5, 0.5]", "weights = [0.5, 0.5]\nrequire = { j2 = 1.0 }"));
    fails(&["plan", not_listed.to_str().unwrap()], 2, &["choose.require", "`j2` is not one of the criteria"]);
    for (from, to, needle) in [
        ("[\"limits\", \"manipulability\"]", "[\"limits\", \"luck\"]", "unknown criterion 'luck'"),
        ("weights = [0.5, 0.5]", "weights = [0.5]", "expected 2 weights"),
        ("weights = [0.5, 0.5]", "weights = [0.5, -0.5]", "must be finite and >= 0"),
        ("[\"limits\", \"manipulability\"]", "[\"limits\", \"clearance\"]", "needs a scene"),
        ("method = \"topsis\"", "method = \"electre\"", "unknown `electre`"),
    ] {
        let file = temp_file("bad-choose.toml", &example.replace(from, to));
        fails(&["plan", file.to_str().unwrap()], 2, &["choose.", needle]);
    }
}

// ---------------------------------------------------------------------------------------
// reach avoid --choose

#[test]
fn move_choose_flags_act_as_the_task_files_choose() {
    // The motion of examples/choose_tracking.toml given on the command line.
    let line = [
        "move",
        "ur5",
        "--from-xyz",
        "0.4,-0.2,0.3",
        "--from-rpy",
        "180,0,0",
        "--to-xyz",
        "0.4,0.2,0.3",
        "--to-rpy",
        "180,0,0",
        "--space",
        "tool",
        "--duration",
        "4",
        "--dt",
        "0.1",
    ];
    let with = |extra: &[&'static str]| [line.as_slice(), extra, &["--json"]].concat();
    let choices = |r: &Value| -> Vec<(String, String)> {
        r["intervals"]
            .as_array()
            .unwrap()
            .iter()
            .map(|i| (i["configuration"].as_str().unwrap().to_string(), i["decision"].as_str().unwrap().to_string()))
            .collect()
    };
    let chosen = json(&with(&["--choose", "topsis", "--criteria", "limits,manipulability", "--weights", "0.5,0.5"]));
    assert_eq!(choices(&chosen), vec![("shoulder=w config=−β wrist=e5".into(), "criterion".into())]);
    // The same samples as `reach plan` on the task file with that [choose].
    let plan = json(&["plan", "examples/choose_tracking.toml", "--json"]);
    assert_eq!(chosen["samples"], plan["motions"][0]["samples"]);
    // Without --choose the default configuration; with j2 (less joint motion) the other one.
    let plain = json(&with(&[]));
    assert_eq!(choices(&plain), vec![("shoulder=w config=+β wrist=e5".into(), "default".into())]);
    let j2 = json(&with(&["--choose", "vikor", "--criteria", "j2"]));
    assert_eq!(choices(&j2), vec![("shoulder=w config=+β wrist=e5".into(), "criterion".into())]);
    let text = ok(&line.iter().copied().chain(["--choose", "topsis", "--criteria", "limits"]).collect::<Vec<_>>());
    assert!(text.contains("(shoulder=w config=−β wrist=e5), chosen by the criteria"), "{text}");
    // J1/J2 joint weights are --joint-weights: joint 1 alone moving 90° gives J1 = π/2.
    let joint = ["move", "ur5", "--from", "0,0,0,0,0,0", "--to", "90,0,0,0,0,0"];
    let r = json(&[joint.as_slice(), &["--joint-weights", "1,0,0,0,0,0", "--json"]].concat());
    assert!((r["effort"]["j1"].as_f64().unwrap() - std::f64::consts::FRAC_PI_2).abs() < 1e-12, "{r}");
    // Bad input: exit 2, naming the flag.
    let bad = |extra: &[&'static str], needles: &[&str]| fails(&[line.as_slice(), extra].concat(), 2, needles);
    bad(&["--choose", "nope", "--criteria", "limits"], &["--choose", "nope"]);
    bad(&["--choose", "topsis", "--criteria", "limits,bogus"], &["--criteria", "bogus"]);
    bad(&["--choose", "topsis", "--criteria", "limits", "--weights", "1,2"], &["--weights", "expected 1 weights"]);
    // Usage errors (clap, several lines): --choose needs --criteria, --weights needs --choose.
    for (extra, needle) in [(&["--choose", "topsis"][..], "--criteria"), (&["--weights", "1"][..], "--choose")] {
        let run = reach(&[line.as_slice(), extra].concat());
        assert_eq!(run.code, 2, "{extra:?}: {}", run.stderr);
        assert!(run.stdout.is_empty() && run.stderr.contains(needle), "{extra:?}: {}", run.stderr);
    }
    fails(&[joint.as_slice(), &["--choose", "topsis", "--criteria", "limits"]].concat(), 2, &["use tool space"]);
}

#[test]
fn avoid_choose_plans_both_sides_and_says_when_only_one_is_feasible() {
    let args =
        ["avoid", "planar3", "--from", "60,-40,-30", "--to-xy", "2.4,0.2", "--obstacle", "2.0,0.7", "--step", "0.1"];
    let mut with = args.to_vec();
    with.extend(["--choose", "topsis", "--json"]);
    let r = json(&with);
    let sides = r["sides"].as_array().unwrap();
    assert_eq!(sides.len(), 2);
    assert_eq!((sides[0]["side"].as_str(), sides[0]["chosen"].as_bool()), (Some("base_side"), Some(true)));
    assert_eq!(sides[1]["outcome"]["outcome"], "leg_blocked");
    assert!(sides[1]["values"].as_array().unwrap().is_empty() && sides[0]["score"].is_null());
    // The chosen plan is the thesis's (the plan without --choose).
    let mut plain = args.to_vec();
    plain.push("--json");
    let p = json(&plain);
    assert_eq!(p["waypoints_m"], r["waypoints_m"]);
    let values = nums(&sides[0]["values"]);
    let s_deg: f64 = nums(&p["leg_s_deg"]).iter().sum();
    assert!((values[0] - s_deg.to_radians()).abs() < 1e-9);
    assert!((values[1] - p["min_clearance_m"].as_f64().unwrap()).abs() < 1e-12);
    let mut text = args.to_vec();
    text.extend(["--choose", "vikor"]);
    assert!(ok(&text).contains("one feasible candidate: nothing to rank"));
    let mut bad = args.to_vec();
    bad.extend(["--choose", "electre"]);
    fails(&bad, 2, &["--choose", "electre"]);
    let mut bad = args.to_vec();
    bad.extend(["--choose", "topsis", "--criteria", "s,luck"]);
    fails(&bad, 2, &["unknown criterion `luck`"]);
    let mut bad = args.to_vec();
    bad.extend(["--choose", "topsis", "--weights", "1,1"]);
    fails(&bad, 2, &["expected 3 weights"]);
    let mut bad = args.to_vec();
    bad.extend(["--choose", "topsis", "--printed-waypoints"]);
    assert_eq!(reach(&bad).code, 2);
}

// reach tasks with cost = "energy"

/// The configurations of a `reach tasks --json` report in radians (node 0 first; `None`:
/// unreachable). Every joint of the robots used here is revolute.
fn task_configs(r: &Value) -> Vec<Option<Vec<f64>>> {
    let rad = |v: &Value| nums(v).into_iter().map(f64::to_radians).collect::<Vec<f64>>();
    let mut configs = vec![Some(rad(&r["node0_q_deg"]))];
    configs.extend(r["points"].as_array().unwrap().iter().map(|p| (!p["q_deg"].is_null()).then(|| rad(&p["q_deg"]))));
    configs
}

/// The leg-energy matrix (J) recomputed by the library from the report's configurations with
/// the example's speed limits and profile.
fn puma_energy_matrix(r: &Value, kind: reach::decide::sequence::EnergyKind) -> Vec<Vec<f64>> {
    use reach::decide::sequence::{energy_costs, leg_durations};
    use reach::motion::{JointRates, Profile};
    let puma = reach::model::presets::get("puma560").unwrap();
    let rates =
        JointRates::new([60.0f64, 60.0, 60.0, 120.0, 120.0, 120.0].iter().map(|v| v.to_radians()).collect(), None)
            .unwrap();
    let configs = task_configs(r);
    let d = leg_durations(&puma, &configs, &rates, Profile::Cycloidal).unwrap();
    energy_costs(&puma, &configs, &d, Profile::Cycloidal, kind).unwrap()
}

#[test]
fn energy_visiting_on_puma560_is_optimal_against_brute_force_over_the_same_leg_energies() {
    let r = json(&["tasks", "puma560", "visiting", "examples/tasks_visiting_energy.toml", "--json"]);
    assert_eq!(r["cost"], "energy");
    assert_eq!(r["unreachable"], serde_json::json!([4]));
    let e = puma_energy_matrix(&r, reach::decide::sequence::EnergyKind::Absolute);
    let plan = &r["plan"];
    assert_eq!(plan["exact"], true);
    let order: Vec<usize> = plan["order"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap() as usize).collect();
    let tour = |o: &[usize]| -> f64 {
        let mut prev = 0;
        o.iter()
            .map(|&j| {
                let c = e[prev][j];
                prev = j;
                c
            })
            .sum()
    };
    // Per leg: the library's energy and J1; totals are the sums.
    let mut prev = 0;
    let configs = task_configs(&r);
    for (leg, &j) in plan["legs"].as_array().unwrap().iter().zip(&order) {
        assert_eq!(leg["point"].as_u64().unwrap() as usize, j);
        assert!((num(&leg["energy_j"]) - e[prev][j]).abs() < 1e-6 * e[prev][j], "leg to {j}");
        let (a, b) = (configs[prev].as_ref().unwrap(), configs[j].as_ref().unwrap());
        let j1 = j1_deg(
            &a.iter().map(|v| v.to_degrees()).collect::<Vec<_>>(),
            &b.iter().map(|v| v.to_degrees()).collect::<Vec<_>>(),
        );
        assert!((num(&leg["j1_rad"]) - j1).abs() < 1e-9, "J1 of the leg to {j}");
        prev = j;
    }
    let total = num(&plan["total_energy_j"]);
    assert!((total - tour(&order)).abs() < 1e-6 * total);
    // Brute force over every order of the six reachable points.
    let mut items: Vec<usize> = vec![1, 2, 3, 5, 6, 7];
    let mut best = f64::INFINITY;
    permutations(&mut items, 0, &mut |p| best = best.min(tour(p)));
    assert!((total - best).abs() < 1e-6 * best, "plan {total} J, brute force {best} J");
    // The J1 plan of the same file orders the points differently: less J1, more energy.
    let text = std::fs::read_to_string(format!("{}/examples/tasks_visiting_energy.toml", common::REPO_ROOT)).unwrap();
    let j1_file = temp_file("energy_as_j1.toml", &text.replace("cost = \"energy\"", "cost = \"j1\""));
    let j1 = json(&["tasks", "puma560", "visiting", j1_file.to_str().unwrap(), "--json"]);
    assert_eq!(j1["cost"], "j1");
    assert!(j1["plan"]["total_energy_j"].is_null() && j1["plan"]["legs"][0]["energy_j"].is_null());
    let j1_order: Vec<usize> =
        j1["plan"]["order"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap() as usize).collect();
    assert_ne!(j1_order, order);
    assert!(tour(&j1_order) > total + 1.0, "J1 order {} J vs energy plan {total} J", tour(&j1_order));
    assert!(num(&j1["plan"]["total_j1_rad"]) < num(&plan["total_j1_rad"]) - 1e-6);
    // Text: units on every energy figure.
    let out = ok(&["tasks", "puma560", "visiting", "examples/tasks_visiting_energy.toml"]);
    assert!(out.contains("leg energy [J]") && out.contains("leg J1 [rad]"), "{out}");
    assert!(out.contains(&format!("energy {total:.3} J")), "{out}");
}

#[test]
fn energy_collection_sums_both_moves_of_each_trip_and_bad_energy_input_exits_2() {
    let file = temp_file(
        "energy_collection.toml",
        "cost = \"energy\"\nmax_velocity = [60, 60, 60, 120, 120, 120]\ncontainer = [0.57, 0.00, 1.01]\n\
         objects = [[0.57, -0.50, 0.79], [0.69, 0.38, 1.01], [0.76, -0.02, 0.30]]\n",
    );
    let r = json(&["tasks", "puma560", "collection", file.to_str().unwrap(), "--budget", "20", "--json"]);
    let e = puma_energy_matrix(&r, reach::decide::sequence::EnergyKind::Absolute);
    for plan in [&r["plan"], &r["within_budget"]] {
        let mut sum = 0.0;
        for leg in plan["legs"].as_array().unwrap() {
            let j = leg["point"].as_u64().unwrap() as usize;
            let trip = e[0][j] + e[j][0];
            assert!((num(&leg["energy_j"]) - trip).abs() < 1e-6 * trip, "trip {j}");
            sum += trip;
        }
        assert!((num(&plan["total_energy_j"]) - sum).abs() < 1e-6 * sum);
    }
    assert_eq!(r["plan"]["legs"].as_array().unwrap().len(), 3);
    assert!(r["plan"]["method"].as_str().unwrap().contains("increasing energy"));
    // No masses: names the robot and the key; no speed limits: asks for max_velocity.
    let spbu6 = temp_file("energy_spbu6.toml", "cost = \"energy\"\ntargets = [[0.4, -0.2, 0.1]]\n");
    fails(&["tasks", "spbu6", "visiting", spbu6.to_str().unwrap()], 2, &["`spbu6`", "cost = \"energy\"", "masses"]);
    let slow = temp_file("energy_no_limits.toml", "cost = \"energy\"\ntargets = [[0.57, 0.0, 1.01]]\n");
    fails(&["tasks", "puma560", "visiting", slow.to_str().unwrap()], 2, &["`puma560`", "max_velocity"]);
    let unknown = temp_file("energy_unknown.toml", "cost = \"joules\"\ntargets = [[0.57, 0.0, 1.01]]\n");
    fails(&["tasks", "puma560", "visiting", unknown.to_str().unwrap()], 2, &["cost", "joules"]);
}

#[test]
fn positive_work_visiting_on_puma560_is_optimal_on_its_asymmetric_matrix() {
    let text = std::fs::read_to_string(format!("{}/examples/tasks_visiting_energy.toml", common::REPO_ROOT)).unwrap();
    let file = temp_file("positive_work.toml", &text.replace("cost = \"energy\"", "cost = \"positive_work\""));
    let r = json(&["tasks", "puma560", "visiting", file.to_str().unwrap(), "--json"]);
    assert_eq!(r["cost"], "positive_work");
    let w = puma_energy_matrix(&r, reach::decide::sequence::EnergyKind::PositiveWork);
    // Points at different heights: the matrix is asymmetric by the potential energy differences.
    assert!(w[7][3] > w[3][7] + 5.0, "0.30 m → 1.01 m {} J vs back {} J", w[7][3], w[3][7]);
    let tour = |o: &[usize]| -> f64 {
        let mut prev = 0;
        o.iter()
            .map(|&j| {
                let c = w[prev][j];
                prev = j;
                c
            })
            .sum()
    };
    let order: Vec<usize> =
        r["plan"]["order"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap() as usize).collect();
    let total = num(&r["plan"]["total_energy_j"]);
    assert!((total - tour(&order)).abs() < 1e-6 * total);
    let mut items: Vec<usize> = vec![1, 2, 3, 5, 6, 7];
    let mut best = f64::INFINITY;
    permutations(&mut items, 0, &mut |p| best = best.min(tour(p)));
    assert!((total - best).abs() < 1e-6 * best, "plan {total} J, brute force {best} J");
    let out = ok(&["tasks", "puma560", "visiting", file.to_str().unwrap()]);
    assert!(out.contains("positive work") && out.contains("leg energy [J]"), "{out}");
}

/// The `tasks` job of `reach tasks ROBOT KIND FILE [--budget S]`, as the library runs it.
fn tasks_job(robot: &str, kind: reach::jobs::tasks::TaskKind, file: &str, budget_s: Option<f64>) -> reach::jobs::Job {
    let task = std::fs::read_to_string(format!("{}/{file}", common::REPO_ROOT)).unwrap();
    reach::jobs::Job {
        robot: reach::jobs::RobotInput::Preset(robot.into()),
        request: reach::jobs::Request::Tasks(reach::jobs::TasksRequest { task_kind: kind, task, budget_s }),
    }
}

#[test]
fn tasks_json_is_the_library_report() {
    use reach::jobs::tasks::TaskKind;
    let file = "examples/tasks_visiting.toml";
    let r = common::assert_report(
        &["tasks", "ur5", "visiting", file, "--budget", "6", "--json"],
        &tasks_job("ur5", TaskKind::Visiting, file, Some(6.0)),
        "tasks.report",
    );
    assert!(r["within_budget"]["total_duration_s"].as_f64().unwrap() <= 6.0);
    let file = "examples/tasks_collection.toml";
    common::assert_report(
        &["tasks", "ur5", "collection", file, "--budget", "8", "--json"],
        &tasks_job("ur5", TaskKind::Collection, file, Some(8.0)),
        "tasks.report",
    );
    let file = "examples/tasks_visiting_energy.toml";
    let r = common::assert_report(
        &["tasks", "puma560", "visiting", file, "--json"],
        &tasks_job("puma560", TaskKind::Visiting, file, None),
        "tasks.report",
    );
    assert!(r["plan"]["total_energy_j"].as_f64().unwrap() > 0.0);
}

/// Seed 003's stiffness and accuracy criteria (docs/choosing.md): each ranked value is
/// recomputed from the eigenvalues of `J_p J_pᵀ` at the solution (not the singular values the
/// library uses), and the two criteria are accepted by `reach move --choose` too.
#[test]
fn stiffness_and_accuracy_rank_ik_solutions_by_the_position_jacobian() {
    let v = json(&[
        "ik",
        "ur5",
        "--matrix",
        UR5_POSE,
        "--from",
        UR5_FROM,
        "--choose",
        "topsis",
        "--criteria",
        "stiffness,accuracy",
        "--json",
    ]);
    let ranking = &v["ranking"];
    assert_eq!(ranking["criteria"][0]["name"], "stiffness");
    assert_eq!(ranking["criteria"][0]["direction"], "more_is_better");
    assert_eq!(
        (ranking["criteria"][1]["name"].as_str(), ranking["criteria"][1]["unit"].as_str()),
        (Some("accuracy"), Some("m"))
    );
    assert_eq!(ranking["criteria"][1]["direction"], "less_is_better");
    let robot = reach::model::presets::get("ur5").unwrap();
    let ranked = ranking["ranked"].as_array().unwrap();
    assert_eq!(ranked.len(), 8);
    for row in ranked {
        let i = row["solution"].as_u64().unwrap() as usize;
        let q: Vec<f64> = nums(&v["solutions"][i]["q_deg"]).iter().map(|d| d.to_radians()).collect();
        let j = robot.jacobian(&q).unwrap();
        let jp = j.fixed_rows::<3>(0).into_owned();
        let eig = (&jp * jp.transpose()).symmetric_eigen().eigenvalues;
        let (lo, hi) = (eig.min().sqrt(), eig.max().sqrt());
        let values = nums(&row["values"]);
        assert!((values[0] - lo / hi).abs() < 1e-6, "solution {i}: {values:?} vs {}", lo / hi);
        assert!((values[1] - hi * 0.01f64.to_radians()).abs() < 1e-9, "solution {i}: {values:?}");
    }
    let v = json(&[
        "move",
        "ur5",
        "--from-xyz",
        "0.4,-0.2,0.3",
        "--from-rpy",
        "180,0,0",
        "--to-xyz",
        "0.4,0.2,0.3",
        "--to-rpy",
        "180,0,0",
        "--space",
        "tool",
        "--duration",
        "4",
        "--dt",
        "0.1",
        "--choose",
        "topsis",
        "--criteria",
        "stiffness,accuracy",
        "--json",
    ]);
    assert!(v["intervals"].as_array().is_some_and(|i| !i.is_empty()));
}
