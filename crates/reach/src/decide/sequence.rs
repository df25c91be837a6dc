//! Task sequencing (seed 001 §8, "collection" and "visiting" tasks).
//!
//! **Numbering.** Every cost or duration matrix is `(n+1) × (n+1)`: node 0 is the start
//! configuration (visiting) or the container (collection), nodes `1..=n` are the targets.
//! Entry `[i][j]` is the cost of moving from node `i` to node `j` (asymmetric allowed);
//! entries are `>= 0` or `+∞` ("impossible"); the diagonal is ignored.
//!
//! **Unreachable targets.** A target `j` whose cost from node 0 (`[0][j]`) or, for collection,
//! back to node 0 (`[j][0]`) is `+∞` is unreachable (e.g. no IK solution): it is listed in
//! `skipped` and left out. [`joint_change_costs`] builds such a matrix from IK solutions.
//!
//! **Visiting** is an open path from node 0 through every reachable target (asymmetric
//! shortest Hamiltonian path). Exact by Held–Karp dynamic programming up to
//! [`EXACT_MAX_TARGETS`] targets; beyond, nearest neighbour followed by 2-opt (segment
//! reversals, evaluated in O(1) with prefix sums so that asymmetric costs are handled).
//!
//! **Collection** is a sequence of independent trips container → object → container. The
//! energy of trip `j` is `[0][j] + [j][0]`, and the total energy `Σ` over trips does **not**
//! depend on the order (asymmetric or not), because every trip starts and ends at the same
//! container configuration. Ordering therefore matters only under a time budget: the largest
//! number of objects that fit is obtained by taking trips in increasing duration (exchange
//! argument: any feasible set of k trips can be replaced by the k shortest), ties broken by
//! lower energy, then by index.
//!
//! **Costs.** [`config_costs`] gives seed 001's J1 (rad) between chosen configurations;
//! [`leg_durations`] the synchronised point-to-point duration of every leg within the joint
//! speed limits (s); [`energy_costs`] the mechanical energy of every such leg (J) for robots
//! with link masses. That energy counts braking as spent (`∫ Σ|τᵢ·q̇ᵢ| dt`), so a leg and its
//! reverse cost the same: the reverse of a rest-to-rest move with a symmetric profile is
//! `q(T − t)`, with the same torques at mirrored instants and negated rates. Gravity decides
//! how large the energy is, not its direction. With [`EnergyKind::PositiveWork`] braking is free
//! (`∫ Σ max(τᵢ·q̇ᵢ, 0) dt`): then a leg costs its reverse plus the potential energy it gains,
//! and the matrix is asymmetric; both solvers handle asymmetric matrices.

use serde::Serialize;

use super::DecideError;
use super::motion_criteria::point_to_point_duration;
use crate::effort::dynamics::{mechanical_energy, positive_work};
use crate::ik::IkSolutions;
use crate::model::Robot;
use crate::motion::{JointMotion, JointRates, Profile};

/// Largest number of reachable targets solved exactly (Held–Karp, `O(2ⁿ n²)`).
pub const EXACT_MAX_TARGETS: usize = 12;

/// An ordered plan over targets.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sequence {
    /// Target node numbers (`1..=n`) in execution order.
    pub order: Vec<usize>,
    /// Total cost of the plan (sum of `legs`).
    pub cost: f64,
    /// Cost of each leg (visiting: from the previous node; collection: the whole trip).
    pub legs: Vec<f64>,
    /// Total duration, when durations were given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub duration: Option<f64>,
    /// Whether the plan is provably optimal.
    pub exact: bool,
    /// Unreachable targets (node numbers), left out.
    pub skipped: Vec<usize>,
}

