//! Batch kernels: one computation over many inputs, split over threads.
//!
//! Front ends that hold many inputs at once (the Python package's numpy arrays, a cluster
//! worker's chunk of poses) call these instead of looping over the single-input functions:
//! the inputs are flat row-major buffers (`N × dof` joint values, `N × 4 × 4` homogeneous
//! matrices), the work is split over a rayon pool (feature `parallel`, on by default; without
//! it the same loop runs on the calling thread and gives the same result), and the outputs are
//! flat row-major buffers again, in input order.
//!
//! Nothing here is a new numeric rule: each row is exactly [`Robot::fk_matrix`],
//! [`Robot::jacobian`], an [`IkSolver::solve`](crate::ik::IkSolver::solve) of the target
//! that [`Pose::target`] reads from the matrix (same validation, same messages), or the
//! Newton–Euler pass of [`crate::effort::dynamics::Dynamics`].
//!
//! Errors name the offending row as `field[i]`, `i` 0-based as in the caller's array (joint
//! numbers inside a message stay 1-based, as everywhere in the crate). The number of rows is
//! capped by [`MAX_BATCH`] before any output is allocated.
//!
//! # Example
//! ```
//! let ur5 = reach::model::presets::get("ur5").unwrap();
//! let q = [0.1, -1.2, 1.0, -0.5, 1.3, 0.4];
//! let t = reach::batch::fk_many(&ur5, &q).unwrap(); // one row: 16 numbers
//! let opts = reach::ik::IkOptions::default();
//! let all = reach::batch::ik_many(&ur5, None, &t, None, &opts).unwrap();
//! assert_eq!((all.targets, all.dof), (1, 6));
//! let found = (0..all.kmax).filter(|&k| all.valid[k]).any(|k| {
//!     (0..6).all(|j| (all.q[k * 6 + j] - q[j]).abs() < 1e-9)
//! });
//! assert!(found);
//! ```

use nalgebra::IsometryMatrix3;

use crate::error::{Error, Result};
use std::collections::HashMap;

use crate::ik::{Branch, IkOptions, IkSolutions, IkTarget, SolverKind};
use crate::jobs::ik::failure_code;
use crate::jobs::input::Pose;
use crate::kinematics::{Lanes, check_q};
use crate::model::Robot;
use crate::simd::{self, Level};

/// Largest number of rows of one batch call (10 million): 10 million 6-joint poses of all
/// branches are about 4 GB of output, the most one call should allocate.
pub const MAX_BATCH: usize = 10_000_000;

/// Rows per rayon task: large enough that a task's bookkeeping is negligible next to its
/// work, small enough that 2–64 threads share 10 000 rows evenly.
const CHUNK: usize = 64;

/// The number of rows of a flat buffer of `width`-wide rows.
///
/// # Errors
/// [`Error::Request`] naming `field` when the length is not a multiple of `width` or there are
/// more than [`MAX_BATCH`] rows.
pub fn rows(field: &str, len: usize, width: usize) -> Result<usize> {
    if width == 0 || !len.is_multiple_of(width) {
        return Err(Error::request(field, format!("expected rows of {width} numbers, got {len} numbers in all")));
    }
    let n = len / width;
    if n > MAX_BATCH {
        return Err(Error::request(field, format!("{n} rows, more than the cap of {MAX_BATCH} per call")));
    }
    Ok(n)
}

/// Runs `f` on every row index `0..n`, in parallel when the `parallel` feature is on, and
/// returns the results in row order (the first error in row order when any fails). `init`
/// makes the per-task state `f` works in (built once per rayon task, not per row).
fn map_rows<S, T: Send>(
    n: usize,
    init: impl Fn() -> S + Sync + Send,
    f: impl Fn(&mut S, usize) -> Result<T> + Sync + Send,
) -> Result<Vec<T>> {
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        // Collected whole first: rayon's `Result` collection would return whichever error
        // came first in time, not in row order.
        let rows: Vec<Result<T>> = (0..n).into_par_iter().with_min_len(CHUNK).map_init(init, f).collect();
        rows.into_iter().collect()
    }
    #[cfg(not(feature = "parallel"))]
    {
        let _ = CHUNK;
        let mut state = init();
        (0..n).map(|i| f(&mut state, i)).collect()
    }
}

