//! Helpers shared by the end-to-end tests of the `reach` binary: running it (from the
//! repository root, stdin closed), the success and failure checks every test file makes
//! (exit status, stdout/stderr discipline, JSON output), scratch files and directories that
//! clean up after themselves, and small JSON and angle helpers.
//!
//! Nothing here knows about a particular command; helpers used by one test file stay in it.

// Each test module uses a different subset of these helpers.
#![allow(dead_code)]

use std::ops::Deref;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};

use serde_json::Value;

/// The repository root: the working directory of every run, so that `examples/…` paths work.
pub const REPO_ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

/// The result of one run of the binary.
pub struct Run {
    /// The exit status.
    pub code: i32,
    /// Everything written on stdout.
    pub stdout: String,
    /// Everything written on stderr.
    pub stderr: String,
}

impl Run {
    /// The run's result from the process output; panics if reach was killed by a signal or
    /// wrote something that is not UTF-8.
    pub fn from_output(out: Output) -> Run {
        Run {
            code: out.status.code().expect("reach was killed by a signal"),
            stdout: String::from_utf8(out.stdout).expect("stdout is UTF-8"),
            stderr: String::from_utf8(out.stderr).expect("stderr is UTF-8"),
        }
    }
}

/// The `reach` binary with `args`, run from the repository root; stdin/stdout/stderr are left
/// for the caller to set.
pub fn reach_command(args: &[&str]) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_reach"));
    command.args(args).current_dir(REPO_ROOT);
    command
}

/// Runs `reach args` from the repository root with stdin closed and captures its output.
pub fn reach(args: &[&str]) -> Run {
    let out = reach_command(args).stdin(Stdio::null()).output().expect("run reach");
    Run::from_output(out)
}

/// Runs a command that must succeed quietly (exit 0, nothing on stderr); returns stdout.
pub fn ok(args: &[&str]) -> String {
    let run = reach(args);
    assert_eq!(run.code, 0, "reach {args:?} failed: {}", run.stderr);
    assert!(run.stderr.is_empty(), "reach {args:?} wrote to stderr: {}", run.stderr);
    run.stdout
}

/// Runs a command that must succeed quietly (see [`ok`]) and print JSON; returns the JSON.
pub fn json(args: &[&str]) -> Value {
    let text = ok(args);
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("reach {args:?}: bad JSON ({e}):\n{text}"))
}

/// Runs a command that prints its report and then exits with `code` (3: a verdict that does
/// not hold, after the report, with one line on stderr); returns the report's JSON.
#[track_caller]
pub fn reported(args: &[&str], code: i32) -> Value {
    let run = reach(args);
    assert_eq!(run.code, code, "reach {args:?}: expected exit {code}; stderr: {}", run.stderr);
    assert!(run.stderr.lines().count() == usize::from(code != 0), "reach {args:?}: stderr {}", run.stderr);
    stdout_json(&run)
}

/// The JSON a run printed on stdout, whatever its exit status (checked by the caller).
pub fn stdout_json(run: &Run) -> Value {
    serde_json::from_str(&run.stdout).unwrap_or_else(|e| panic!("bad JSON on stdout ({e}):\n{}", run.stdout))
}

/// Checks a failed run's output: nothing on stdout and exactly one line on stderr, starting
/// with `error: `, with no panic or backtrace. Returns that line (without its newline).
#[track_caller]
pub fn one_error_line(run: &Run) -> String {
    assert!(run.stdout.is_empty(), "stdout not empty: {}", run.stdout);
    assert_eq!(run.stderr.lines().count(), 1, "stderr is not one line:\n{}", run.stderr);
    let line = run.stderr.trim_end().to_string();
    assert!(line.starts_with("error: "), "stderr: {line}");
    assert!(!line.contains("panicked") && !line.contains("backtrace"), "stderr: {line}");
    line
}

