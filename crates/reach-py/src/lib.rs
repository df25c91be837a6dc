//! `reach._reach`: the Python extension module of the `reach` package (pyo3 + maturin).
//!
//! A thin adapter: numpy arrays in, the library's batch kernels ([`reach::batch`]) or its jobs
//! layer ([`reach::jobs`]) in the middle, numpy arrays and dicts out. Nothing here computes a
//! numeric rule of its own: unit conversions are [`reach::jobs::input::to_si`] /
//! [`reach::jobs::input::from_si`], poses are validated by [`reach::jobs::input::Pose`], IK
//! options by [`reach::jobs::ik::solver_options`], and every workflow is a
//! [`reach::jobs::Request`] run by [`reach::jobs::run`]. Batch calls release the GIL while the
//! library works (on its rayon pool). Library errors become [`ReachError`], a `ValueError`
//! carrying the library's one-line message.
//!
//! The Python side (`python/reach/`) re-exports the class, turns reports' numeric lists into
//! numpy arrays (`_convert.py`) and holds the optional parts (Ray, SciPy / spatialmath).

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use std::collections::HashMap;

use pyo3::types::{PyDict, PyList, PyString, PyTuple};
use reach::ik::{IkOptions, SolverKind, numeric::TaskAxes};
use reach::jobs::input::MotionSample;
use reach::jobs::input::{AngleUnit, from_si, to_si};
use reach::jobs::view::ViewEvent;
use reach::jobs::{self, IkRequest, Joints, MoveReport, Pose, Request, RobotInput, ViewRequest};
use reach::model::{Convention, Joint, JointKind, RobotSpec, presets};

pyo3::create_exception!(
    _reach,
    ReachError,
    PyValueError,
    "Bad input rejected by the reach library; the message is the library's (naming the field)."
);

/// A library error as a Python exception.
fn lib_err(e: &reach::Error) -> PyErr {
    ReachError::new_err(reach::one_line(&e.to_string()))
}

/// A `ValueError` naming the argument.
fn value_err(message: impl Into<String>) -> PyErr {
    ReachError::new_err(message.into())
}

/// A float64 array of `obj` (any array-like; a spatialmath `SE3` through its `.A`), C-contiguous,
/// with its shape.
fn float_array(py: Python<'_>, obj: &Bound<'_, PyAny>, name: &str) -> PyResult<(Vec<usize>, Vec<f64>)> {
    let np = py.import("numpy")?;
    let source =
        if obj.hasattr("A")? && !obj.is_instance(&np.getattr("ndarray")?)? { obj.getattr("A")? } else { obj.clone() };
    let array = np
        .call_method1("ascontiguousarray", (source, "float64"))
        .map_err(|e| value_err(format!("{name}: expected an array of numbers ({e})")))?;
    let array: PyReadonlyArrayDyn<'_, f64> = array.extract()?;
    let shape = array.shape().to_vec();
    let data = array.as_slice().map_err(|e| value_err(format!("{name}: {e}")))?.to_vec();
    Ok((shape, data))
}

/// `Some(n)` for a batch `(N, *inner)`, `None` for one item of shape `inner`; a `ValueError`
/// naming the argument and both shapes otherwise.
fn batch_shape(name: &str, shape: &[usize], inner: &[usize]) -> PyResult<Option<usize>> {
    if shape == inner {
        return Ok(None);
    }
    if shape.len() == inner.len() + 1 && &shape[1..] == inner {
        return Ok(Some(shape[0]));
    }
    Err(value_err(format!(
        "{name}: expected shape {} or (N, {}), got {}",
        tuple(inner),
        tuple(inner).trim_matches(['(', ')', ',']),
        tuple(shape)
    )))
}

/// A shape as Python prints it: `(6,)`, `(3, 5)`.
fn tuple(shape: &[usize]) -> String {
    let items: Vec<String> = shape.iter().map(ToString::to_string).collect();
    if items.len() == 1 { format!("({},)", items[0]) } else { format!("({})", items.join(", ")) }
}

/// A float64 numpy array of `data` with `shape`.
fn to_numpy<'py>(py: Python<'py>, data: Vec<f64>, shape: Vec<usize>) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_vec(py, data).reshape(shape)?.into_any())
}

/// A bool numpy array of `data` with `shape`.
fn to_numpy_bool<'py>(py: Python<'py>, data: Vec<bool>, shape: Vec<usize>) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_vec(py, data).reshape(shape)?.into_any())
}

/// JSON text as Python objects, numeric lists as numpy arrays (`reach._convert.arrays`).
fn from_json<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyAny>> {
    let value = py.import("json")?.call_method1("loads", (text,))?;
    py.import("reach._convert")?.call_method1("arrays", (value,))
}

/// A serialisable library value as Python objects (see [`from_json`]).
fn to_python<'py, T: serde::Serialize>(py: Python<'py>, value: &T) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value).map_err(|e| value_err(e.to_string()))?;
    from_json(py, &text)
}

/// How a [`Robot`] was made, to rebuild it when unpickled.
#[derive(serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
enum State {
    /// A preset or a description's text.
    Input(RobotInput),
    /// [`Robot::from_dh`]'s table, SI.
    Dh(DhTable),
}

/// A DH table as given to [`Robot::from_dh`] (SI).
#[derive(serde::Serialize, serde::Deserialize)]
struct DhTable {
    rows: Vec<f64>,
    width: usize,
    prismatic: Vec<usize>,
    modified: bool,
    name: String,
}

/// A robot model: kinematics, IK and every workflow of the `reach` library.
#[pyclass(module = "reach", name = "Robot", frozen)]
struct Robot {
    robot: reach::Robot,
    /// How to rebuild it (pickling, e.g. for Ray workers): JSON, see [`Robot::restore`].
    state: String,
    /// The URDF file it was read from (canonical path), whose visual meshes its views draw.
    urdf_file: Option<std::path::PathBuf>,
}

/// The file a URDF document at `document` (canonical path) names as `filename` (`package://`,
/// relative or `file://`, [`reach::model::mesh_file_path`]).
fn mesh_file(document: &std::path::Path, filename: &str) -> Result<std::path::PathBuf, String> {
    reach::model::mesh_file_path(document, filename, &|d: &std::path::Path| d.is_dir())
}

impl Robot {
    fn from_input(input: RobotInput) -> PyResult<Self> {
        let robot = input.load().map_err(|e| lib_err(&e))?.robot;
        let state = serde_json::to_string(&State::Input(input)).map_err(|e| value_err(e.to_string()))?;
        Ok(Robot { robot, state, urdf_file: None })
    }

