//! Output helpers shared by the commands: number formatting, matrices, poses, tables, JSON.
//!
//! Conventions of the printed output:
//!
//! * human-readable output names its units (`[m]`, `[deg]`); JSON field names carry the unit
//!   (`xyz_m`, `rpy_deg`), and JSON numbers are SI unless the name says otherwise;
//! * 4×4 matrices are row-major (`matrix[row][column]`);
//! * `rpy` is roll–pitch–yaw about fixed axes, `R = Rz(yaw)·Ry(pitch)·Rx(roll)`;
//! * quaternions are `w x y z` with `w ≥ 0` (of the two equivalent signs, the one with a
//!   non-negative scalar part is printed).

use std::io::Write;

use serde::Serialize;

use crate::error::CliError;

pub use reach::jobs::PoseReport;
pub use reach::jobs::input::{rpy_deg, rpy_rad};

/// The outcome of a command whose report is on `out` already: the one mapping of a verdict to
/// the exit status. `None` (the verdict holds: feasible, reached, clear) is success; a
/// `failure` (infeasible, no solution, not proven clear) flushes the report (`main` discards
/// unflushed output on an error) and fails with [`CliError::NoSolution`] (exit status 3, the
/// failure as the one line on stderr).
///
/// # Errors
/// [`CliError::NoSolution`] with `failure`; [`CliError::Output`] when the flush fails.
pub fn verdict_exit(out: &mut dyn Write, failure: Option<String>) -> Result<(), CliError> {
    match failure {
        None => Ok(()),
        Some(failure) => {
            out.flush()?;
            Err(CliError::NoSolution(failure))
        }
    }
}

/// Writes `contents` to the file `path` given with `option` (`--csv`, `-o`, `--svg`).
///
/// # Errors
/// [`CliError::BadInput`] naming the option and the path when the file cannot be written.
pub fn write_file(option: &str, path: &std::path::Path, contents: impl AsRef<[u8]>) -> Result<(), CliError> {
    std::fs::write(path, contents).map_err(|e| CliError::bad_input(format!("{option} {}: {e}", path.display())))
}

/// Reads the text of the input file `path`; `-` is standard input (read once, the same text
/// for every reader of `-` in the command).
///
/// # Errors
/// [`CliError::BadInput`] naming the path (or standard input) when it cannot be read.
pub fn read_file(path: &std::path::Path) -> Result<String, CliError> {
    if path == std::path::Path::new("-") {
        return read_stdin();
    }
    std::fs::read_to_string(path).map_err(|e| CliError::bad_input(format!("cannot read `{}`: {e}", path.display())))
}

/// The whole standard input as text, read on the first call and kept for the next.
fn read_stdin() -> Result<String, CliError> {
    use std::io::Read;
    static STDIN: std::sync::OnceLock<Result<String, String>> = std::sync::OnceLock::new();
    STDIN
        .get_or_init(|| {
            let mut text = String::new();
            std::io::stdin().read_to_string(&mut text).map(|_| text).map_err(|e| e.to_string())
        })
        .clone()
        .map_err(|e| CliError::bad_input(format!("cannot read standard input: {e}")))
}

/// Reads a motion file: `reach move --json`'s output (or any JSON `{"samples": [{"t_s",
/// "q_deg"}, ...]}`, or `reach path --json`), or the CSV of `reach move --csv` /
/// `reach retime --csv` (`reach::jobs::input::parse_motion_file`).
///
/// # Errors
/// [`CliError::BadInput`] naming the path when it cannot be read or is not such JSON.
pub fn read_motion_file(path: &std::path::Path) -> Result<Vec<reach::jobs::input::MotionSample>, CliError> {
    let name = if path == std::path::Path::new("-") { "standard input".into() } else { path.display().to_string() };
    reach::jobs::input::parse_motion_file(&read_file(path)?)
        .map_err(|e| CliError::bad_input(format!("{name}: {}", reach::one_line(&e.to_string()))))
}

/// Writes `value` as indented JSON followed by a newline.
///
/// Like `serde_json`'s pretty printer (fields in declaration order), except that arrays of
/// plain values (numbers, `null`, booleans, strings) stay on one line, so a 4×4 matrix
/// takes four lines, not 24.
///
/// # Errors
/// [`CliError::Output`] when writing fails; [`CliError::Internal`] if `value` cannot be
/// represented as JSON.
pub fn write_json<T: Serialize>(out: &mut dyn Write, value: &T) -> Result<(), CliError> {
    let compact = serde_json::to_string(value)?;
    let mut text = String::with_capacity(compact.len() * 2);
    let mut parser = Compact { text: compact.as_bytes(), pos: 0 };
    parser.value(0, &mut text);
    text.push('\n');
    out.write_all(text.as_bytes())?;
    Ok(())
}

/// Re-indents the compact JSON written by `serde_json::to_string` (which is valid, has no
/// blanks outside strings, and keeps the field order).
struct Compact<'a> {
    text: &'a [u8],
    pos: usize,
}