/// Runs a command that must fail with exit status `code`, print nothing on stdout and one
/// `error: ` line on stderr (see [`one_error_line`]) that contains every `needle`. Returns the
/// line.
#[track_caller]
pub fn fails(args: &[&str], code: i32, needles: &[&str]) -> String {
    let run = reach(args);
    assert_eq!(run.code, code, "reach {args:?}: expected exit {code}, got {}; stderr: {}", run.code, run.stderr);
    let line = one_error_line(&run);
    for needle in needles {
        assert!(line.contains(needle), "reach {args:?}: `{line}` does not mention `{needle}`");
    }
    line
}

/// A JSON number as `f64`.
pub fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// A JSON array of numbers as `Vec<f64>`.
pub fn nums(v: &Value) -> Vec<f64> {
    v.as_array().unwrap_or_else(|| panic!("not an array: {v}")).iter().map(num).collect()
}

/// Difference `a − b` of two angles in degrees, wrapped into [−180, 180) degrees.
pub fn angle_gap(a: f64, b: f64) -> f64 {
    (a - b + 540.0).rem_euclid(360.0) - 180.0
}

/// A fresh, empty directory under the system temporary directory, removed with everything in
/// it when dropped. Dereferences to its path.
pub struct Scratch(PathBuf);

/// A fresh scratch directory whose name contains `tag` (for a reader of `/tmp`), this process
/// id and a per-process counter, so parallel tests and test binaries never share one.
pub fn scratch(tag: &str) -> Scratch {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "reach-cli-test-{tag}-{}-{}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("create {}: {e}", dir.display()));
    Scratch(dir)
}

impl Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A file in its own scratch directory, removed (with the directory) when dropped.
/// Dereferences to the file's path.
pub struct TempFile {
    path: PathBuf,
    // Owns the directory; dropped (and removed) with the file.
    _dir: Scratch,
}

/// Writes `contents` to a file called `name` in a fresh scratch directory.
pub fn temp_file(name: &str, contents: &str) -> TempFile {
    let dir = scratch("file");
    let path = dir.join(name);
    std::fs::write(&path, contents).unwrap_or_else(|e| panic!("write {}: {e}", path.display()));
    TempFile { path, _dir: dir }
}

impl Deref for TempFile {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.path
    }
}

impl AsRef<Path> for TempFile {
    fn as_ref(&self) -> &Path {
        &self.path
    }
}

/// Checks a command's `--json` output against the library: it must equal the library's report
/// for the same job (`reach::jobs::Job::run`, serialised), and validate against the JSON Schema
/// `docs/schemas/<schema>.schema.json`. Returns the output.
#[allow(dead_code, reason = "not every test module checks reports")]
pub fn assert_report(args: &[&str], job: &reach::jobs::Job, schema: &str) -> Value {
    let output = json(args);
    let report = job.run().unwrap_or_else(|e| panic!("the library fails the same job: {e}"));
    let mut expected = serde_json::to_value(&report).unwrap();
    // The CLI prints the workflow's report itself, without the `kind` tag of `jobs::Report`.
    if let Value::Object(map) = &mut expected {
        map.remove("kind");
    }
    assert_eq!(output, expected, "`reach {}` --json differs from the library report", args.join(" "));
    assert_valid(schema, &output);
    output
}

/// Validates `value` against `docs/schemas/<schema>.schema.json`, listing every violation.
#[allow(dead_code, reason = "not every test module checks reports")]
pub fn assert_valid(schema: &str, value: &Value) {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../docs/schemas/{schema}.schema.json"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let schema_value: Value = serde_json::from_str(&text).unwrap();
    let validator = jsonschema::validator_for(&schema_value).unwrap_or_else(|e| panic!("{schema}: bad schema: {e}"));
    let errors: Vec<String> = validator.iter_errors(value).map(|e| format!("{} at {}", e, e.instance_path())).collect();
    assert!(errors.is_empty(), "output does not match {schema}: {errors:#?}");
}