/// Joint vectors per structure-of-arrays block of [`fk_many`] and of [`jacobian_many`]
/// ([`CHUNK`] is a multiple of both): the fastest of 2, 4 and 8 on the 2-core test machine
/// (x86_64 with SSE2 only, as the crate is built by default; best of 60 calls of 10 000 rows
/// on one thread, 2026-12-02): for FK 8 lanes ran ≈ 10 % faster than 4 (and 4 1.5–2.2×
/// faster than 2), for the Jacobian (twice the live values) 4 ran ≈ 5 % faster than 8. The
/// blocks run compiled for the widest level the processor has ([`simd::run`]); there too
/// (2026-12-03, AVX2 and AVX-512, load average 5–7) 16 rows per FK block ran 10–25 % slower
/// than 8, and 8 per Jacobian block no faster than 4.
const FK_LANES: usize = 8;
/// See [`FK_LANES`].
const JACOBIAN_LANES: usize = 4;
const _: () = assert!(CHUNK.is_multiple_of(FK_LANES) && CHUNK.is_multiple_of(JACOBIAN_LANES));

/// Runs `f(first_row, input_rows, output_rows)` on every chunk of [`CHUNK`] rows of `input`
/// (`width_in` numbers a row) and the matching rows of `out` (`width_out` numbers a row), in
/// parallel when the `parallel` feature is on; returns the first error in row order.
fn fill_rows(
    input: &[f64],
    width_in: usize,
    out: &mut [f64],
    width_out: usize,
    f: impl Fn(usize, &[f64], &mut [f64]) -> Result<()> + Sync + Send,
) -> Result<()> {
    let (step_in, step_out) = (CHUNK * width_in.max(1), CHUNK * width_out.max(1));
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        let done: Vec<Result<()>> = input
            .par_chunks(step_in)
            .zip(out.par_chunks_mut(step_out))
            .enumerate()
            .map(|(c, (i, o))| f(c * CHUNK, i, o))
            .collect();
        done.into_iter().collect()
    }
    #[cfg(not(feature = "parallel"))]
    {
        input.chunks(step_in).zip(out.chunks_mut(step_out)).enumerate().try_for_each(|(c, (i, o))| f(c * CHUNK, i, o))
    }
}

/// Checks every row of `q` (`dof` numbers a row, the first being row `first` of the caller's
/// array): the error names the first row with a non-finite value, as `q[i]`.
fn check_rows(first: usize, q: &[f64], dof: usize) -> Result<()> {
    for (r, row) in q.chunks_exact(dof).enumerate() {
        check_q(dof, row).map_err(|e| Error::request(format!("q[{}]", first + r), e.to_string()))?;
    }
    Ok(())
}

/// The rows of `q` (`dof` numbers a row) as lanes: joint `j` of row `l` at `[j][l]`.
#[inline(always)]
fn gather<const L: usize>(q: &[f64], dof: usize, lanes: &mut [Lanes<L>]) {
    for (j, lane) in lanes.iter_mut().enumerate() {
        *lane = std::array::from_fn(|l| q[l * dof + j]);
    }
}

/// Inverse dynamics of every row: the joint torques/forces `τ = M(q)·q̈ + C(q, q̇)·q̇ + g(q)`
/// (N·m revolute, N prismatic; `N × dof`) of the rows of `q`, `qd`, `qdd` (`N × dof` each, SI:
/// rad or m, per second, per second squared), exactly
/// [`Dynamics::inverse_dynamics_into`](crate::effort::dynamics::Dynamics::inverse_dynamics_into)
/// of each row. `qd` / `qdd` `None` are zeros: with both `None`, the gravity load `g(q)`.
///
/// # Errors
/// [`Error::Request`] with field `q`, `qd` or `qdd` (shape, cap, a length unlike `q`'s) or
/// `q[i]` (a bad row); [`Error::Dynamics`] when the robot has no inertial data.
pub fn inverse_dynamics_many(robot: &Robot, q: &[f64], qd: Option<&[f64]>, qdd: Option<&[f64]>) -> Result<Vec<f64>> {
    let dof = robot.dof();
    let n = rows("q", q.len(), dof)?;
    for (field, rates) in [("qd", qd), ("qdd", qdd)] {
        if let Some(r) = rates
            && r.len() != q.len()
        {
            return Err(Error::request(
                field,
                format!("expected {n} rows of {dof} numbers like `q`, got {} numbers", r.len()),
            ));
        }
    }
    crate::effort::dynamics::Dynamics::new(robot)?;
    let mut out = vec![0.0; n * dof];
    let zeros = vec![0.0; dof];
    fill_rows(q, dof, &mut out, dof, |first, q, out| {
        let mut work = crate::effort::dynamics::Dynamics::new(robot)?;
        for (r, (q, tau)) in q.chunks_exact(dof).zip(out.chunks_exact_mut(dof)).enumerate() {
            let row = first + r;
            let (qd, qdd) = [qd, qdd].map(|m| m.map_or(zeros.as_slice(), |m| &m[row * dof..(row + 1) * dof])).into();
            work.inverse_dynamics_into(q, qd, qdd, tau)
                .map_err(|e| Error::request(format!("q[{row}]"), e.to_string()))?;
        }
        Ok(())
    })?;
    Ok(out)
}

