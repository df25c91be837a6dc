//! Multi-criteria decision methods on a decision matrix (candidates × criteria).
//!
//! Methods: weighted sum over min–max normalised scores, TOPSIS (vector normalisation,
//! closeness coefficient), VIKOR (S, R, Q with `v = 0.5`, and the acceptance conditions C1/C2 with
//! the compromise set, [`VikorAcceptance`]) and a Pareto (non-dominated) filter.
//!
//! Conventions shared by every method:
//! - weights are non-negative, finite, not all zero, one per criterion; they are normalised
//!   to sum 1 inside;
//! - a **constant column** (all candidates equal on a criterion) cannot discriminate: it
//!   contributes the same amount to every candidate (its min–max and VIKOR terms are 0 for all,
//!   its TOPSIS column is all-equal, or all-zero when the values are zero). It is not an error;
//! - ties in the final score are broken by candidate index (lower index ranks first).

use serde::Serialize;

use super::DecideError;

/// Whether larger or smaller values of a criterion are preferred.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Direction {
    /// Larger values are better (a benefit criterion).
    MoreIsBetter,
    /// Smaller values are better (a cost criterion).
    LessIsBetter,
}

impl Direction {
    /// `+1` for more-is-better, `-1` for less-is-better.
    pub fn sign(self) -> f64 {
        match self {
            Direction::MoreIsBetter => 1.0,
            Direction::LessIsBetter => -1.0,
        }
    }
}

/// A criterion: a name, the unit of its values and the preferred direction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Criterion {
    /// Short name (e.g. `"change"`).
    pub name: String,
    /// Unit of the values (e.g. `"rad"`, `"m"`, `"1"` for dimensionless).
    pub unit: String,
    /// Preferred direction.
    pub direction: Direction,
}

impl Criterion {
    /// A criterion from its parts.
    pub fn new(name: impl Into<String>, unit: impl Into<String>, direction: Direction) -> Self {
        Criterion { name: name.into(), unit: unit.into(), direction }
    }
}

/// Checks one weight per criterion and returns them normalised to sum 1 (the check of
/// [`DecisionMatrix::normalised_weights`], usable before any candidate exists). `criteria` are
/// the criterion names, in order; they name the offending weight in the error.
///
/// # Errors
/// [`DecideError::NoCriteria`] for no criteria, [`DecideError::WeightCount`] when the counts
/// differ, [`DecideError::InvalidWeight`] for a NaN, infinite or negative weight,
/// [`DecideError::ZeroWeights`] when every weight is zero.
pub fn normalise_weights<S: AsRef<str>>(criteria: &[S], weights: &[f64]) -> Result<Vec<f64>, DecideError> {
    if criteria.is_empty() {
        return Err(DecideError::NoCriteria);
    }
    if weights.len() != criteria.len() {
        return Err(DecideError::WeightCount { expected: criteria.len(), found: weights.len() });
    }
    for (j, w) in weights.iter().enumerate() {
        if !w.is_finite() || *w < 0.0 {
            return Err(DecideError::InvalidWeight { criterion: criteria[j].as_ref().to_string(), value: *w });
        }
    }
    let sum: f64 = weights.iter().sum();
    if sum <= 0.0 {
        return Err(DecideError::ZeroWeights);
    }
    Ok(weights.iter().map(|w| w / sum).collect())
}

/// A validated decision matrix: one row per candidate, one column per criterion, all finite.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DecisionMatrix {
    criteria: Vec<Criterion>,
    rows: Vec<Vec<f64>>,
}

impl DecisionMatrix {
    /// Builds a matrix, checking shape and finiteness.
    ///
    /// # Errors
    /// [`DecideError::NoCriteria`], [`DecideError::NoCandidates`], [`DecideError::RowLength`],
    /// [`DecideError::NonFiniteValue`].
    pub fn new(criteria: Vec<Criterion>, rows: Vec<Vec<f64>>) -> Result<Self, DecideError> {
        if criteria.is_empty() {
            return Err(DecideError::NoCriteria);
        }
        if rows.is_empty() {
            return Err(DecideError::NoCandidates);
        }
        for (i, row) in rows.iter().enumerate() {
            if row.len() != criteria.len() {
                return Err(DecideError::RowLength { candidate: i, expected: criteria.len(), found: row.len() });
            }
            for (j, v) in row.iter().enumerate() {
                if !v.is_finite() {
                    return Err(DecideError::NonFiniteValue {
                        candidate: i,
                        criterion: criteria[j].name.clone(),
                        value: *v,
                    });
                }
            }
        }
        Ok(DecisionMatrix { criteria, rows })
    }