fn check_matrix(what: &'static str, m: &[Vec<f64>]) -> Result<usize, DecideError> {
    let size = m.len();
    if size == 0 {
        return Err(DecideError::CostShape {
            what,
            reason: "empty; expected (n+1)×(n+1) with node 0 the start".into(),
        });
    }
    for (i, row) in m.iter().enumerate() {
        if row.len() != size {
            return Err(DecideError::CostShape {
                what,
                reason: format!("row {i} has {} entries, expected {size} (square matrix)", row.len()),
            });
        }
        for (j, &v) in row.iter().enumerate() {
            if i != j && (v.is_nan() || v < 0.0) {
                return Err(DecideError::InvalidCost { what, from: i, to: j, value: v });
            }
        }
    }
    Ok(size - 1)
}

fn same_shape(a: &[Vec<f64>], b: &[Vec<f64>]) -> Result<(), DecideError> {
    if a.len() != b.len() {
        return Err(DecideError::CostShape {
            what: "durations",
            reason: format!("{} nodes, but the cost matrix has {}", b.len(), a.len()),
        });
    }
    Ok(())
}

fn path_cost(c: &[Vec<f64>], order: &[usize]) -> (f64, Vec<f64>) {
    let mut prev = 0;
    let legs: Vec<f64> = order
        .iter()
        .map(|&j| {
            let l = c[prev][j];
            prev = j;
            l
        })
        .collect();
    (legs.iter().sum(), legs)
}

/// Exact shortest open path from node 0 through all of `nodes` (Held–Karp). Returns the order.
fn held_karp(c: &[Vec<f64>], nodes: &[usize]) -> Vec<usize> {
    let m = nodes.len();
    if m == 0 {
        return Vec::new();
    }
    let full = 1usize << m;
    let mut dp = vec![f64::INFINITY; full * m];
    let mut parent = vec![usize::MAX; full * m];
    for k in 0..m {
        dp[(1 << k) * m + k] = c[0][nodes[k]];
    }
    for mask in 1..full {
        for last in 0..m {
            let cur = dp[mask * m + last];
            if mask & (1 << last) == 0 || cur == f64::INFINITY {
                continue;
            }
            for next in 0..m {
                if mask & (1 << next) != 0 {
                    continue;
                }
                let nm = mask | (1 << next);
                let v = cur + c[nodes[last]][nodes[next]];
                // Strict `<` keeps the first (lowest-index) predecessor: deterministic ties.
                if v < dp[nm * m + next] {
                    dp[nm * m + next] = v;
                    parent[nm * m + next] = last;
                }
            }
        }
    }
    let mask = full - 1;
    let mut last = (0..m).fold(0, |b, k| if dp[mask * m + k] < dp[mask * m + b] { k } else { b });
    let mut order = Vec::with_capacity(m);
    let mut mask = mask;
    loop {
        order.push(nodes[last]);
        let p = parent[mask * m + last];
        mask &= !(1 << last);
        if p == usize::MAX {
            break;
        }
        last = p;
    }
    order.reverse();
    order
}

/// Nearest neighbour from node 0 (ties by lower node number).
fn nearest_neighbour(c: &[Vec<f64>], nodes: &[usize]) -> Vec<usize> {
    let mut left: Vec<usize> = nodes.to_vec();
    let mut order = Vec::with_capacity(nodes.len());
    let mut cur = 0;
    while !left.is_empty() {
        let mut best = 0;
        for k in 1..left.len() {
            if c[cur][left[k]] < c[cur][left[best]] {
                best = k;
            }
        }
        cur = left.remove(best);
        order.push(cur);
    }
    order
}