/// The joint-space mass matrix of every row of `q` (`N × dof`, SI): `N × dof × dof`,
/// row-major, exactly [`Dynamics::mass_matrix_into`](crate::effort::dynamics::Dynamics::mass_matrix_into)
/// of each row.
///
/// # Errors
/// As [`inverse_dynamics_many`].
pub fn mass_matrix_many(robot: &Robot, q: &[f64]) -> Result<Vec<f64>> {
    let dof = robot.dof();
    let n = rows("q", q.len(), dof)?;
    crate::effort::dynamics::Dynamics::new(robot)?;
    let mut out = vec![0.0; n * dof * dof];
    fill_rows(q, dof, &mut out, dof * dof, |first, q, out| {
        let mut work = crate::effort::dynamics::Dynamics::new(robot)?;
        let mut m = nalgebra::DMatrix::zeros(dof, dof);
        for (r, (q, row_out)) in q.chunks_exact(dof).zip(out.chunks_exact_mut(dof * dof)).enumerate() {
            work.mass_matrix_into(q, &mut m).map_err(|e| Error::request(format!("q[{}]", first + r), e.to_string()))?;
            // Row-major, as every batch output.
            for (i, row) in row_out.chunks_exact_mut(dof).enumerate() {
                row.iter_mut().enumerate().for_each(|(j, x)| *x = m[(i, j)]);
            }
        }
        Ok(())
    })?;
    Ok(out)
}

/// The tool pose of every row of `q` (`N × dof`, SI): `N × 4 × 4` homogeneous matrices,
/// row-major, exactly [`Robot::fk_matrix`] of each row (to rounding: blocks of rows go through
/// a structure-of-arrays kernel that repeats its operations lane by lane).
///
/// # Performance
/// Rows go through the chain product eight at a time, each matrix entry an array of one value
/// per row, so the arithmetic runs on vector registers (compiled for the widest level the
/// processor has, [`crate::simd`]: one AVX-512 register holds an entry of all eight rows); the
/// last `N mod 8` rows take the one-row path. 1.8–2.2× the throughput of a loop over [`Robot::fk_matrix`] on one core
/// (`benches/kinematics.rs`: group `fk_many` against `rows_one_at_a_time`).
///
/// # Errors
/// [`Error::Request`] with field `q` (shape, cap) or `q[i]` (a non-finite value in row `i`,
/// the joint named 1-based).
pub fn fk_many(robot: &Robot, q: &[f64]) -> Result<Vec<f64>> {
    fk_rows::<FK_LANES>(robot, q, simd::level())
}

/// [`fk_many`] with blocks of `LANES` rows, the blocks' kernel compiled for `level`.
fn fk_rows<const LANES: usize>(robot: &Robot, q: &[f64], level: Level) -> Result<Vec<f64>> {
    let dof = robot.dof();
    let n = rows("q", q.len(), dof)?;
    let mut out = vec![0.0; n * 16];
    fill_rows(q, dof, &mut out, 16, |first, q, out| {
        check_rows(first, q, dof)?;
        let whole = q.len() / (LANES * dof) * LANES;
        let (blocks, rest) = q.split_at(whole * dof);
        let (outs, rest_out) = out.split_at_mut(whole * 16);
        let mut lanes = vec![[0.0; LANES]; dof];
        simd::run_at(level, FkBlocks::<LANES> { robot, q: blocks, out: outs, lanes: &mut lanes });
        let first = first + whole;
        for (r, (q, pose)) in rest.chunks_exact(dof).zip(rest_out.chunks_exact_mut(16)).enumerate() {
            let t = robot.fk_matrix(q).map_err(|e| Error::request(format!("q[{}]", first + r), e.to_string()))?;
            pose.copy_from_slice(&homogeneous(&t));
        }
        Ok(())
    })?;
    Ok(out)
}