    fn dh(rows: &[f64], width: usize, prismatic: &[usize], modified: bool, name: &str) -> PyResult<Self> {
        let n = rows.len() / width;
        if let Some(&bad) = prismatic.iter().find(|&&j| j >= n) {
            return Err(value_err(format!("prismatic: joint index {bad} is not below the {n} rows")));
        }
        let joints = (0..n)
            .map(|i| {
                let r = &rows[i * width..(i + 1) * width];
                let joint = if prismatic.contains(&i) {
                    Joint::prismatic(r[0], r[1], r[2], r[3])
                } else {
                    Joint::revolute(r[0], r[1], r[2], r[3])
                };
                let joint = joint.named(format!("q{}", i + 1));
                if width == 6 { joint.with_limits(r[4], r[5]) } else { joint }
            })
            .collect();
        let convention = if modified { Convention::Mdh } else { Convention::Dh };
        let robot =
            reach::Robot::new(RobotSpec::new(name, convention, joints)).map_err(|e| lib_err(&reach::Error::from(e)))?;
        let dh =
            DhTable { rows: rows.to_vec(), width, prismatic: prismatic.to_vec(), modified, name: name.to_string() };
        let state = serde_json::to_string(&State::Dh(dh)).map_err(|e| value_err(e.to_string()))?;
        Ok(Robot { robot, state, urdf_file: None })
    }

    /// Joint values of `q` (the last axis has one value per joint) in SI.
    fn si(&self, q: Vec<f64>, degrees: bool) -> Vec<f64> {
        if !degrees {
            return q;
        }
        let joints = self.robot.joints();
        q.iter().enumerate().map(|(i, v)| to_si(joints[i % joints.len()].kind, *v, AngleUnit::Deg)).collect()
    }

    /// SI joint values in degrees (revolute) or metres (prismatic) when `degrees`.
    fn display(&self, q: Vec<f64>, degrees: bool) -> Vec<f64> {
        if !degrees {
            return q;
        }
        let joints = self.robot.joints();
        q.iter().enumerate().map(|(i, v)| from_si(joints[i % joints.len()].kind, *v, AngleUnit::Deg)).collect()
    }

    /// A joint array `(dof,)` or `(N, dof)`: its rows (SI) and `N` (`None` for one vector).
    fn joint_rows(
        &self,
        py: Python<'_>,
        q: &Bound<'_, PyAny>,
        name: &str,
        degrees: bool,
    ) -> PyResult<(Option<usize>, Vec<f64>)> {
        let (shape, data) = float_array(py, q, name)?;
        let n = batch_shape(name, &shape, &[self.robot.dof()])?;
        Ok((n, self.si(data, degrees)))
    }