/// 2-opt on an open path that starts at node 0 (fixed); first-improvement, until no
/// reversal improves by more than a relative 1e-12 (at most 100 000 passes, a safety cap).
fn two_opt(c: &[Vec<f64>], order: &mut [usize]) {
    let n = order.len();
    if n < 2 {
        return;
    }
    let mut improved = true;
    let mut passes = 0;
    while improved && passes < 100_000 {
        improved = false;
        passes += 1;
        // p[k] = node at position k, position 0 = start.
        let p: Vec<usize> = std::iter::once(0).chain(order.iter().copied()).collect();
        // fwd[k] = Σ_{t<k} c[p_t][p_{t+1}], rev[k] = Σ_{t<k} c[p_{t+1}][p_t].
        let mut fwd = vec![0.0; n + 1];
        let mut rev = vec![0.0; n + 1];
        for t in 0..n {
            fwd[t + 1] = fwd[t] + c[p[t]][p[t + 1]];
            rev[t + 1] = rev[t] + c[p[t + 1]][p[t]];
        }
        'outer: for i in 1..n {
            for j in (i + 1)..=n {
                // Reverse positions i..=j.
                let old_in = c[p[i - 1]][p[i]];
                let new_in = c[p[i - 1]][p[j]];
                let (old_out, new_out) = if j < n { (c[p[j]][p[j + 1]], c[p[i]][p[j + 1]]) } else { (0.0, 0.0) };
                let old_mid = fwd[j] - fwd[i];
                let new_mid = rev[j] - rev[i];
                let delta = (new_in + new_out + new_mid) - (old_in + old_out + old_mid);
                if delta < -1e-12 * (1.0 + fwd[n].abs()) {
                    order[i - 1..j].reverse();
                    improved = true;
                    break 'outer;
                }
            }
        }
    }
}

/// Orders the reachable targets as an open path from node 0 minimising total cost.
///
/// # Errors
/// [`DecideError::CostShape`], [`DecideError::InvalidCost`].
pub fn visiting(costs: &[Vec<f64>]) -> Result<Sequence, DecideError> {
    let n = check_matrix("costs", costs)?;
    let (nodes, skipped): (Vec<usize>, Vec<usize>) = (1..=n).partition(|&j| costs[0][j].is_finite());
    let exact = nodes.len() <= EXACT_MAX_TARGETS;
    let order = if exact {
        held_karp(costs, &nodes)
    } else {
        let mut o = nearest_neighbour(costs, &nodes);
        two_opt(costs, &mut o);
        o
    };
    let (cost, legs) = path_cost(costs, &order);
    Ok(Sequence { order, cost, legs, duration: None, exact, skipped })
}

/// Heuristic visiting order (nearest neighbour + 2-opt) regardless of size; for measuring the
/// heuristic's gap against [`visiting`]'s exact answer.
///
/// # Errors
/// As [`visiting`].
pub fn visiting_heuristic(costs: &[Vec<f64>]) -> Result<Sequence, DecideError> {
    let n = check_matrix("costs", costs)?;
    let (nodes, skipped): (Vec<usize>, Vec<usize>) = (1..=n).partition(|&j| costs[0][j].is_finite());
    let mut order = nearest_neighbour(costs, &nodes);
    two_opt(costs, &mut order);
    let (cost, legs) = path_cost(costs, &order);
    Ok(Sequence { order, cost, legs, duration: None, exact: false, skipped })
}