impl Compact<'_> {
    fn peek(&self) -> u8 {
        self.text.get(self.pos).copied().unwrap_or(b']')
    }

    /// Copies one scalar (string, number, literal) to `out`.
    fn scalar(&mut self, out: &mut String) {
        let start = self.pos;
        if self.peek() == b'"' {
            self.pos += 1;
            while self.pos < self.text.len() {
                match self.text[self.pos] {
                    b'\\' => self.pos += 2,
                    b'"' => {
                        self.pos += 1;
                        break;
                    }
                    _ => self.pos += 1,
                }
            }
        } else {
            while self.pos < self.text.len() && !matches!(self.text[self.pos], b',' | b']' | b'}' | b':') {
                self.pos += 1;
            }
        }
        out.push_str(&String::from_utf8_lossy(&self.text[start..self.pos.min(self.text.len())]));
    }

    /// Whether the array starting at `self.pos` (on its `[`) holds only scalars.
    fn flat_array(&self) -> bool {
        let mut in_string = false;
        let mut escaped = false;
        for &c in &self.text[self.pos + 1..] {
            match (in_string, escaped, c) {
                (true, true, _) => escaped = false,
                (true, false, b'\\') => escaped = true,
                (true, false, b'"') | (false, _, b'"') => in_string = !in_string,
                (false, _, b'[' | b'{') => return false,
                (false, _, b']') => return true,
                _ => {}
            }
        }
        true
    }

    fn value(&mut self, depth: usize, out: &mut String) {
        let indent = |d: usize| "  ".repeat(d);
        match self.peek() {
            open @ (b'[' | b'{') => {
                let close = if open == b'[' { b']' } else { b'}' };
                let flat = open == b'[' && self.flat_array();
                self.pos += 1;
                out.push(char::from(open));
                if self.peek() == close {
                    self.pos += 1;
                    out.push(char::from(close));
                    return;
                }
                loop {
                    if flat {
                        self.scalar(out);
                    } else {
                        out.push('\n');
                        out.push_str(&indent(depth + 1));
                        if open == b'{' {
                            self.scalar(out); // key
                            self.pos += 1; // ':'
                            out.push_str(": ");
                        }
                        self.value(depth + 1, out);
                    }
                    let c = self.peek();
                    self.pos += 1;
                    if c == b',' {
                        out.push_str(if flat { ", " } else { "," });
                    } else {
                        break;
                    }
                }
                if !flat {
                    out.push('\n');
                    out.push_str(&indent(depth));
                }
                out.push(char::from(close));
            }
            _ => self.scalar(out),
        }
    }
}

/// `x` with a fixed number of decimals, never printing `-0.000`.
#[must_use]
pub fn fixed(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') { s[1..].to_string() } else { s }
}

/// `x` with at most 9 decimals and no trailing zeros: `90`, `0.4318`, `-1.570796327`.
///
/// Meant for values that were typed by a person (description files), where conversion
/// noise such as `90.00000000000001` should not show.
#[must_use]
pub fn num(x: f64) -> String {
    if !x.is_finite() {
        return if x.is_nan() {
            "NaN".into()
        } else if x > 0.0 {
            "inf".into()
        } else {
            "-inf".into()
        };
    }
    let s = fixed(x, 9);
    let s = if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s };
    if s == "-0" { "0".into() } else { s }
}

/// Joins values formatted by [`num`] with single spaces.
#[must_use]
pub fn nums(values: &[f64]) -> String {
    values.iter().map(|&v| num(v)).collect::<Vec<_>>().join(" ")
}

/// Joins values formatted by [`fixed`] with single spaces.
#[must_use]
pub fn fixeds(values: &[f64], decimals: usize) -> String {
    values.iter().map(|&v| fixed(v, decimals)).collect::<Vec<_>>().join(" ")
}

/// Writes the rows of a matrix with aligned columns, each line starting with `indent`.
///
/// # Errors
/// [`CliError::Output`] when writing fails.
pub fn write_matrix<R: AsRef<[f64]>>(
    out: &mut dyn Write,
    rows: &[R],
    decimals: usize,
    indent: &str,
) -> Result<(), CliError> {
    let cells: Vec<Vec<String>> =
        rows.iter().map(|r| r.as_ref().iter().map(|&v| fixed(v, decimals)).collect()).collect();
    let width = cells.iter().flatten().map(String::len).max().unwrap_or(0);
    for row in cells {
        let line: Vec<String> = row.iter().map(|c| format!("{c:>width$}")).collect();
        writeln!(out, "{indent}{}", line.join("  "))?;
    }
    Ok(())
}