/// The block loop of [`fk_many`] as a [`simd::Kernel`]: the tool poses of `q` (checked rows,
/// a whole number of blocks of `L`) into `out` (16 numbers a row); `lanes` (one per joint)
/// holds a block.
struct FkBlocks<'a, const L: usize> {
    robot: &'a Robot,
    q: &'a [f64],
    out: &'a mut [f64],
    lanes: &'a mut [Lanes<L>],
}

impl<const L: usize> simd::Kernel for FkBlocks<'_, L> {
    type Output = ();
    #[inline(always)]
    fn run(self) {
        let (dof, lanes) = (self.robot.dof(), self.lanes);
        for (q, out) in self.q.chunks_exact(L * dof).zip(self.out.chunks_exact_mut(L * 16)) {
            gather::<L>(q, dof, lanes);
            let t = self.robot.fk_lanes(lanes);
            for (l, pose) in out.chunks_exact_mut(16).enumerate() {
                for i in 0..3 {
                    pose[i * 4..i * 4 + 3].copy_from_slice(&[t.r[i][0][l], t.r[i][1][l], t.r[i][2][l]]);
                    pose[i * 4 + 3] = t.p[i][l];
                }
                pose[12..].copy_from_slice(&[0.0, 0.0, 0.0, 1.0]);
            }
        }
    }
}

/// The geometric Jacobian of every row of `q` (`N × dof`, SI): `N × 6 × dof`, row-major,
/// exactly [`Robot::jacobian`] of each row (to rounding, as [`fk_many`]: blocks of four rows
/// through a structure-of-arrays kernel, the last `N mod 4` rows through
/// [`Robot::jacobian_into`]).
///
/// # Errors
/// As [`fk_many`].
pub fn jacobian_many(robot: &Robot, q: &[f64]) -> Result<Vec<f64>> {
    jacobian_rows::<JACOBIAN_LANES>(robot, q, simd::level())
}

/// [`jacobian_many`] with blocks of `LANES` rows, the blocks' kernel compiled for `level`.
fn jacobian_rows<const LANES: usize>(robot: &Robot, q: &[f64], level: Level) -> Result<Vec<f64>> {
    let dof = robot.dof();
    let n = rows("q", q.len(), dof)?;
    let width = 6 * dof;
    let mut out = vec![0.0; n * width];
    fill_rows(q, dof, &mut out, width, |first, q, out| {
        check_rows(first, q, dof)?;
        let whole = q.len() / (LANES * dof) * LANES;
        let (blocks, rest) = q.split_at(whole * dof);
        let (outs, rest_out) = out.split_at_mut(whole * width);
        let mut lanes = vec![[0.0; LANES]; dof];
        let mut j_lanes = vec![[0.0; LANES]; width];
        simd::run_at(
            level,
            JacobianBlocks::<LANES> { robot, q: blocks, out: outs, lanes: &mut lanes, j_lanes: &mut j_lanes },
        );
        let mut one = crate::Jacobian::zeros(dof);
        let first = first + whole;
        for (r, (q, j)) in rest.chunks_exact(dof).zip(rest_out.chunks_exact_mut(width)).enumerate() {
            robot.jacobian_into(q, &mut one).map_err(|e| Error::request(format!("q[{}]", first + r), e.to_string()))?;
            for (k, v) in j.iter_mut().enumerate() {
                *v = one[(k / dof, k % dof)];
            }
        }
        Ok(())
    })?;
    Ok(out)
}

/// The block loop of [`jacobian_many`] as a [`simd::Kernel`]: the Jacobians of `q` (checked
/// rows, a whole number of blocks of `L`) into `out` (`6 × dof` numbers a row); `lanes` (one
/// per joint) and `j_lanes` (one per Jacobian entry) hold a block.
struct JacobianBlocks<'a, const L: usize> {
    robot: &'a Robot,
    q: &'a [f64],
    out: &'a mut [f64],
    lanes: &'a mut [Lanes<L>],
    j_lanes: &'a mut [Lanes<L>],
}