/// The largest number of reachable targets the tool can visit (open path from node 0) within
/// `budget` seconds, given per-leg `durations` (same shape as `costs`). Exact (dynamic
/// programming over subsets, minimum duration per subset and last target) up to
/// [`EXACT_MAX_TARGETS`] targets; among the largest feasible subsets the one with the shortest
/// duration is returned (ties: the first found). Beyond, the longest prefix within budget of the
/// heuristic duration-ordered path (`exact = false`).
///
/// # Errors
/// Shape/value errors of either matrix; [`DecideError::InvalidBudget`].
pub fn visiting_within_budget(
    costs: &[Vec<f64>],
    durations: &[Vec<f64>],
    budget: f64,
) -> Result<Sequence, DecideError> {
    let n = check_matrix("costs", costs)?;
    check_matrix("durations", durations)?;
    same_shape(costs, durations)?;
    if !budget.is_finite() || budget < 0.0 {
        return Err(DecideError::InvalidBudget(budget));
    }
    let (nodes, skipped): (Vec<usize>, Vec<usize>) =
        (1..=n).partition(|&j| costs[0][j].is_finite() && durations[0][j].is_finite());
    let m = nodes.len();
    let d = durations;
    let (order, exact) = if m <= EXACT_MAX_TARGETS {
        let full = 1usize << m;
        let mut dp = vec![f64::INFINITY; full * m.max(1)];
        let mut parent = vec![usize::MAX; full * m.max(1)];
        for k in 0..m {
            dp[(1 << k) * m + k] = d[0][nodes[k]];
        }
        let mut best: Option<(u32, f64, usize, usize)> = None; // (count, duration, mask, last)
        for mask in 1..full {
            for last in 0..m {
                let cur = dp[mask * m + last];
                if mask & (1 << last) == 0 || cur > budget {
                    continue;
                }
                let cnt = mask.count_ones();
                if best.is_none_or(|(bc, bd, _, _)| cnt > bc || (cnt == bc && cur < bd)) {
                    best = Some((cnt, cur, mask, last));
                }
                for next in 0..m {
                    if mask & (1 << next) != 0 {
                        continue;
                    }
                    let nm = mask | (1 << next);
                    let v = cur + d[nodes[last]][nodes[next]];
                    if v < dp[nm * m + next] {
                        dp[nm * m + next] = v;
                        parent[nm * m + next] = last;
                    }
                }
            }
        }
        let mut order = Vec::new();
        if let Some((_, _, mut mask, mut last)) = best {
            loop {
                order.push(nodes[last]);
                let p = parent[mask * m + last];
                mask &= !(1 << last);
                if p == usize::MAX {
                    break;
                }
                last = p;
            }
            order.reverse();
        }
        (order, true)
    } else {
        let mut o = nearest_neighbour(d, &nodes);
        two_opt(d, &mut o);
        let mut t = 0.0;
        let mut prev = 0;
        let mut keep = 0;
        for &j in &o {
            t += d[prev][j];
            if t > budget {
                break;
            }
            prev = j;
            keep += 1;
        }
        o.truncate(keep);
        (o, false)
    };
    let (cost, legs) = path_cost(costs, &order);
    let (duration, _) = path_cost(d, &order);
    Ok(Sequence { order, cost, legs, duration: Some(duration), exact, skipped })
}

/// Collection: trips container (node 0) → object → container for every reachable object,
/// cheapest trip first (ties by index). The total energy is order-independent (module docs);
/// `legs` holds each trip's energy `[0][j] + [j][0]`. `exact` is always true.
///
/// # Errors
/// [`DecideError::CostShape`], [`DecideError::InvalidCost`].
pub fn collection(costs: &[Vec<f64>]) -> Result<Sequence, DecideError> {
    let n = check_matrix("costs", costs)?;
    let (mut nodes, skipped): (Vec<usize>, Vec<usize>) =
        (1..=n).partition(|&j| costs[0][j].is_finite() && costs[j][0].is_finite());
    let trip = |j: usize| costs[0][j] + costs[j][0];
    nodes.sort_by(|&a, &b| trip(a).total_cmp(&trip(b)).then(a.cmp(&b)));
    let legs: Vec<f64> = nodes.iter().map(|&j| trip(j)).collect();
    Ok(Sequence { cost: legs.iter().sum(), legs, order: nodes, duration: None, exact: true, skipped })
}