/// Writes a pose for people: position [m], rpy [deg], quaternion, 4×4 matrix. Every line
/// starts with `indent`.
///
/// # Errors
/// [`CliError::Output`] when writing fails.
pub fn write_pose(out: &mut dyn Write, pose: &PoseReport, indent: &str) -> Result<(), CliError> {
    let mut lines = Table::key_value();
    lines.pair("position [m]", format!("{}   (x y z)", fixeds(&pose.xyz_m, 6)));
    lines.pair("rpy [deg]", format!("{}   (roll pitch yaw: R = Rz(yaw)·Ry(pitch)·Rx(roll))", fixeds(&pose.rpy_deg, 4)));
    lines.pair("quaternion", format!("{}   (w x y z)", fixeds(&pose.quat_wxyz, 6)));
    lines.pair("matrix", "(row-major, world ← tool)");
    lines.write(out, indent)?;
    write_matrix(out, &pose.matrix, 6, &format!("{indent}  "))
}

/// Alignment of a table column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Align {
    /// Pad on the right.
    Left,
    /// Pad on the left (numbers).
    Right,
}

/// A matrix with one column per joint (`q1 … qn`): each row its label, then its entries with
/// six decimals (the Jacobian's rows, the mass matrix).
pub fn joint_matrix_table<'a>(dof: usize, rows: impl IntoIterator<Item = (String, &'a [f64])>) -> Table {
    let headers: Vec<String> = (1..=dof).map(|i| format!("q{i}")).collect();
    let mut columns = vec![("", Align::Left)];
    columns.extend(headers.iter().map(|h| (h.as_str(), Align::Right)));
    let mut table = Table::new(&columns);
    for (label, row) in rows {
        let mut cells = vec![label];
        cells.extend(row.iter().map(|&v| fixed(v, 6)));
        table.row(cells);
    }
    table
}

/// A plain-text table with a header row and aligned columns.
#[derive(Debug, Clone, Default)]
pub struct Table {
    header: Vec<String>,
    align: Vec<Align>,
    rows: Vec<Vec<String>>,
    show_header: bool,
}

impl Table {
    /// A table with these column headers and alignments.
    #[must_use]
    pub fn new(columns: &[(&str, Align)]) -> Self {
        Table {
            header: columns.iter().map(|(h, _)| (*h).to_string()).collect(),
            align: columns.iter().map(|(_, a)| *a).collect(),
            rows: Vec::new(),
            show_header: true,
        }
    }

    /// A two-column `key  value` list without a header row.
    #[must_use]
    pub fn key_value() -> Self {
        Table { show_header: false, ..Table::new(&[("", Align::Left), ("", Align::Left)]) }
    }

    /// Appends a `key  value` row.
    pub fn pair(&mut self, key: &str, value: impl Into<String>) {
        self.rows.push(vec![key.to_string(), value.into()]);
    }

    /// Appends a row (missing cells are blank, extra cells are ignored).
    pub fn row(&mut self, cells: Vec<String>) {
        self.rows.push(cells);
    }

    /// Writes the table, each line starting with `indent`, columns two spaces apart.
    ///
    /// # Errors
    /// [`CliError::Output`] when writing fails.
    pub fn write(&self, out: &mut dyn Write, indent: &str) -> Result<(), CliError> {
        let n = self.header.len();
        let cell = |row: &Vec<String>, c: usize| row.get(c).cloned().unwrap_or_default();
        let header = self.show_header.then_some(&self.header);
        let widths: Vec<usize> = (0..n)
            .map(|c| header.into_iter().chain(&self.rows).map(|r| cell(r, c).chars().count()).max().unwrap_or(0))
            .collect();
        for row in header.into_iter().chain(&self.rows) {
            let mut line = String::from(indent);
            for (c, (width, align)) in widths.iter().zip(&self.align).enumerate() {
                let text = cell(row, c);
                let pad = width - text.chars().count();
                if c > 0 {
                    line.push_str("  ");
                }
                match align {
                    Align::Left => {
                        line.push_str(&text);
                        line.push_str(&" ".repeat(pad));
                    }
                    Align::Right => {
                        line.push_str(&" ".repeat(pad));
                        line.push_str(&text);
                    }
                }
            }
            writeln!(out, "{}", line.trim_end())?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn numbers_print_without_noise_or_negative_zero() {
        assert_eq!(num(FRAC_PI_2.to_degrees()), "90");
        assert_eq!(num(0.4 / 1e-3), "400");
        assert_eq!(num(-1e-12), "0");
        assert_eq!(num(0.4318), "0.4318");
        assert_eq!(fixed(-1e-9, 3), "0.000");
        assert_eq!(fixed(-0.5, 1), "-0.5");
        assert_eq!(num(f64::INFINITY), "inf");
    }

    #[test]
    fn json_keeps_number_arrays_on_one_line() {
        let mut buf = Vec::new();
        let value = serde_json::json!({
            "m": [[1.0, 2.0], [3.0, -0.5]],
            "s": "a\"b],{\\",
            "e": [],
            "o": {},
            "n": null,
            "l": [{"k": ["x,", "]"]}, true]
        });
        write_json(&mut buf, &value).unwrap();
        let text = String::from_utf8(buf).unwrap();
        assert!(text.contains("    [1.0, 2.0],\n    [3.0, -0.5]\n"), "{text}");
        assert!(text.contains(r#""k": ["x,", "]"]"#), "{text}");
        let back: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(back, value);
    }
}