impl<const L: usize> simd::Kernel for JacobianBlocks<'_, L> {
    type Output = ();
    #[inline(always)]
    fn run(self) {
        let (dof, lanes, j_lanes) = (self.robot.dof(), self.lanes, self.j_lanes);
        let width = 6 * dof;
        for (q, out) in self.q.chunks_exact(L * dof).zip(self.out.chunks_exact_mut(L * width)) {
            gather::<L>(q, dof, lanes);
            self.robot.jacobian_lanes(lanes, j_lanes);
            for (l, j) in out.chunks_exact_mut(width).enumerate() {
                for (v, lane) in j.iter_mut().zip(j_lanes.iter()) {
                    *v = lane[l];
                }
            }
        }
    }
}

/// Every IK solution of many targets, packed into arrays: row `i`'s solutions fill slots
/// `0..count[i]` of `kmax` slots, the rest are padding (`q` NaN, `valid` false).
#[derive(Debug, Clone, PartialEq)]
pub struct IkBatch {
    /// Number of targets `N`.
    pub targets: usize,
    /// Joints per solution.
    pub dof: usize,
    /// Slots per target: the largest number of solutions of any target (0 when none has one).
    pub kmax: usize,
    /// Solutions, `N × kmax × dof`, SI, NaN in padding slots.
    pub q: Vec<f64>,
    /// `N × kmax`: whether the slot holds a solution.
    pub valid: Vec<bool>,
    /// `N × kmax`: whether the solution is within the joint limits (false in padding).
    pub within_limits: Vec<bool>,
    /// `N × kmax`: position error of the solution by FK, metres (NaN in padding).
    pub position_error: Vec<f64>,
    /// `N × kmax`: orientation error of the solution by FK, radians (NaN in padding).
    pub orientation_error: Vec<f64>,
    /// `N × kmax`: whether the solution sits at a singular configuration (false in padding).
    pub singular: Vec<bool>,
    /// `N`: how many solutions each target has.
    pub count: Vec<usize>,
    /// `N`: `ok`, or the stable code of why no solution is within limits
    /// ([`failure_code`]: `unreachable`, `outside_limits`, …).
    pub status: Vec<&'static str>,
    /// `N × kmax`: index of the solution's branch label in [`IkBatch::labels`]
    /// ([`IkBatch::NO_LABEL`] in padding).
    pub branch: Vec<u32>,
    /// The distinct branch labels (`shoulder=left elbow=up wrist=flip`), in order of first
    /// appearance.
    pub labels: Vec<String>,
    /// Name of the solver used.
    pub solver: &'static str,
}

impl IkBatch {
    /// The label index of a padding slot.
    pub const NO_LABEL: u32 = u32::MAX;
}