/// Collection within a time budget: the largest number of objects whose trips
/// (`durations[0][j] + durations[j][0]`) fit in `budget` seconds — the shortest trips, ties by
/// lower energy then index (optimal: see module docs).
///
/// # Errors
/// Shape/value errors of either matrix; [`DecideError::InvalidBudget`].
pub fn collection_within_budget(
    costs: &[Vec<f64>],
    durations: &[Vec<f64>],
    budget: f64,
) -> Result<Sequence, DecideError> {
    let n = check_matrix("costs", costs)?;
    check_matrix("durations", durations)?;
    same_shape(costs, durations)?;
    if !budget.is_finite() || budget < 0.0 {
        return Err(DecideError::InvalidBudget(budget));
    }
    let reach = |j: usize| {
        costs[0][j].is_finite() && costs[j][0].is_finite() && durations[0][j].is_finite() && durations[j][0].is_finite()
    };
    let (mut nodes, skipped): (Vec<usize>, Vec<usize>) = (1..=n).partition(|&j| reach(j));
    let trip = |j: usize| costs[0][j] + costs[j][0];
    let time = |j: usize| durations[0][j] + durations[j][0];
    nodes.sort_by(|&a, &b| time(a).total_cmp(&time(b)).then(trip(a).total_cmp(&trip(b))).then(a.cmp(&b)));
    let mut t = 0.0;
    let mut order = Vec::new();
    for j in nodes {
        if t + time(j) > budget {
            break;
        }
        t += time(j);
        order.push(j);
    }
    let legs: Vec<f64> = order.iter().map(|&j| trip(j)).collect();
    Ok(Sequence { cost: legs.iter().sum(), legs, order, duration: Some(t), exact: true, skipped })
}

/// Configurations and a cost matrix built from IK solutions (seed 001 §3.8 J1).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConfigCosts {
    /// Node 0's configuration followed by the chosen configuration per target (`None`:
    /// no feasible IK solution — unreachable).
    pub configs: Vec<Option<Vec<f64>>>,
    /// `(n+1)×(n+1)` matrix of J1 = `Σ ωᵢ |qᵢ − q'ᵢ|` (joint differences as
    /// [`Joint::difference`](crate::model::Joint::difference), as the leg durations) between
    /// configurations; `+∞` to and from unreachable targets.
    pub costs: Vec<Vec<f64>>,
}

/// Builds [`ConfigCosts`]: for each target, the feasible IK solution with the smallest weighted
/// joint change from `start` ([`IkSolutions::closest_to`]), then the J1 matrix between all
/// chosen configurations.
///
/// # Errors
/// [`DecideError::BadVector`] when `start` or `weights` do not have one finite value per joint
/// (weights also `>= 0`).
pub fn joint_change_costs(
    robot: &Robot,
    start: &[f64],
    targets: &[IkSolutions],
    weights: &[f64],
) -> Result<ConfigCosts, DecideError> {
    let dof = robot.dof();
    for (what, v, w) in [("start", start, false), ("joint weights", weights, true)] {
        if v.len() != dof || v.iter().any(|x| !x.is_finite() || (w && *x < 0.0)) {
            return Err(DecideError::BadVector {
                what,
                reason: format!("expected {dof} finite values{}, got {v:?}", if w { " >= 0" } else { "" }),
            });
        }
    }
    let mut configs = vec![Some(start.to_vec())];
    configs.extend(targets.iter().map(|t| {
        let mut near = t.clone();
        near.express_near(robot, start);
        near.closest_to(start, weights).map(|s| s.q.clone())
    }));
    config_costs(robot, configs, weights)
}