    /// Runs the `kind` workflow of a request dict and/or keyword arguments (keywords win;
    /// `defaults` fill fields neither gives).
    fn workflow<'py>(
        slf: &Bound<'py, Self>,
        kind: &str,
        request: Option<&Bound<'py, PyAny>>,
        kwargs: Option<&Bound<'py, PyDict>>,
        defaults: &[(&str, &str)],
        degrees: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let py = slf.py();
        let merged = PyDict::new(py);
        for (k, v) in defaults {
            merged.set_item(k, v)?;
        }
        if let Some(r) = request {
            merged.call_method1("update", (r,))?;
        }
        if let Some(k) = kwargs {
            merged.update(k.as_mapping())?;
        }
        let text: String =
            py.import("reach._convert")?.call_method1("workflow", (kind, merged, PyDict::new(py)))?.extract()?;
        let request: Request = serde_json::from_str(&text)
            .map_err(|e| value_err(format!("{kind} request: {}", reach::one_line(&e.to_string()))))?;
        Robot::run_request(slf, py, &request, degrees)
    }

    /// Runs one request. The report is the CLI's `--json` output as a dict, except that a
    /// sampled motion (`move`, each motion of `plan`, the timed path of `path`) carries its
    /// trajectory as SI arrays ([`Robot::set_trajectory`]) instead of its `samples` list, and
    /// `check`'s verdict is flat ([`Robot::flat_check`]). Motions come back as `reach.Motion` (a dict
    /// that shows itself in a notebook).
    fn run_request<'py>(
        slf: &Bound<'py, Self>,
        py: Python<'py>,
        request: &Request,
        degrees: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let this = slf.get();
        let robot = &this.robot;
        let motion = |dict: Bound<'py, PyDict>, view: &ViewRequest| -> PyResult<Bound<'py, PyAny>> {
            let view = serde_json::to_string(view).map_err(|e| value_err(e.to_string()))?;
            py.import("reach._results")?.getattr("Motion")?.call1((dict, slf, view))
        };
        if let Request::Path(r) = request {
            let run = py.detach(|| jobs::world::path::path_run(robot, r)).map_err(|e| lib_err(&e))?;
            let dict = to_python(py, &run.report)?.cast_into::<PyDict>()?;
            let k = run.waypoints.len();
            dict.set_item(
                "waypoints",
                to_numpy(py, this.display(run.waypoints.concat(), degrees), vec![k, robot.dof()])?,
            )?;
            let Some(timed) = run.timed else { return Ok(dict.into_any()) };
            let samples = timed
                .times
                .iter()
                .zip(&timed.q)
                .map(|(&t_s, q)| MotionSample { t_s, q_deg: this.display(q.clone(), true) })
                .collect();
            this.set_trajectory(py, &dict, timed.times, timed.q, timed.qd, None, degrees)?;
            let xyz: Vec<f64> = timed.tool_xyz_m.iter().flatten().copied().collect();
            dict.set_item("tool_xyz", to_numpy(py, xyz, vec![timed.tool_xyz_m.len(), 3])?)?;
            let view = ViewRequest { samples: Some(samples), scene: Some(r.scene.clone()), ..ViewRequest::default() };
            return motion(dict, &view);
        }
        let report = py.detach(|| jobs::run(robot, request)).map_err(|e| lib_err(&e))?;
        match (&report, request) {
            (jobs::Report::Move(m), Request::Move(r)) => {
                let dict = this.motion_dict(py, m, degrees)?;
                let view = ViewRequest {
                    samples: Some(
                        m.samples.iter().map(|s| MotionSample { t_s: s.t_s, q_deg: s.q_deg.clone() }).collect(),
                    ),
                    events: ViewEvent::of_move(m, 0.0),
                    scene: r.scene.clone(),
                    ..ViewRequest::default()
                };
                return motion(dict, &view);
            }
            (jobs::Report::Plan(p), Request::Plan(r)) => {
                let dict = to_python(py, p)?.cast_into::<PyDict>()?;
                let motions = PyList::empty(py);
                for m in &p.motions {
                    motions.append(this.motion_dict(py, m, degrees)?)?;
                }
                dict.set_item("motions", motions)?;
                let view = ViewRequest { task: Some(r.task.clone()), scene: r.scene.clone(), ..ViewRequest::default() };
                return motion(dict, &view);
            }
            (jobs::Report::Check(c), _) => return this.flat_check(py, c, degrees),
            _ => {}
        }
        // The CLI prints the workflow's own report; `kind` only tags the enum.
        let mut value = serde_json::to_value(&report).map_err(|e| value_err(e.to_string()))?;
        if let Some(map) = value.as_object_mut() {
            map.remove("kind");
        }
        to_python(py, &value)
    }

    /// Sets a sampled trajectory on `dict` as arrays: `t` `(M,)` seconds and `q`, `qd`, `qdd`
    /// `(M, dof)` from SI rows (rad or m, per second, per second squared), shown in degrees
    /// (prismatic metres) per second… with `degrees`. `qdd` when the report has none: the
    /// library's rate rule on the positions ([`reach::effort::dynamics::joint_rates`]).
    #[allow(clippy::too_many_arguments, reason = "the four arrays of one trajectory")]
    fn set_trajectory(
        &self,
        py: Python<'_>,
        dict: &Bound<'_, PyDict>,
        t: Vec<f64>,
        q: Vec<Vec<f64>>,
        qd: Vec<Vec<f64>>,
        qdd: Option<Vec<Vec<f64>>>,
        degrees: bool,
    ) -> PyResult<()> {
        let qdd = match qdd {
            Some(qdd) => qdd,
            None => {
                reach::effort::dynamics::joint_rates(&self.robot, &t, &q)
                    .map_err(|e| value_err(format!("samples: {e}")))?
                    .1
            }
        };
        let (m, dof) = (t.len(), self.robot.dof());
        dict.set_item("t", to_numpy(py, t, vec![m])?)?;
        for (key, rows) in [("q", q), ("qd", qd), ("qdd", qdd)] {
            dict.set_item(key, to_numpy(py, self.display(rows.concat(), degrees), vec![m, dof])?)?;
        }
        Ok(())
    }

    /// A move report as a dict: its `samples` become the trajectory arrays
    /// ([`Robot::set_trajectory`]) and the tool's path `tool_xyz` `(M, 3)` metres and
    /// `tool_rpy` `(M, 3)` radians (roll, pitch, yaw); everything else as the CLI prints it.
    fn motion_dict<'py>(&self, py: Python<'py>, report: &MoveReport, degrees: bool) -> PyResult<Bound<'py, PyDict>> {
        let dict = to_python(py, report)?.cast_into::<PyDict>()?;
        dict.del_item("samples")?;
        let robot = &self.robot;
        let m = report.samples.len();
        let (mut t, mut q, mut qd) = (Vec::with_capacity(m), Vec::with_capacity(m), Vec::with_capacity(m));
        let (mut xyz, mut rpy) = (Vec::with_capacity(3 * m), Vec::with_capacity(3 * m));
        for (k, s) in report.samples.iter().enumerate() {
            t.push(s.t_s);
            q.push(Joints::Deg(s.q_deg.clone()).si(robot, &format!("samples: sample {k}")).map_err(|e| lib_err(&e))?);
            qd.push(self.si(s.qd_deg_s.clone(), true));
            xyz.extend(s.xyz_m);
            rpy.extend(s.rpy_deg.iter().map(|a| a.to_radians()));
        }
        self.set_trajectory(py, &dict, t, q, qd, None, degrees)?;
        dict.set_item("tool_xyz", to_numpy(py, xyz, vec![m, 3])?)?;
        dict.set_item("tool_rpy", to_numpy(py, rpy, vec![m, 3])?)?;
        Ok(dict)
    }

    /// The HTML of a view request (JSON text of a [`ViewRequest`]; `None`: the robot at home):
    /// `reach view`'s offline page, in an `<iframe srcdoc>` for a notebook when `frame`.
    fn view_html(&self, request: Option<&str>, frame: bool, meshes: bool) -> PyResult<String> {
        let mut request: ViewRequest = match request {
            Some(text) => serde_json::from_str(text)
                .map_err(|e| value_err(format!("view request: {}", reach::one_line(&e.to_string()))))?,
            None => ViewRequest::default(),
        };
        if meshes && request.urdf.is_none() {
            request.urdf = self.view_urdf()?;
        }
        let report = jobs::view::view(&self.robot, &request).map_err(|e| lib_err(&e))?;
        let json = serde_json::to_string(&report).map_err(|e| value_err(e.to_string()))?;
        let page = jobs::view::page(&report.robot, &json, false);
        Ok(if frame { notebook_frame(&page) } else { page })
    }

    /// A check report as a dict with a flat verdict: `verdict` is the outcome's name (`free`,
    /// `outside_zone`, `self_collision`, `obstacle`), its fields beside it prefixed `verdict_`
    /// (`verdict_link`, `verdict_obstacle` (0-based index), `verdict_zone`, `verdict_link_a`,
    /// `verdict_link_b`), `clear` the verdict of the whole check
    /// ([`reach::jobs::CheckReport::is_clear`]: the configuration free and its motion, when
    /// given, proven clear), and the joint values `q` (and the motion's `to`) in SI (degrees
    /// with `degrees`) beside the report's `q_deg` (`to_deg`).
    fn flat_check<'py>(
        &self,
        py: Python<'py>,
        report: &jobs::CheckReport,
        degrees: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let mut value = serde_json::to_value(report).map_err(|e| value_err(e.to_string()))?;
        let si = |q: &[f64], field: &str| -> PyResult<Vec<f64>> {
            let q = Joints::Deg(q.to_vec()).si(&self.robot, field).map_err(|e| lib_err(&e))?;
            Ok(self.display(q, degrees))
        };
        if let Some(map) = value.as_object_mut() {
            if let Some(serde_json::Value::Object(verdict)) = map.remove("verdict") {
                for (k, v) in verdict {
                    map.insert(if k == "verdict" { k } else { format!("verdict_{k}") }, v);
                }
            }
            map.insert("clear".into(), report.is_clear().into());
            map.insert("q".into(), si(&report.q_deg, "q_deg")?.into());
            if let (Some(motion), Some(serde_json::Value::Object(m))) = (&report.motion, map.get_mut("motion")) {
                m.insert("to".into(), si(&motion.to_deg, "to_deg")?.into());
            }
        }
        to_python(py, &value)
    }

    /// For a robot read from a URDF file: the document with every visual mesh it references,
    /// read from disk (what `reach view` draws); `None` for other robots.
    fn view_urdf(&self) -> PyResult<Option<jobs::view::ViewUrdf>> {
        let (Some(document), Ok(State::Input(RobotInput::Urdf { text, base, tip, .. }))) =
            (&self.urdf_file, serde_json::from_str::<State>(&self.state))
        else {
            return Ok(None);
        };
        let chain = reach::model::UrdfChain { base, tip };
        let urdf = jobs::view::ViewUrdf::read(&text, &chain, |filename| {
            let fail = |message: String| reach::Error::File { what: "mesh file", message };
            let file = mesh_file(document, filename).map_err(|why| fail(format!("`{filename}`: {why}")))?;
            std::fs::read(&file).map_err(|e| fail(format!("`{filename}` ({}): {e}", file.display())))
        })
        .map_err(|e| {
            value_err(format!("{} (meshes=False draws the links as capsules)", reach::one_line(&e.to_string())))
        })?;
        Ok(Some(urdf))
    }
}

/// A page (the viewer's HTML) as an `<iframe srcdoc>` for a notebook cell: the page is its
/// own document, so its script runs and its styles stay inside; the attribute is escaped
/// (`&`, `"`, `<`, `>`), so the page's text cannot end it.
fn notebook_frame(page: &str) -> String {
    let escaped = page.replace('&', "&amp;").replace('"', "&quot;").replace('<', "&lt;").replace('>', "&gt;");
    format!(
        "<iframe srcdoc=\"{escaped}\" style=\"width: 100%; height: 520px; border: 0\" \
         sandbox=\"allow-scripts\"></iframe>"
    )
}