/// Every IK solution of each target of `targets` (`N × 4 × 4` homogeneous matrices,
/// row-major), with the solver `kind` (default: [`SolverKind::detect`]) and `options`; row `i`
/// of `seeds` (`N × dof`, SI), when given, replaces `options.seed` for target `i` (the numeric
/// solver's first start; the angle kept at a wrist singularity). Each target is validated as
/// [`Pose::target`] validates a `matrix` (finite, last row `0 0 0 1`, orthonormal rotation).
///
/// # Performance
/// One solver is built per rayon task; the closed forms of 6R arms solve 10 000 poses in a
/// few tens of milliseconds per core.
///
/// # Errors
/// [`Error::Request`] naming `T` / `seeds` (shape, cap) or `T[i].matrix` / `seeds[i]` (the
/// row's value); [`Error::Ik`] when the named solver does not fit the robot or an option is
/// invalid.
pub fn ik_many(
    robot: &Robot,
    kind: Option<SolverKind>,
    targets: &[f64],
    seeds: Option<&[f64]>,
    options: &IkOptions,
) -> Result<IkBatch> {
    let dof = robot.dof();
    let n = rows("T", targets.len(), 16)?;
    if let Some(s) = seeds {
        let m = rows("seeds", s.len(), dof)?;
        if m != n {
            return Err(Error::request("seeds", format!("{m} rows of seeds for {n} targets")));
        }
    }
    let kind = kind.unwrap_or_else(|| SolverKind::detect(robot));
    let solver_name = kind.build(robot)?.name();
    let solve_row = |solver: &dyn crate::ik::IkSolver, i: usize| -> Result<IkSolutions> {
        let target = target_of(&targets[i * 16..(i + 1) * 16], &format!("T[{i}]"))?;
        let seed = match seeds {
            Some(s) => {
                let row = &s[i * dof..(i + 1) * dof];
                if let Some(j) = row.iter().position(|v| !v.is_finite()) {
                    return Err(Error::request(
                        format!("seeds[{i}]"),
                        format!("joint {}: value must be a finite number, got {}", j + 1, row[j]),
                    ));
                }
                Some(row.to_vec())
            }
            None => options.seed.clone(),
        };
        let opts = IkOptions { seed, ..options.clone() };
        Ok(solver.solve(robot, &target, &opts)?)
    };
    // Each task solves a chunk of rows and packs it on its own thread (the solutions are
    // freed where they were allocated); the chunks are then copied into place.
    let chunks = n.div_ceil(CHUNK);
    let packed: Vec<Packed> = map_rows(
        chunks,
        || kind.build(robot),
        |solver, c| {
            // `build` succeeded above, so it does not fail here.
            let solver = solver.as_ref().map_err(|e| Error::Ik(e.clone()))?;
            let rows = c * CHUNK..((c + 1) * CHUNK).min(n);
            let solved = rows.map(|i| solve_row(solver.as_ref(), i)).collect::<Result<Vec<_>>>()?;
            Ok(Packed::of(solved, dof))
        },
    )?;
    let kmax = packed.iter().map(|p| p.kmax).max().unwrap_or(0);
    let slots = n * kmax;
    let mut out = IkBatch {
        targets: n,
        dof,
        kmax,
        q: vec![f64::NAN; slots * dof],
        valid: vec![false; slots],
        within_limits: vec![false; slots],
        position_error: vec![f64::NAN; slots],
        orientation_error: vec![f64::NAN; slots],
        singular: vec![false; slots],
        count: Vec::with_capacity(n),
        status: Vec::with_capacity(n),
        branch: vec![IkBatch::NO_LABEL; slots],
        labels: Vec::new(),
        solver: solver_name,
    };
    let mut label_index: HashMap<Branch, u32> = HashMap::new();
    let mut row = 0;
    for p in packed {
        // The chunk's labels as global indices (each distinct label written out once).
        let global: Vec<u32> = p
            .branches
            .into_iter()
            .map(|b| {
                let next = u32::try_from(out.labels.len()).unwrap_or(IkBatch::NO_LABEL - 1);
                *label_index.entry(b).or_insert_with_key(|b| {
                    out.labels.push(b.to_string());
                    next
                })
            })
            .collect();
        for (r, (&count, status)) in p.count.iter().zip(&p.status).enumerate() {
            let (from, to) = (r * p.kmax, row * kmax);
            out.q[to * dof..(to + count) * dof].copy_from_slice(&p.q[from * dof..(from + count) * dof]);
            for k in 0..count {
                out.valid[to + k] = true;
                out.within_limits[to + k] = p.within_limits[from + k];
                out.position_error[to + k] = p.position_error[from + k];
                out.orientation_error[to + k] = p.orientation_error[from + k];
                out.singular[to + k] = p.singular[from + k];
                out.branch[to + k] = global[p.branch[from + k] as usize];
            }
            out.count.push(count);
            out.status.push(status);
            row += 1;
        }
    }
    Ok(out)
}

/// One chunk of rows packed as [`IkBatch`] with the chunk's own `kmax` and its own label table.
struct Packed {
    kmax: usize,
    q: Vec<f64>,
    within_limits: Vec<bool>,
    position_error: Vec<f64>,
    orientation_error: Vec<f64>,
    singular: Vec<bool>,
    /// Index into `branches`.
    branch: Vec<u32>,
    branches: Vec<Branch>,
    count: Vec<usize>,
    status: Vec<&'static str>,
}