    /// The criteria (columns).
    pub fn criteria(&self) -> &[Criterion] {
        &self.criteria
    }

    /// The rows (one per candidate).
    pub fn rows(&self) -> &[Vec<f64>] {
        &self.rows
    }

    /// Number of candidates.
    pub fn candidates(&self) -> usize {
        self.rows.len()
    }

    fn column(&self, j: usize) -> impl Iterator<Item = f64> + '_ {
        self.rows.iter().map(move |r| r[j])
    }

    /// Best and worst value of column `j` in the criterion's direction.
    fn best_worst(&self, j: usize) -> (f64, f64) {
        let (lo, hi) = self.column(j).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
        match self.criteria[j].direction {
            Direction::MoreIsBetter => (hi, lo),
            Direction::LessIsBetter => (lo, hi),
        }
    }

    /// Checks weights and returns them normalised to sum 1.
    ///
    /// # Errors
    /// [`DecideError::WeightCount`], [`DecideError::InvalidWeight`], [`DecideError::ZeroWeights`].
    pub fn normalised_weights(&self, weights: &[f64]) -> Result<Vec<f64>, DecideError> {
        let names: Vec<&str> = self.criteria.iter().map(|c| c.name.as_str()).collect();
        normalise_weights(&names, weights)
    }

    /// Fails with [`DecideError::ZeroColumn`] naming the first criterion whose value is zero for
    /// every candidate (e.g. manipulability when every candidate is singular). The methods
    /// themselves accept such a column (it cannot discriminate, see the module docs); callers
    /// that want the user to drop it instead call this first.
    ///
    /// # Errors
    /// [`DecideError::ZeroColumn`].
    pub fn reject_zero_columns(&self) -> Result<(), DecideError> {
        match (0..self.criteria.len()).find(|&j| self.column(j).all(|v| v == 0.0)) {
            Some(j) => Err(DecideError::ZeroColumn { criterion: self.criteria[j].name.clone() }),
            None => Ok(()),
        }
    }

    /// True when candidate `a` dominates `b`: at least as good on every criterion and strictly
    /// better on one.
    pub fn dominates(&self, a: usize, b: usize) -> bool {
        let mut strictly = false;
        for (j, c) in self.criteria.iter().enumerate() {
            let d = c.direction.sign() * (self.rows[a][j] - self.rows[b][j]);
            if d < 0.0 {
                return false;
            }
            if d > 0.0 {
                strictly = true;
            }
        }
        strictly
    }

    /// Indices of the non-dominated (Pareto-optimal) candidates, ascending. Candidates with
    /// identical rows are all kept.
    pub fn pareto(&self) -> Vec<usize> {
        let n = self.rows.len();
        (0..n).filter(|&i| !(0..n).any(|k| k != i && self.dominates(k, i))).collect()
    }
}

/// A ranking method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// Weighted sum of min–max normalised scores (1 = best value in the set, 0 = worst).
    WeightedSum,
    /// TOPSIS (Hwang & Yoon 1981): vector normalisation, weighted distances to the ideal and
    /// anti-ideal points, closeness coefficient `C = d⁻/(d⁺ + d⁻)`.
    Topsis,
    /// VIKOR (Opricovic & Tzeng 2004) with `v = 0.5`: group utility S, individual regret R and
    /// compromise index Q; smaller Q is better.
    Vikor,
}

impl Method {
    /// The method's name as used in files and on the command line.
    pub fn as_str(self) -> &'static str {
        match self {
            Method::WeightedSum => "weighted-sum",
            Method::Topsis => "topsis",
            Method::Vikor => "vikor",
        }
    }

    /// Parses `weighted-sum`/`sum`, `topsis` or `vikor`.
    pub fn parse(name: &str) -> Option<Method> {
        match name.to_ascii_lowercase().as_str() {
            "weighted-sum" | "weighted_sum" | "sum" => Some(Method::WeightedSum),
            "topsis" => Some(Method::Topsis),
            "vikor" => Some(Method::Vikor),
            _ => None,
        }
    }
}

/// VIKOR's compromise parameter: weight of the group-utility strategy.
pub const VIKOR_V: f64 = 0.5;