/// Builds [`ConfigCosts`] from configurations already chosen (node 0 first; `None`:
/// unreachable): the J1 matrix `Σ ωᵢ |qᵢ − q'ᵢ|` between them, joint differences as
/// [`Joint::difference`](crate::model::Joint::difference) (what the leg's joint-space move
/// travels, the same rule as [`leg_durations`] and [`energy_costs`]).
///
/// # Errors
/// [`DecideError::BadVector`] when `weights` or a configuration does not have one finite value
/// per joint (weights also `>= 0`), or node 0 is `None`.
pub fn config_costs(
    robot: &Robot,
    configs: Vec<Option<Vec<f64>>>,
    weights: &[f64],
) -> Result<ConfigCosts, DecideError> {
    let dof = robot.dof();
    crate::effort::joint_weights(robot, Some(weights)).map_err(|e| DecideError::BadVector {
        what: "joint weights",
        reason: format!("expected {dof} finite values >= 0: {e}"),
    })?;
    check_configs(robot, &configs)?;
    let j1 = |a: &[f64], b: &[f64]| -> f64 {
        robot.joints().iter().enumerate().map(|(i, jt)| weights[i] * jt.difference(a[i], b[i]).abs()).sum()
    };
    let costs = configs
        .iter()
        .map(|a| {
            configs
                .iter()
                .map(|b| match (a, b) {
                    (Some(a), Some(b)) => j1(a, b),
                    _ => f64::INFINITY,
                })
                .collect()
        })
        .collect();
    Ok(ConfigCosts { configs, costs })
}

/// Which mechanical energy [`leg_energy`] integrates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EnergyKind {
    /// `∫ Σᵢ |τᵢ·q̇ᵢ| dt` ([`mechanical_energy`]): braking counted as spent; a move and its
    /// reverse cost the same.
    Absolute,
    /// `∫ Σᵢ max(τᵢ·q̇ᵢ, 0) dt` ([`positive_work`]): braking free; lifting costs more than
    /// lowering by the potential energy gained.
    PositiveWork,
}

/// Sample intervals per leg in [`energy_costs`] (so `ENERGY_INTERVALS_PER_LEG + 1` samples,
/// both ends included).
pub const ENERGY_INTERVALS_PER_LEG: usize = 64;

fn check_configs(robot: &Robot, configs: &[Option<Vec<f64>>]) -> Result<(), DecideError> {
    let dof = robot.dof();
    if configs.first().is_none_or(Option::is_none) {
        return Err(DecideError::BadVector { what: "configurations", reason: "node 0 (start) is missing".into() });
    }
    if let Some(k) =
        configs.iter().position(|c| c.as_ref().is_some_and(|q| q.len() != dof || q.iter().any(|v| !v.is_finite())))
    {
        return Err(DecideError::BadVector {
            what: "configurations",
            reason: format!("node {k}: expected {dof} finite joint values"),
        });
    }
    Ok(())
}

/// `(n+1)×(n+1)` matrix of leg durations (s): entry `[i][j]` is the duration of the fastest
/// synchronised point-to-point joint move from configuration `i` to `j` with `profile` within
/// `rates` ([`point_to_point_duration`]; joint differences as [`Joint::difference`](crate::model::Joint::difference)); `0` on the
/// diagonal, `+∞` to and from unreachable (`None`) nodes.
///
/// # Errors
/// [`DecideError::BadVector`] for a missing node 0 or a configuration without one finite value
/// per joint; [`DecideError::Criterion`] when the differences do not fit `rates`.
pub fn leg_durations(
    robot: &Robot,
    configs: &[Option<Vec<f64>>],
    rates: &JointRates,
    profile: Profile,
) -> Result<Vec<Vec<f64>>, DecideError> {
    check_configs(robot, configs)?;
    // The synchronised duration depends only on |Δq|: each pair is timed once and mirrored.
    let mut d = vec![vec![f64::INFINITY; configs.len()]; configs.len()];
    for (i, a) in configs.iter().enumerate() {
        let Some(a) = a else { continue };
        d[i][i] = 0.0;
        for (j, b) in configs.iter().enumerate().skip(i + 1) {
            if let Some(b) = b {
                let delta: Vec<f64> =
                    robot.joints().iter().enumerate().map(|(n, jt)| jt.difference(a[n], b[n])).collect();
                d[i][j] = point_to_point_duration(&delta, rates, profile)?;
                d[j][i] = d[i][j];
            }
        }
    }
    Ok(d)
}