impl Packed {
    fn of(solved: Vec<IkSolutions>, dof: usize) -> Packed {
        let kmax = solved.iter().map(|s| s.solutions.len()).max().unwrap_or(0);
        let slots = solved.len() * kmax;
        let mut p = Packed {
            kmax,
            q: vec![f64::NAN; slots * dof],
            within_limits: vec![false; slots],
            position_error: vec![f64::NAN; slots],
            orientation_error: vec![f64::NAN; slots],
            singular: vec![false; slots],
            branch: vec![0; slots],
            branches: Vec::new(),
            count: Vec::with_capacity(solved.len()),
            status: Vec::with_capacity(solved.len()),
        };
        let mut lookup: HashMap<Branch, u32> = HashMap::new();
        for (i, s) in solved.into_iter().enumerate() {
            p.count.push(s.solutions.len());
            p.status.push(s.failure.as_ref().map_or("ok", failure_code));
            for (k, sol) in s.solutions.into_iter().enumerate() {
                let slot = i * kmax + k;
                p.q[slot * dof..(slot + 1) * dof].copy_from_slice(&sol.q);
                p.within_limits[slot] = sol.within_limits;
                p.position_error[slot] = sol.position_error;
                p.orientation_error[slot] = sol.orientation_error;
                p.singular[slot] = !sol.singularities.is_empty();
                let next = u32::try_from(lookup.len()).unwrap_or(u32::MAX);
                p.branch[slot] = *lookup.entry(sol.branch).or_insert(next);
            }
        }
        let mut branches: Vec<(u32, Branch)> = lookup.into_iter().map(|(b, i)| (i, b)).collect();
        branches.sort_unstable_by_key(|(i, _)| *i);
        p.branches = branches.into_iter().map(|(_, b)| b).collect();
        p
    }
}

/// The IK target of a row-major 4×4 matrix, validated as a request's `matrix` pose.
fn target_of(m: &[f64], field: &str) -> Result<IkTarget> {
    let mut rows = [[0.0; 4]; 4];
    for (r, row) in rows.iter_mut().enumerate() {
        row.copy_from_slice(&m[r * 4..r * 4 + 4]);
    }
    Pose { matrix: Some(rows), ..Pose::default() }.target(field)
}