/// One candidate's place in a ranking, with the numbers that explain it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RankedCandidate {
    /// Index of the candidate in the matrix.
    pub index: usize,
    /// 1-based rank (1 = best).
    pub rank: usize,
    /// The method's score: weighted sum (higher better), TOPSIS closeness (higher better) or
    /// VIKOR Q (lower better).
    pub score: f64,
    /// Per-criterion normalised values: min–max score in \[0,1\] with 1 = best (weighted sum),
    /// vector-normalised value `x/‖column‖` (TOPSIS), or the regret `(f* − f)/(f* − f⁻)` in
    /// \[0,1\] with 0 = best (VIKOR).
    pub normalised: Vec<f64>,
    /// TOPSIS: weighted distance to the ideal point.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub distance_ideal: Option<f64>,
    /// TOPSIS: weighted distance to the anti-ideal point.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub distance_anti_ideal: Option<f64>,
    /// VIKOR: group utility S (weighted sum of regrets).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vikor_s: Option<f64>,
    /// VIKOR: individual regret R (largest weighted regret).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vikor_r: Option<f64>,
    /// Whether no other candidate dominates this one.
    pub pareto_optimal: bool,
}

/// A ranking of all candidates, best first.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Ranking {
    /// The method used.
    pub method: Method,
    /// The criteria, in column order.
    pub criteria: Vec<Criterion>,
    /// The weights used, normalised to sum 1.
    pub weights: Vec<f64>,
    /// Candidates in rank order (best first).
    pub ranked: Vec<RankedCandidate>,
    /// VIKOR only: whether the Q-best candidate is an acceptable compromise (conditions C1
    /// and C2), and the compromise set when it is not.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vikor: Option<VikorAcceptance>,
}

/// VIKOR's acceptance test of the Q-best candidate a′ (Opricovic & Tzeng 2004, EJOR
/// 156:445–455, §3 step 5), with a″ the second by Q and m the number of candidates:
///
/// * C1, acceptable advantage: `Q(a″) − Q(a′) ≥ DQ`, `DQ = 1/(m − 1)`;
/// * C2, acceptable stability: a′ is also best (possibly tied) by S or by R.
///
/// When both hold, a′ alone is the compromise solution. Otherwise the compromise set is
/// a′, a″ when only C2 fails, and every candidate with `Q − Q(a′) < DQ` when C1 fails.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VikorAcceptance {
    /// `DQ = 1/(m − 1)` (0 with a single candidate, where both conditions hold trivially).
    pub dq: f64,
    /// C1: `Q(a″) − Q(a′) ≥ DQ`.
    pub acceptable_advantage: bool,
    /// C2: a′ is also best by S or by R.
    pub acceptable_stability: bool,
    /// The compromise set, candidate indices in Q order (best first); `[a′]` when C1 and C2 hold.
    pub compromise: Vec<usize>,
}

impl VikorAcceptance {
    /// C1, C2 and the compromise set of `ranked` (in Q order, best first, with S and R set).
    fn of(ranked: &[RankedCandidate]) -> Self {
        let m = ranked.len();
        let dq = if m > 1 { 1.0 / (m - 1) as f64 } else { 0.0 };
        let (Some(first), second) = (ranked.first(), ranked.get(1)) else {
            return VikorAcceptance { dq, acceptable_advantage: true, acceptable_stability: true, compromise: vec![] };
        };
        let acceptable_advantage = second.is_none_or(|a2| a2.score - first.score >= dq);
        let best = |f: fn(&RankedCandidate) -> Option<f64>| ranked.iter().filter_map(f).fold(f64::INFINITY, f64::min);
        let (s_best, r_best) = (best(|c| c.vikor_s), best(|c| c.vikor_r));
        let acceptable_stability =
            first.vikor_s.is_some_and(|s| s <= s_best) || first.vikor_r.is_some_and(|r| r <= r_best);
        let compromise = if !acceptable_advantage {
            ranked.iter().take_while(|c| c.score - first.score < dq).map(|c| c.index).collect()
        } else if !acceptable_stability {
            ranked.iter().take(2).map(|c| c.index).collect()
        } else {
            vec![first.index]
        };
        VikorAcceptance { dq, acceptable_advantage, acceptable_stability, compromise }
    }

    /// Whether the Q-best candidate is the compromise solution on its own (C1 and C2 hold).
    #[must_use]
    pub fn accepted(&self) -> bool {
        self.acceptable_advantage && self.acceptable_stability
    }
}

impl Ranking {
    /// Index (in the matrix) of the best candidate.
    pub fn best(&self) -> usize {
        self.ranked[0].index
    }

    /// Candidate indices, best first.
    pub fn order(&self) -> Vec<usize> {
        self.ranked.iter().map(|r| r.index).collect()
    }

    /// The entry for candidate `index`, if it exists.
    pub fn candidate(&self, index: usize) -> Option<&RankedCandidate> {
        self.ranked.iter().find(|r| r.index == index)
    }
}