#[pymethods]
impl Robot {
    /// A preset robot by name (`Robot.presets()` lists them).
    #[staticmethod]
    fn preset(name: &str) -> PyResult<Self> {
        Robot::from_input(RobotInput::Preset(name.to_string()))
    }

    /// The names of the preset robots.
    #[staticmethod]
    fn presets() -> Vec<&'static str> {
        presets::names()
    }

    /// A robot from a TOML or URDF description file (URDF by extension `.urdf` / `.xml` or a
    /// text starting with `<`); `base` and `tip` select a URDF chain.
    #[staticmethod]
    #[pyo3(signature = (path, base=None, tip=None, srdf=None))]
    fn from_file(
        path: std::path::PathBuf,
        base: Option<String>,
        tip: Option<String>,
        srdf: Option<std::path::PathBuf>,
    ) -> PyResult<Self> {
        let text = std::fs::read_to_string(&path)
            .map_err(|e| PyOSError::new_err(format!("cannot read robot file `{}`: {e}", path.display())))?;
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        let urdf = matches!(ext.as_deref(), Some("urdf" | "xml")) || text.trim_start().starts_with('<');
        if !urdf && (base.is_some() || tip.is_some() || srdf.is_some()) {
            return Err(value_err("base/tip/srdf apply to a URDF file; this is a TOML description"));
        }
        if !urdf {
            return Robot::from_input(RobotInput::Toml { text });
        }
        let canonical = std::fs::canonicalize(&path).unwrap_or_else(|_| path.clone());
        let read = |filename: &str| {
            let file = mesh_file(&canonical, filename).ok()?;
            file.exists().then(|| std::fs::read(&file).map_err(|e| format!("{}: {e}", file.display())))
        };
        let mut input = RobotInput::urdf(text, &reach::model::UrdfChain { base, tip }, read).map_err(value_err)?;
        if let (Some(srdf), RobotInput::Urdf { srdf: s, .. }) = (srdf, &mut input) {
            *s = Some(
                std::fs::read_to_string(&srdf)
                    .map_err(|e| PyOSError::new_err(format!("cannot read SRDF file `{}`: {e}", srdf.display())))?,
            );
        }
        Ok(Robot { urdf_file: Some(canonical), ..Robot::from_input(input)? })
    }

    /// A robot from the text of a TOML description.
    #[staticmethod]
    fn from_toml(text: String) -> PyResult<Self> {
        Robot::from_input(RobotInput::Toml { text })
    }

    /// A robot from a DH table: rows `(n, 4)` `[a, alpha, d, offset]` or `(n, 6)` with
    /// `[lower, upper]` limits; metres and radians (degrees for angles with `degrees=True`).
    /// Standard DH, modified (Craig) DH with `modified=True`; `prismatic` lists the 0-based
    /// indices of prismatic joints (their `d` is the offset of the joint variable, and their
    /// limits are metres).
    #[staticmethod]
    #[pyo3(signature = (rows, modified=false, degrees=false, prismatic=Vec::new(), name="dh".to_string()))]
    fn from_dh(
        py: Python<'_>,
        rows: &Bound<'_, PyAny>,
        modified: bool,
        degrees: bool,
        prismatic: Vec<usize>,
        name: String,
    ) -> PyResult<Self> {
        let (shape, mut data) = float_array(py, rows, "rows")?;
        let width = match shape.as_slice() {
            [n, w @ (4 | 6)] if *n > 0 => *w,
            _ => return Err(value_err(format!("rows: expected shape (n, 4) or (n, 6), got {}", tuple(&shape)))),
        };
        if degrees {
            // alpha and the θ offset are angles; limits are angles for revolute joints only.
            let angle = |row: usize, col: usize| col == 1 || col == 3 || (col >= 4 && !prismatic.contains(&row));
            for (k, v) in data.iter_mut().enumerate() {
                if angle(k / width, k % width) {
                    *v = to_si(JointKind::Revolute, *v, AngleUnit::Deg);
                }
            }
        }
        Robot::dh(&data, width, &prismatic, modified, &name)
    }

    /// Rebuilds a robot from [`Robot::__reduce__`]'s state (and the URDF file its views
    /// draw the meshes of).
    #[staticmethod]
    #[pyo3(signature = (state, urdf_file=None))]
    fn _restore(state: &str, urdf_file: Option<std::path::PathBuf>) -> PyResult<Self> {
        let robot = match serde_json::from_str::<State>(state)
            .map_err(|e| value_err(format!("not a reach.Robot state: {e}")))?
        {
            State::Input(input) => Robot::from_input(input),
            State::Dh(d) => Robot::dh(&d.rows, d.width, &d.prismatic, d.modified, &d.name),
        }?;
        Ok(Robot { urdf_file, ..robot })
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let restore = slf.get_type().getattr("_restore")?;
        let this = slf.get();
        let args = (this.state.clone(), this.urdf_file.clone()).into_pyobject(slf.py())?;
        Ok((restore, args))
    }

    /// `Robot(name='ur5', dof=6, joints='RRRRRR', limits_deg=[±360, …], solver='…')`: the
    /// joint kinds (`R` revolute, `P` prismatic), each joint's limits (revolute degrees,
    /// prismatic metres; `±a` when symmetric, `free` for a continuous joint) and the IK solver
    /// picked for it.
    fn __repr__(&self) -> String {
        let joints = self.robot.joints();
        let kinds: String = joints.iter().map(|j| if j.kind == JointKind::Prismatic { 'P' } else { 'R' }).collect();
        let number = |v: f64| {
            let text = format!("{v:.3}");
            let text = text.trim_end_matches('0').trim_end_matches('.');
            if text == "-0" { "0".to_string() } else { text.to_string() }
        };
        let limits: Vec<String> = joints
            .iter()
            .map(|j| {
                let (lo, hi) =
                    (from_si(j.kind, j.limits.lower, AngleUnit::Deg), from_si(j.kind, j.limits.upper, AngleUnit::Deg));
                if !lo.is_finite() && !hi.is_finite() {
                    "free".to_string()
                } else if lo == -hi {
                    format!("±{}", number(hi))
                } else {
                    format!("{}..{}", number(lo), number(hi))
                }
            })
            .collect();
        format!(
            "Robot(name='{}', dof={}, joints='{kinds}', limits_deg=[{}], solver='{}')",
            self.robot.name().replace('\\', "\\\\").replace('\'', "\\'"),
            self.robot.dof(),
            limits.join(", "),
            SolverKind::detect(&self.robot).as_str()
        )
    }

    /// The robot in the 3-D viewer (`reach view`'s page, offline), in an `<iframe srcdoc>` for
    /// a notebook: at home.
    fn _repr_html_(&self) -> PyResult<String> {
        self.view_html(None, true, true)
    }

    /// `reach view`'s offline page of a view request (the JSON text of a
    /// `reach::jobs::ViewRequest`; `None`: the robot at home), in an `<iframe srcdoc>` for a
    /// notebook when `frame`; a robot read from a URDF file drawn with its visual meshes
    /// unless `meshes=False`.
    #[pyo3(signature = (request=None, frame=true, meshes=true))]
    fn _view_html(&self, request: Option<&str>, frame: bool, meshes: bool) -> PyResult<String> {
        self.view_html(request, frame, meshes)
    }

    /// A view of the robot (`reach view`): at `q` (SI, or degrees with `degrees=True`;
    /// default home) among the obstacles of `scene` (a `reach.Scene`, a path, or the text of a
    /// scene file). The result shows itself in a notebook (`_repr_html_`); `.html` is the
    /// full page, `.save(path)` writes it. A robot read from a URDF file is drawn with its
    /// visual meshes (read from disk when shown) unless `meshes=False`.
    #[pyo3(signature = (q=None, scene=None, degrees=false, meshes=true))]
    fn view<'py>(
        slf: &Bound<'py, Self>,
        q: Option<&Bound<'py, PyAny>>,
        scene: Option<&Bound<'py, PyAny>>,
        degrees: bool,
        meshes: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let py = slf.py();
        let this = slf.get();
        let mut request = ViewRequest::default();
        if let Some(q) = q {
            let (n, q) = this.joint_rows(py, q, "q", degrees)?;
            if n.is_some() {
                return Err(value_err(format!("q: expected shape ({},)", this.robot.dof())));
            }
            request.q = Some(Joints::Rad(q));
        }
        if let Some(scene) = scene {
            request.scene = Some(py.import("reach._convert")?.call_method1("scene_text", (scene,))?.extract()?);
        }
        let request = serde_json::to_string(&request).map_err(|e| value_err(e.to_string()))?;
        py.import("reach._results")?.getattr("View")?.call1((slf, request, meshes))
    }

    /// The robot's name.
    #[getter]
    fn name(&self) -> &str {
        self.robot.name()
    }

    /// Number of joints.
    #[getter]
    fn dof(&self) -> usize {
        self.robot.dof()
    }

    /// Joint names, base to tip.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.robot.joints().iter().map(|j| j.name.clone()).collect()
    }

    /// Joint kinds, `"revolute"` or `"prismatic"`.
    #[getter]
    fn joint_kinds(&self) -> Vec<&'static str> {
        self.robot.joints().iter().map(|j| j.kind.as_str()).collect()
    }

    /// Joint limits `(dof, 2)`: radians / metres (degrees for revolute joints with
    /// `degrees=True`); ±inf for a continuous joint.
    #[pyo3(signature = (degrees=false))]
    fn limits<'py>(&self, py: Python<'py>, degrees: bool) -> PyResult<Bound<'py, PyAny>> {
        let joints = self.robot.joints();
        let mut data = Vec::with_capacity(2 * joints.len());
        for j in joints {
            for v in [j.limits.lower, j.limits.upper] {
                data.push(if degrees { from_si(j.kind, v, AngleUnit::Deg) } else { v });
            }
        }
        to_numpy(py, data, vec![joints.len(), 2])
    }

    /// Joint limits as the Robotics Toolbox's `qlim`: `(2, dof)`, lower bounds then upper,
    /// radians / metres.
    #[getter]
    fn qlim<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let joints = self.robot.joints();
        let data = joints.iter().map(|j| j.limits.lower).chain(joints.iter().map(|j| j.limits.upper)).collect();
        to_numpy(py, data, vec![2, joints.len()])
    }

    /// The home configuration `(dof,)` (SI, or degrees with `degrees=True`).
    #[pyo3(signature = (degrees=false))]
    fn home<'py>(&self, py: Python<'py>, degrees: bool) -> PyResult<Bound<'py, PyAny>> {
        to_numpy(py, self.display(self.robot.home(), degrees), vec![self.robot.dof()])
    }

    /// Forward kinematics: `q` `(dof,)` → `(4, 4)`, `(N, dof)` → `(N, 4, 4)`.
    #[pyo3(signature = (q, degrees=false))]
    fn fk<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>, degrees: bool) -> PyResult<Bound<'py, PyAny>> {
        let (n, q) = self.joint_rows(py, q, "q", degrees)?;
        let robot = &self.robot;
        let t = py.detach(|| reach::batch::fk_many(robot, &q)).map_err(|e| lib_err(&e))?;
        to_numpy(py, t, n.map_or(vec![4, 4], |n| vec![n, 4, 4]))
    }

    /// Geometric Jacobian (world frame, rows vx vy vz wx wy wz): `(dof,)` → `(6, dof)`,
    /// `(N, dof)` → `(N, 6, dof)`.
    #[pyo3(signature = (q, degrees=false))]
    fn jacobian<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>, degrees: bool) -> PyResult<Bound<'py, PyAny>> {
        let (n, q) = self.joint_rows(py, q, "q", degrees)?;
        let robot = &self.robot;
        let dof = robot.dof();
        let j = py.detach(|| reach::batch::jacobian_many(robot, &q)).map_err(|e| lib_err(&e))?;
        to_numpy(py, j, n.map_or(vec![6, dof], |n| vec![n, 6, dof]))
    }

    /// Inverse dynamics (recursive Newton–Euler, the robot's gravity): joint torques/forces
    /// `τ = M(q)·q̈ + C(q, q̇)·q̇ + g(q)` (N·m revolute, N prismatic) for `q`, `qd`, `qdd`
    /// (SI: rad or m, per second, per second squared), each `(dof,)` → `(dof,)` or
    /// `(N, dof)` → `(N, dof)`, all of one shape; `qd` / `qdd` default to zeros.
    #[pyo3(signature = (q, qd=None, qdd=None))]
    fn rne<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qd: Option<&Bound<'py, PyAny>>,
        qdd: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (n, q) = self.joint_rows(py, q, "q", false)?;
        let rates = |name: &str, v: Option<&Bound<'py, PyAny>>| -> PyResult<Option<Vec<f64>>> {
            let Some(v) = v else { return Ok(None) };
            let (m, v) = self.joint_rows(py, v, name, false)?;
            if m != n {
                return Err(value_err(format!(
                    "{name}: expected the shape of q ({}), got {}",
                    tuple(&n.map_or(vec![self.robot.dof()], |n| vec![n, self.robot.dof()])),
                    tuple(&m.map_or(vec![self.robot.dof()], |m| vec![m, self.robot.dof()]))
                )));
            }
            Ok(Some(v))
        };
        let (qd, qdd) = (rates("qd", qd)?, rates("qdd", qdd)?);
        let robot = &self.robot;
        let tau = py
            .detach(|| reach::batch::inverse_dynamics_many(robot, &q, qd.as_deref(), qdd.as_deref()))
            .map_err(|e| lib_err(&e))?;
        to_numpy(py, tau, n.map_or(vec![robot.dof()], |n| vec![n, robot.dof()]))
    }

    /// Gravity load `g(q)`: the joint torques/forces (N·m, N) that hold the arm still at `q`
    /// (SI), `(dof,)` → `(dof,)` or `(N, dof)` → `(N, dof)`.
    fn gravload<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        self.rne(py, q, None, None)
    }

    /// Joint-space mass (inertia) matrix `M(q)` (kg·m², kg·m, kg by joint kinds) at `q` (SI):
    /// `(dof,)` → `(dof, dof)`, `(N, dof)` → `(N, dof, dof)`; symmetric.
    fn inertia<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let (n, q) = self.joint_rows(py, q, "q", false)?;
        let robot = &self.robot;
        let dof = robot.dof();
        let m = py.detach(|| reach::batch::mass_matrix_many(robot, &q)).map_err(|e| lib_err(&e))?;
        to_numpy(py, m, n.map_or(vec![dof, dof], |n| vec![n, dof, dof]))
    }

    /// Inverse kinematics of one pose `T` (4×4): the `reach ik --json` report as a dict, plus
    /// `q` `(k, dof)` (SI, or degrees with `degrees=True`) of its `solutions`, `branch`,
    /// `position_error`, `orientation_error` and `within_limits` per solution.
    #[pyo3(signature = (
        T, all=true, degrees=false, q0=None, solver=None, choose=None, criteria=None, weights=None,
        joint_weights=None, restarts=None, max_iterations=None, time_budget_s=None
    ))]
    #[allow(non_snake_case, clippy::too_many_arguments, reason = "Python keyword arguments")]
    fn ik<'py>(
        &self,
        py: Python<'py>,
        T: &Bound<'py, PyAny>,
        all: bool,
        degrees: bool,
        q0: Option<&Bound<'py, PyAny>>,
        solver: Option<&str>,
        choose: Option<&str>,
        criteria: Option<Vec<String>>,
        weights: Option<Vec<f64>>,
        joint_weights: Option<Vec<f64>>,
        restarts: Option<usize>,
        max_iterations: Option<usize>,
        time_budget_s: Option<f64>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (shape, t) = float_array(py, T, "T")?;
        if batch_shape("T", &shape, &[4, 4])?.is_some() {
            return Err(value_err(format!("T: expected shape (4, 4) (use ik_all for a batch), got {}", tuple(&shape))));
        }
        let mut request = serde_json::json!({
            "target": {"matrix": [&t[0..4], &t[4..8], &t[8..12], &t[12..16]]},
            "all": all,
            "numeric": {"restarts": restarts, "max_iterations": max_iterations, "time_budget_s": time_budget_s},
        });
        if let Some(q0) = q0 {
            let (n, q) = self.joint_rows(py, q0, "q0", false)?;
            if n.is_some() {
                return Err(value_err(format!("q0: expected shape ({},)", self.robot.dof())));
            }
            request["from"] = if degrees { serde_json::json!({"deg": q}) } else { serde_json::json!({"rad": q}) };
        }
        if let Some(s) = solver {
            request["solver"] = s.into();
        }
        if let Some(w) = joint_weights {
            request["joint_weights"] = w.into();
        }
        if choose.is_some() || criteria.is_some() || weights.is_some() {
            let mut c = serde_json::json!({"method": choose.unwrap_or("topsis")});
            if let Some(k) = criteria {
                c["criteria"] = k.into();
            }
            if let Some(w) = weights {
                c["weights"] = w.into();
            }
            request["choose"] = c;
        }
        strip_nulls(&mut request);
        let request: IkRequest =
            serde_json::from_value(request).map_err(|e| value_err(reach::one_line(&e.to_string())))?;
        let robot = &self.robot;
        let report = py.detach(|| jobs::ik::ik(robot, &request)).map_err(|e| lib_err(&e))?;
        let dof = robot.dof();
        let mut q = Vec::with_capacity(report.solutions.len() * dof);
        for s in &report.solutions {
            let si = Joints::Deg(s.q_deg.clone()).si(robot, "q_deg").map_err(|e| lib_err(&e))?;
            q.extend(self.display(si, degrees));
        }
        let k = report.solutions.len();
        let out = to_python(py, &report)?;
        let dict = out.cast::<PyDict>()?;
        dict.set_item("q", to_numpy(py, q, vec![k, dof])?)?;
        dict.set_item("branch", report.solutions.iter().map(|s| s.branch.clone()).collect::<Vec<_>>())?;
        dict.set_item(
            "position_error",
            to_numpy(py, report.solutions.iter().map(|s| s.position_error_m).collect(), vec![k])?,
        )?;
        dict.set_item(
            "orientation_error",
            to_numpy(py, report.solutions.iter().map(|s| s.orientation_error_rad).collect(), vec![k])?,
        )?;
        dict.set_item(
            "within_limits",
            to_numpy_bool(py, report.solutions.iter().map(|s| s.within_limits).collect(), vec![k])?,
        )?;
        Ok(out)
    }

    /// Every IK solution of each pose of `T` `(N, 4, 4)` (or one `(4, 4)`), on all cores: a
    /// dict of `q` `(N, kmax, dof)` NaN-padded, `valid` `(N, kmax)`, `within_limits`,
    /// `position_error`, `orientation_error`, `singular` `(N, kmax)`, `count` `(N,)`,
    /// `status` (N codes), `branch` (N lists of labels), `branch_index` `(N, kmax)` (index
    /// into `labels`, -1 in padding), `labels` (the distinct labels) and `solver`.
    ///
    /// `seeds` `(dof,)` or `(N, dof)`: the numeric solver's first start per pose (and the
    /// angle kept at a wrist singularity). Numeric solver: `restarts`, `max_iterations`,
    /// `time_budget_s` (per pose), `mask` = `"pose"` (6 equations), `"position_approach"`
    /// (tool z axis free to roll) or `"position"`.
    #[pyo3(signature = (
        T, solver=None, seeds=None, degrees=false, mask="pose", restarts=None, max_iterations=None,
        time_budget_s=None, position_tolerance_m=None, orientation_tolerance_rad=None
    ))]
    #[allow(non_snake_case, clippy::too_many_arguments, reason = "Python keyword arguments")]
    fn ik_all<'py>(
        &self,
        py: Python<'py>,
        T: &Bound<'py, PyAny>,
        solver: Option<&str>,
        seeds: Option<&Bound<'py, PyAny>>,
        degrees: bool,
        mask: &str,
        restarts: Option<usize>,
        max_iterations: Option<usize>,
        time_budget_s: Option<f64>,
        position_tolerance_m: Option<f64>,
        orientation_tolerance_rad: Option<f64>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (shape, t) = float_array(py, T, "T")?;
        let single = batch_shape("T", &shape, &[4, 4])?.is_none();
        let kind = match solver {
            None => None,
            Some(name) => Some(SolverKind::parse(name).ok_or_else(|| {
                let known: Vec<&str> = SolverKind::ALL.iter().map(|k| k.as_str()).collect();
                value_err(format!("solver: unknown solver `{name}` (known: {})", known.join(", ")))
            })?),
        };
        let axes = match mask {
            "pose" => TaskAxes::Pose,
            "position_approach" => TaskAxes::PositionApproach,
            "position" => TaskAxes::Position,
            other => {
                return Err(value_err(format!(
                    "mask: expected \"pose\", \"position_approach\" or \"position\", got `{other}`"
                )));
            }
        };
        let mut request = IkRequest::new(Pose::default());
        request.numeric = jobs::ik::IkNumericRequest {
            restarts,
            max_iterations,
            time_budget_s,
            position_tolerance_m,
            orientation_tolerance_rad,
        };
        let robot = &self.robot;
        let dof = robot.dof();
        let mut options: IkOptions = jobs::ik::solver_options(&request, &robot.home()).map_err(|e| lib_err(&e))?;
        options.numeric.axes = axes;
        let seeds = match seeds {
            None => None,
            Some(s) => {
                let (n, rows) = self.joint_rows(py, s, "seeds", degrees)?;
                match n {
                    None => {
                        options.seed = Some(rows);
                        None
                    }
                    Some(_) => Some(rows),
                }
            }
        };
        let all = py
            .detach(|| reach::batch::ik_many(robot, kind, &t, seeds.as_deref(), &options))
            .map_err(|e| lib_err(&e))?;
        let (n, k) = (all.targets, all.kmax);
        let lead = |mut tail: Vec<usize>| {
            if !single {
                tail.insert(0, n);
            }
            tail
        };
        let out = PyDict::new(py);
        out.set_item("q", to_numpy(py, self.display(all.q, degrees), lead(vec![k, dof]))?)?;
        out.set_item("valid", to_numpy_bool(py, all.valid, lead(vec![k]))?)?;
        out.set_item("within_limits", to_numpy_bool(py, all.within_limits, lead(vec![k]))?)?;
        out.set_item("position_error", to_numpy(py, all.position_error, lead(vec![k]))?)?;
        out.set_item("orientation_error", to_numpy(py, all.orientation_error, lead(vec![k]))?)?;
        out.set_item("singular", to_numpy_bool(py, all.singular, lead(vec![k]))?)?;
        let count: Vec<f64> = all.count.iter().map(|&c| c as f64).collect();
        out.set_item(
            "count",
            py.import("numpy")?.call_method1("asarray", (to_numpy(py, count, lead(vec![]))?, "int64"))?,
        )?;
        // Each distinct label and status is one Python string, shared by the rows.
        let labels: Vec<Bound<'py, PyString>> = all.labels.iter().map(|l| PyString::new(py, l)).collect();
        let row_labels = |i: usize| {
            let idx = &all.branch[i * k..i * k + all.count[i]];
            PyList::new(py, idx.iter().map(|&j| labels[j as usize].clone()))
        };
        let index: Vec<f64> = all
            .branch
            .iter()
            .map(|&j| if j == reach::batch::IkBatch::NO_LABEL { -1.0 } else { f64::from(j) })
            .collect();
        let np = py.import("numpy")?;
        out.set_item("branch_index", np.call_method1("asarray", (to_numpy(py, index, lead(vec![k]))?, "int64"))?)?;
        out.set_item("labels", &labels)?;
        if single {
            out.set_item("status", all.status[0])?;
            out.set_item("branch", row_labels(0)?)?;
        } else {
            let mut statuses: HashMap<&str, Bound<'py, PyString>> = HashMap::new();
            let status = PyList::empty(py);
            for s in &all.status {
                status.append(statuses.entry(s).or_insert_with(|| PyString::new(py, s)).clone())?;
            }
            let branch = PyList::empty(py);
            for i in 0..n {
                branch.append(row_labels(i)?)?;
            }
            out.set_item("status", status)?;
            out.set_item("branch", branch)?;
        }
        out.set_item("solver", all.solver)?;
        Ok(out.into_any())
    }

    /// One motion (`reach move --json`): the `move` request's fields as keyword arguments or a
    /// dict (`from`, `to`, `space`, `duration_s`, `scene`, …); the report as a `reach.Motion`
    /// (a dict): the CLI's report with its samples as arrays `t` `(M,)` s, `q`, `qd`, `qdd`
    /// `(M, dof)` and the tool's `tool_xyz` (m), `tool_rpy` (rad) `(M, 3)`. SI (rad, m, per
    /// second, per second squared) even when the request gives degrees; degrees (prismatic
    /// joints metres) with `degrees=True`. `qdd` is the library's rate rule on `q`
    /// (`reach::effort::dynamics::joint_rates`); `qd` is the planner's.
    #[pyo3(name = "move", signature = (request=None, degrees=false, **kwargs))]
    fn move_<'py>(
        slf: &Bound<'py, Self>,
        request: Option<&Bound<'py, PyAny>>,
        degrees: bool,
        kwargs: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        Robot::workflow(slf, "move", request, kwargs, &[], degrees)
    }

    /// A tool-space motion tracked through IK (`reach move --space tool --json`): `move` with
    /// `space="tool"` unless given; the result as `move`'s.
    #[pyo3(signature = (request=None, degrees=false, **kwargs))]
    fn track<'py>(
        slf: &Bound<'py, Self>,
        request: Option<&Bound<'py, PyAny>>,
        degrees: bool,
        kwargs: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        Robot::workflow(slf, "move", request, kwargs, &[("space", "tool")], degrees)
    }

    /// Every motion of a task file (`reach plan --json`): `task` (the file's text), `scene`;
    /// a `reach.Motion` whose `motions` are dicts with arrays as `move`'s (SI unless
    /// `degrees=True`).
    #[pyo3(signature = (request=None, degrees=false, **kwargs))]
    fn plan<'py>(
        slf: &Bound<'py, Self>,
        request: Option<&Bound<'py, PyAny>>,
        degrees: bool,
        kwargs: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        Robot::workflow(slf, "plan", request, kwargs, &[], degrees)
    }

    /// Seed 000's planar detour around point obstacles (`reach avoid --json`).
    #[pyo3(signature = (request=None, **kwargs))]
    fn avoid<'py>(
        slf: &Bound<'py, Self>,
        request: Option<&Bound<'py, PyAny>>,
        kwargs: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        Robot::workflow(slf, "avoid", request, kwargs, &[], false)
    }

    /// Seed 004's configuration-space grid (`reach cspace --json`).
    #[pyo3(signature = (request=None, **kwargs))]
    fn cspace<'py>(
        slf: &Bound<'py, Self>,
        request: Option<&Bound<'py, PyAny>>,
        kwargs: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        Robot::workflow(slf, "cspace", request, kwargs, &[], false)
    }

    /// Stepper step schedules for a motion (`reach drive --json`).
    #[pyo3(signature = (request=None, **kwargs))]
    fn drive<'py>(
        slf: &Bound<'py, Self>,
        request: Option<&Bound<'py, PyAny>>,
        kwargs: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        Robot::workflow(slf, "drive", request, kwargs, &[], false)
    }

    /// A collision-free timed joint-space path through a scene (`reach path --json`): when a
    /// path is found, a `reach.Motion` with the timed path's samples as arrays `t`, `q`,
    /// `qd`, `qdd` and `tool_xyz` (SI unless `degrees=True`, as `move`'s); else the report.
    #[pyo3(signature = (request=None, degrees=false, **kwargs))]
    fn path<'py>(
        slf: &Bound<'py, Self>,
        request: Option<&Bound<'py, PyAny>>,
        degrees: bool,
        kwargs: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        Robot::workflow(slf, "path", request, kwargs, &[], degrees)
    }

    /// The time-optimal motion through joint waypoints `(N, dof)` (SI, or degrees with
    /// `degrees=True`) under the robot's velocity and acceleration limits, proven within them
    /// between samples (`reach retime --json`, TOPP-RA): a dict with `duration_s`, the limits,
    /// `worst_velocity_ratio` / `worst_acceleration_ratio` per joint, and the samples as
    /// arrays `t` `(M,)`, `q`, `qd`, `qdd` `(M, dof)` in SI. Keywords as the request:
    /// `interpolation` (`"spline"`, default, or `"linear"`), `dt`, `max_velocity_scale`,
    /// `max_acceleration_scale`, `points_per_piece`.
    ///
    /// `degrees=True` reads the waypoints in degrees (prismatic joints in metres); the arrays
    /// stay SI unless `degrees_out=True`.
    #[pyo3(signature = (waypoints, degrees=false, degrees_out=false, **kwargs))]
    fn time_parameterize<'py>(
        &self,
        py: Python<'py>,
        waypoints: &Bound<'py, PyAny>,
        degrees: bool,
        degrees_out: bool,
        kwargs: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (n, q) = self.joint_rows(py, waypoints, "waypoints", degrees)?;
        if n.is_none() {
            return Err(value_err("waypoints: expected shape (N, dof) with N ≥ 2, got one joint vector"));
        }
        let options: serde_json::Value = match kwargs {
            Some(k) => serde_json::from_str(
                &py.import("reach._convert")?.call_method1("request_json", (k,))?.extract::<String>()?,
            )
            .map_err(|e| value_err(e.to_string()))?,
            None => serde_json::json!({}),
        };
        let mut request = options;
        let rows: Vec<Joints> = q.chunks(self.robot.dof()).map(|r| Joints::Rad(r.to_vec())).collect();
        request["waypoints"] = serde_json::to_value(rows).map_err(|e| value_err(e.to_string()))?;
        let request: reach::jobs::retime::RetimeRequest = serde_json::from_value(request)
            .map_err(|e| value_err(format!("time_parameterize: {}", reach::one_line(&e.to_string()))))?;
        let robot = &self.robot;
        let mut report = py.detach(|| reach::jobs::retime::retime(robot, &request)).map_err(|e| lib_err(&e))?;
        let samples = std::mem::take(&mut report.samples);
        let dict = to_python(py, &report)?.cast_into::<PyDict>()?;
        dict.del_item("samples")?;
        let t = samples.iter().map(|s| s.t_s).collect();
        let column =
            |f: &dyn Fn(&reach::jobs::retime::RetimeSample) -> &Vec<f64>| samples.iter().map(f).cloned().collect();
        let (q, qd, qdd) = (column(&|s| &s.q), column(&|s| &s.qd), column(&|s| &s.qdd));
        self.set_trajectory(py, &dict, t, q, qd, Some(qdd), degrees_out)?;
        Ok(dict.into_any())
    }

    /// Collisions and clearances of one configuration in a scene (`reach check --json`), with
    /// a flat verdict: `verdict` the outcome's name (`free`, `obstacle`, `self_collision`,
    /// `outside_zone`), its fields beside it (`verdict_link`, `verdict_obstacle`, …) and
    /// `clear`, whether the whole check (the configuration and its motion, when given) holds.
    #[pyo3(signature = (request=None, degrees=false, **kwargs))]
    fn check<'py>(
        slf: &Bound<'py, Self>,
        request: Option<&Bound<'py, PyAny>>,
        degrees: bool,
        kwargs: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        Robot::workflow(slf, "check", request, kwargs, &[], degrees)
    }

    /// Runs any workflow: `request` is a dict (or JSON text) of a `reach::jobs::Request`, with
    /// its `"kind"` (`fk`, `ik`, `move`, `plan`, `avoid`, `cspace`, `drive`, …); returns the
    /// report (the CLI's `--json` output) as a dict, numeric lists as numpy arrays, motions and
    /// checks as the workflow methods return them.
    #[pyo3(signature = (request, degrees=false))]
    fn run<'py>(slf: &Bound<'py, Self>, request: &Bound<'py, PyAny>, degrees: bool) -> PyResult<Bound<'py, PyAny>> {
        let py = slf.py();
        let text: String = if let Ok(s) = request.extract::<String>() {
            s
        } else {
            py.import("reach._convert")?.call_method1("request_json", (request,))?.extract()?
        };
        let request: Request = serde_json::from_str(&text)
            .map_err(|e| value_err(format!("request: {}", reach::one_line(&e.to_string()))))?;
        Robot::run_request(slf, py, &request, degrees)
    }
}