/// Mechanical energy (J) of the point-to-point joint move from `q0` to `q1` with `profile`
/// lasting `duration` seconds ([`JointMotion::for_robot`]): `∫ Σᵢ |τᵢ·q̇ᵢ| dt`
/// ([`mechanical_energy`], braking counted as spent) or `∫ Σᵢ max(τᵢ·q̇ᵢ, 0) dt`
/// ([`positive_work`], braking free) by `kind`, with Newton–Euler torques including gravity,
/// sampled at [`ENERGY_INTERVALS_PER_LEG`]` + 1` evenly spaced instants with the motion's exact
/// rates and accelerations, trapezoid rule. A zero duration (no joint moves) costs 0 J.
///
/// # Errors
/// [`DecideError::Dynamics`] when the robot has no link masses; [`DecideError::BadVector`] for
/// bad configurations or a negative/non-finite duration.
pub fn leg_energy(
    robot: &Robot,
    q0: &[f64],
    q1: &[f64],
    duration: f64,
    profile: Profile,
    kind: EnergyKind,
) -> Result<f64, DecideError> {
    if !robot.has_dynamics() {
        return Err(crate::effort::dynamics::DynamicsError::NoInertialData { robot: robot.name().to_string() }.into());
    }
    if !duration.is_finite() || duration < 0.0 {
        return Err(DecideError::BadVector {
            what: "leg duration",
            reason: format!("must be a finite number of seconds >= 0, got {duration}"),
        });
    }
    if duration == 0.0 {
        return Ok(0.0);
    }
    let motion = JointMotion::for_robot(robot, q0, q1, 0.0, duration, profile)
        .map_err(|e| DecideError::BadVector { what: "leg", reason: e.to_string() })?;
    let n = ENERGY_INTERVALS_PER_LEG;
    let times: Vec<f64> = (0..=n).map(|k| duration * k as f64 / n as f64).collect();
    let q: Vec<Vec<f64>> = times.iter().map(|&t| motion.position(t)).collect();
    let qd: Vec<Vec<f64>> = times.iter().map(|&t| motion.velocity(t)).collect();
    let qdd: Vec<Vec<f64>> = times.iter().map(|&t| motion.acceleration(t)).collect();
    Ok(match kind {
        EnergyKind::Absolute => mechanical_energy(robot, &times, &q, &qd, &qdd)?,
        EnergyKind::PositiveWork => positive_work(robot, &times, &q, &qd, &qdd)?,
    })
}

/// `(n+1)×(n+1)` matrix of leg energies (J, [`leg_energy`]) between configurations, each leg
/// lasting `durations[i][j]` (e.g. from [`leg_durations`]) with `profile`; `0` on the diagonal,
/// `+∞` to and from unreachable (`None`) nodes. With [`EnergyKind::Absolute`] symmetric up to
/// rounding when the durations are; with [`EnergyKind::PositiveWork`] asymmetric (module docs).
///
/// # Errors
/// As [`leg_energy`]; [`DecideError::CostShape`] when `durations` does not match `configs`.
pub fn energy_costs(
    robot: &Robot,
    configs: &[Option<Vec<f64>>],
    durations: &[Vec<f64>],
    profile: Profile,
    kind: EnergyKind,
) -> Result<Vec<Vec<f64>>, DecideError> {
    check_configs(robot, configs)?;
    check_matrix("durations", durations)?;
    if durations.len() != configs.len() {
        return Err(DecideError::CostShape {
            what: "durations",
            reason: format!("{} nodes, but there are {} configurations", durations.len(), configs.len()),
        });
    }
    let mut e = vec![vec![f64::INFINITY; configs.len()]; configs.len()];
    for (i, a) in configs.iter().enumerate() {
        for (j, b) in configs.iter().enumerate() {
            if let (Some(a), Some(b)) = (a, b) {
                e[i][j] = if i == j { 0.0 } else { leg_energy(robot, a, b, durations[i][j], profile, kind)? };
            }
        }
    }
    Ok(e)
}