/// Ranks the candidates of `matrix` with `method` and `weights` (one per criterion).
///
/// # Errors
/// Weight errors from [`DecisionMatrix::normalised_weights`].
pub fn rank(matrix: &DecisionMatrix, weights: &[f64], method: Method) -> Result<Ranking, DecideError> {
    let w = matrix.normalised_weights(weights)?;
    let n = matrix.candidates();
    let m = matrix.criteria.len();
    let pareto = matrix.pareto();
    let mut entries: Vec<RankedCandidate> = (0..n)
        .map(|i| RankedCandidate {
            index: i,
            rank: 0,
            score: 0.0,
            normalised: vec![0.0; m],
            distance_ideal: None,
            distance_anti_ideal: None,
            vikor_s: None,
            vikor_r: None,
            pareto_optimal: pareto.contains(&i),
        })
        .collect();
    let higher_better = match method {
        Method::WeightedSum => {
            for j in 0..m {
                let (best, worst) = matrix.best_worst(j);
                let span = best - worst;
                for (i, e) in entries.iter_mut().enumerate() {
                    // Constant column: 0 for everyone (documented in the module header).
                    e.normalised[j] = if span == 0.0 { 0.0 } else { (matrix.rows[i][j] - worst) / span };
                }
            }
            for e in &mut entries {
                e.score = e.normalised.iter().zip(&w).map(|(r, w)| r * w).sum();
            }
            true
        }
        Method::Topsis => {
            let mut ideal = vec![0.0; m];
            let mut anti = vec![0.0; m];
            for j in 0..m {
                let norm = matrix.column(j).map(|v| v * v).sum::<f64>().sqrt();
                for (i, e) in entries.iter_mut().enumerate() {
                    e.normalised[j] = if norm == 0.0 { 0.0 } else { matrix.rows[i][j] / norm };
                }
                let weighted = entries.iter().map(|e| w[j] * e.normalised[j]);
                let (lo, hi) = weighted.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
                (ideal[j], anti[j]) = match matrix.criteria[j].direction {
                    Direction::MoreIsBetter => (hi, lo),
                    Direction::LessIsBetter => (lo, hi),
                };
            }
            for e in &mut entries {
                let mut dp = 0.0;
                let mut dm = 0.0;
                for j in 0..m {
                    let v = w[j] * e.normalised[j];
                    dp += (v - ideal[j]).powi(2);
                    dm += (v - anti[j]).powi(2);
                }
                let (dp, dm) = (dp.sqrt(), dm.sqrt());
                e.distance_ideal = Some(dp);
                e.distance_anti_ideal = Some(dm);
                // All candidates equal on every weighted criterion: d⁺ = d⁻ = 0; they tie at 0.5.
                e.score = if dp + dm == 0.0 { 0.5 } else { dm / (dp + dm) };
            }
            true
        }
        Method::Vikor => {
            for j in 0..m {
                let (best, worst) = matrix.best_worst(j);
                let span = best - worst;
                for (i, e) in entries.iter_mut().enumerate() {
                    // `+ 0.0` turns the −0 of a best value on a less-is-better column into 0.
                    e.normalised[j] = if span == 0.0 { 0.0 } else { (best - matrix.rows[i][j]) / span + 0.0 };
                }
            }
            for e in &mut entries {
                let terms = e.normalised.iter().zip(&w).map(|(d, w)| d * w);
                e.vikor_s = Some(terms.clone().sum());
                e.vikor_r = Some(terms.fold(0.0, f64::max));
            }
            let s: Vec<f64> = entries.iter().map(|e| e.vikor_s.unwrap_or(0.0)).collect();
            let r: Vec<f64> = entries.iter().map(|e| e.vikor_r.unwrap_or(0.0)).collect();
            let (s_lo, s_hi) = min_max(&s);
            let (r_lo, r_hi) = min_max(&r);
            for (i, e) in entries.iter_mut().enumerate() {
                let qs = if s_hi > s_lo { (s[i] - s_lo) / (s_hi - s_lo) } else { 0.0 };
                let qr = if r_hi > r_lo { (r[i] - r_lo) / (r_hi - r_lo) } else { 0.0 };
                e.score = VIKOR_V * qs + (1.0 - VIKOR_V) * qr;
            }
            false
        }
    };
    entries.sort_by(|a, b| {
        let ord = if higher_better { b.score.total_cmp(&a.score) } else { a.score.total_cmp(&b.score) };
        ord.then(a.index.cmp(&b.index))
    });
    for (k, e) in entries.iter_mut().enumerate() {
        e.rank = k + 1;
    }
    let vikor = (method == Method::Vikor).then(|| VikorAcceptance::of(&entries));
    Ok(Ranking { method, criteria: matrix.criteria.clone(), weights: w, ranked: entries, vikor })
}

fn min_max(v: &[f64]) -> (f64, f64) {
    v.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| (lo.min(x), hi.max(x)))
}