/// A pose as 16 numbers, row-major.
fn homogeneous(t: &IsometryMatrix3<f64>) -> [f64; 16] {
    let h = t.to_homogeneous();
    let mut out = [0.0; 16];
    for r in 0..4 {
        for c in 0..4 {
            out[r * 4 + c] = h[(r, c)];
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;
    use crate::rng::SplitMix64;

    fn random_q(robot: &Robot, n: usize, seed: u64) -> Vec<f64> {
        let mut rng = SplitMix64(seed);
        (0..n * robot.dof()).map(|_| (2.0 * rng.next_f64() - 1.0) * std::f64::consts::PI).collect()
    }

    #[test]
    fn fk_many_is_fk_of_each_row() {
        let puma = presets::get("puma560").unwrap();
        let q = random_q(&puma, 300, 7);
        let t = fk_many(&puma, &q).unwrap();
        assert_eq!(t.len(), 300 * 16);
        for i in [0, 17, 299] {
            let one = puma.fk_matrix(&q[i * 6..i * 6 + 6]).unwrap().to_homogeneous();
            for k in 0..16 {
                assert_eq!(t[i * 16 + k], one[(k / 4, k % 4)]);
            }
        }
    }

    #[test]
    fn jacobian_many_is_jacobian_of_each_row() {
        let panda = presets::get("panda").unwrap();
        let q = random_q(&panda, 100, 9);
        let j = jacobian_many(&panda, &q).unwrap();
        let one = panda.jacobian(&q[7 * 42..7 * 42 + 7]).unwrap();
        for r in 0..6 {
            for c in 0..7 {
                assert_eq!(j[42 * 42 + r * 7 + c], one[(r, c)]);
            }
        }
    }

    /// A URDF arm (general constants and reframed DH steps), a modified-DH arm with a tool,
    /// a standard-DH arm and the mimic arm.
    fn batch_robots() -> Vec<Robot> {
        let urdf = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/panda.urdf")).unwrap();
        let chain = crate::model::UrdfChain { base: None, tip: Some("panda_hand".into()) };
        let mimic = crate::model::UrdfChain { base: Some("base".into()), tip: Some("tool".into()) };
        let mut robots = vec![
            Robot::from_urdf_str(&urdf, &chain).unwrap(),
            Robot::from_urdf_str(include_str!("../tests/data/mimic_arm.urdf"), &mimic).unwrap(),
        ];
        robots.extend(["panda", "puma560", "ur5"].map(|n| presets::get(n).unwrap()));
        robots
    }

    #[test]
    fn batch_kernels_give_the_same_bits_at_every_level() {
        for robot in batch_robots() {
            let dof = robot.dof();
            // 2 chunks and a remainder: both block paths and the one-row path.
            let q = random_q(&robot, 2 * CHUNK + 13, 5);
            let fk = fk_rows::<FK_LANES>(&robot, &q, Level::Baseline).unwrap();
            let jac = jacobian_rows::<JACOBIAN_LANES>(&robot, &q, Level::Baseline).unwrap();
            for (i, row) in q.chunks_exact(dof).enumerate() {
                let one = robot.fk_matrix(row).unwrap().to_homogeneous();
                assert!((0..16).all(|k| fk[i * 16 + k].to_bits() == one[(k / 4, k % 4)].to_bits()), "row {i}");
                let one = robot.jacobian(row).unwrap();
                let width = 6 * dof;
                assert!((0..width).all(|k| jac[i * width + k].to_bits() == one[(k / dof, k % dof)].to_bits()));
            }
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            for level in simd::levels() {
                let name = level.name();
                assert_eq!(bits(&fk_rows::<FK_LANES>(&robot, &q, level).unwrap()), bits(&fk), "fk {name}");
                assert_eq!(bits(&fk_rows::<16>(&robot, &q, level).unwrap()), bits(&fk), "fk 16 {name}");
                let j = jacobian_rows::<JACOBIAN_LANES>(&robot, &q, level).unwrap();
                assert_eq!(bits(&j), bits(&jac), "jacobian {name}");
                assert_eq!(bits(&jacobian_rows::<8>(&robot, &q, level).unwrap()), bits(&jac), "jacobian 8 {name}");
            }
        }
    }

    #[test]
    fn ik_many_contains_every_generating_configuration() {
        let ur5 = presets::get("ur5").unwrap();
        let q = random_q(&ur5, 500, 11);
        let t = fk_many(&ur5, &q).unwrap();
        let all = ik_many(&ur5, None, &t, None, &IkOptions::default()).unwrap();
        assert!(all.kmax <= 8 && all.kmax >= 1);
        for i in 0..500 {
            let hit = (0..all.count[i]).any(|k| {
                let s = &all.q[(i * all.kmax + k) * 6..][..6];
                s.iter().zip(&q[i * 6..i * 6 + 6]).all(|(a, b)| crate::angle::wrap(a - b).abs() < 1e-7)
            });
            assert!(hit, "row {i}: {:?}", &q[i * 6..i * 6 + 6]);
            if i % 97 == 0 {
                // the same solutions, in the same order, with the same labels as one solve
                let one = crate::ik::solve(&ur5, &target_of(&t[i * 16..][..16], "T").unwrap(), &IkOptions::default())
                    .unwrap();
                assert_eq!(one.solutions.len(), all.count[i]);
                for (k, s) in one.solutions.iter().enumerate() {
                    let slot = i * all.kmax + k;
                    assert_eq!(all.labels[all.branch[slot] as usize], s.branch.to_string());
                    assert_eq!(&all.q[slot * 6..][..6], &s.q[..]);
                }
            }
            assert!(
                (all.count[i]..all.kmax)
                    .all(|k| !all.valid[i * all.kmax + k] && all.q[(i * all.kmax + k) * 6].is_nan())
            );
        }
    }

    #[test]
    fn bad_rows_are_named() {
        let ur5 = presets::get("ur5").unwrap();
        let mut q = vec![0.0; 12];
        q[8] = f64::NAN;
        let e = fk_many(&ur5, &q).unwrap_err().to_string();
        assert!(e.contains("q[1]") && e.contains("joint 3"), "{e}");
        assert!(fk_many(&ur5, &q[..7]).unwrap_err().to_string().contains("rows of 6"));
        let mut t = fk_many(&ur5, &[0.0; 12]).unwrap();
        t[16 + 15] = 2.0;
        let e = ik_many(&ur5, None, &t, None, &IkOptions::default()).unwrap_err().to_string();
        assert!(e.contains("T[1].matrix") && e.contains("0 0 0 1"), "{e}");
    }
}