/// Removes `null` members of objects (optional request fields left out).
fn strip_nulls(v: &mut serde_json::Value) {
    match v {
        serde_json::Value::Object(map) => {
            map.retain(|_, x| !x.is_null());
            map.values_mut().for_each(strip_nulls);
        }
        serde_json::Value::Array(items) => items.iter_mut().for_each(strip_nulls),
        _ => {}
    }
}

/// What a scene file holds (`reach.Scene` validates and describes itself with it): the
/// scene parsed by the library (`reach::jobs::world::parse_scene`, its errors name the entry
/// and field), as a dict of `obstacles` and `tool_zone` (lists of names), `moving` (names of
/// the obstacles with a velocity) and, for a TOML scene, its `length_unit` and `angle_unit`
/// (`None` for a MoveIt planning scene).
#[pyfunction]
fn _scene_info<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyDict>> {
    let scene = jobs::world::parse_scene(text).map_err(|e| lib_err(&e))?;
    let out = PyDict::new(py);
    let names = |list: &[reach::world::Obstacle]| list.iter().map(|o| o.name.clone()).collect::<Vec<_>>();
    out.set_item("obstacles", names(&scene.obstacles))?;
    out.set_item("tool_zone", names(&scene.tool_zone))?;
    out.set_item("moving", scene.obstacles.iter().filter(|o| o.moves()).map(|o| o.name.clone()).collect::<Vec<_>>())?;
    let (mut length, mut angle) = (None, None);
    if !jobs::world::is_moveit_scene(text) {
        // The library read the file: its units are strings it accepted ("m"/"mm",
        // "deg"/"rad", angles in degrees by default).
        let table: toml::Table = text.parse().map_err(|e: toml::de::Error| value_err(e.to_string()))?;
        length = table.get("length_unit").and_then(|v| v.as_str()).map(str::to_string);
        angle = Some(table.get("angle_unit").and_then(|v| v.as_str()).unwrap_or("deg").to_string());
    }
    out.set_item("length_unit", length)?;
    out.set_item("angle_unit", angle)?;
    Ok(out)
}

/// The extension module.
#[pymodule]
fn _reach(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Robot>()?;
    m.add_function(wrap_pyfunction!(_scene_info, m)?)?;
    m.add("ReachError", m.py().get_type::<ReachError>())?;
    m.add("MAX_BATCH", reach::batch::MAX_BATCH)?;
    Ok(())
}
