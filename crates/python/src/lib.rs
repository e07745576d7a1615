//! The native module `wornjoint._native`: scenes as dicts, runs, and sweep tasks for the
//! `wornjoint` Python package (its `__init__.py` wraps these in a friendlier API).
//!
//! Every run goes through the same code as `wearsim run` ([`scene::from_table`],
//! [`sim::overrides::RunOverrides`], [`sim::run_scene`]), so its numbers equal the
//! command line's bit for bit; runs release the GIL. Bad input raises `SceneError` (a
//! `ValueError`) naming the field, a failed run `RunError`, a bad sweep file `SweepError` (a
//! `ValueError`); an internal panic is caught and raised as `RunError`, never a crash.
//!
//! Built by `pip install ./crates/python` (maturin); used through the package:
//!
//! ```python
//! import wornjoint
//! scene = wornjoint.load("lgres")
//! scene["clearance_joints"][0]["clearance"] = 3e-4
//! r = wornjoint.run(scene, cycles=1, stages=0)
//! print(r.summary["response"]["dissipated_per_cycle_j"], r.contact["A_Fn"].max())
//! ```

use std::collections::BTreeMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;

use numpy::{PyArray1, PyArray2};
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use sim::overrides::RunOverrides;
use sim::{Response, RunOutcome};
use sweep::{LocalOptions, Row, Sweep};

create_exception!(
    _native,
    SceneError,
    PyValueError,
    "A scene is invalid; the message names the field."
);
create_exception!(
    _native,
    RunError,
    PyRuntimeError,
    "A run failed (integrator, budget, contact outside its validity)."
);
create_exception!(
    _native,
    SweepError,
    PyValueError,
    "A sweep file is invalid (the message names the field) or its outputs cannot be written."
);

fn scene_err(e: impl std::fmt::Display) -> PyErr {
    SceneError::new_err(e.to_string())
}

fn sweep_err(e: &sweep::SweepError) -> PyErr {
    if e.is_bad_input() {
        SweepError::new_err(e.to_string())
    } else {
        PyRuntimeError::new_err(e.to_string())
    }
}

/// The text of a panic payload.
fn panic_text(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<&str>()
        .map(ToString::to_string)
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown".into())
}

/// Built-in scenes: name → one-line summary.
#[pyfunction]
fn scenes() -> BTreeMap<&'static str, &'static str> {
    lgres::scenes::BUILTINS
        .iter()
        .map(|b| (b.name, b.summary))
        .collect()
}

/// A built-in name or a file path → (name outputs are filed under, merged table). Neither
/// raises the unknown-built-in error, which lists the known names.
fn load_table(spec: &str) -> Result<(String, toml::Table), scene::SceneError> {
    scene::load_named(spec, None, lgres::scenes::BUILTINS).map_err(|e| match e {
        scene::LoadError::NotFound(e) => e.into_unknown_builtin(),
        scene::LoadError::Scene(e) => e,
    })
}

fn toml_to_py<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        toml::Value::String(s) => PyString::new(py, s).into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(f) => PyFloat::new(py, *f).into_any(),
        toml::Value::Boolean(b) => PyBool::new(py, *b).to_owned().into_any(),
        toml::Value::Datetime(d) => PyString::new(py, &d.to_string()).into_any(),
        toml::Value::Array(a) => {
            let items = a
                .iter()
                .map(|x| toml_to_py(py, x))
                .collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any()
        }
        toml::Value::Table(t) => table_to_py(py, t)?.into_any(),
    })
}

fn table_to_py<'py>(py: Python<'py>, t: &toml::Table) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (k, v) in t {
        d.set_item(k, toml_to_py(py, v)?)?;
    }
    Ok(d)
}

/// A Python value as TOML; `path` names it in errors.
fn py_to_toml(v: &Bound<'_, PyAny>, path: &str) -> PyResult<toml::Value> {
    let unsupported = || {
        let ty = v
            .get_type()
            .name()
            .map_or_else(|_| "?".to_string(), |n| n.to_string());
        scene_err(format!(
            "in scene: {path}: a value of type {ty} cannot be a scene value (use str, int, \
             float, bool, list or dict)"
        ))
    };
    if v.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(v.extract()?));
    }
    if v.is_instance_of::<PyInt>() {
        return v
            .extract::<i64>()
            .map(toml::Value::Integer)
            .map_err(|_| scene_err(format!("in scene: {path}: integer out of range")));
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(v.extract()?));
    }
    if let Ok(s) = v.cast::<PyString>() {
        return Ok(toml::Value::String(s.extract()?));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        return Ok(toml::Value::Table(dict_to_table(d, path)?));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let mut items = Vec::new();
        for (k, x) in v.try_iter()?.enumerate() {
            items.push(py_to_toml(&x?, &format!("{path}[{k}]"))?);
        }
        return Ok(toml::Value::Array(items));
    }
    // NumPy scalars and other numbers: an integer if it is one, else a float.
    if v.hasattr("__index__")?
        && let Ok(i) = v.call_method0("__index__").and_then(|i| i.extract::<i64>())
    {
        return Ok(toml::Value::Integer(i));
    }
    if v.hasattr("__float__")?
        && let Ok(f) = v.call_method0("__float__").and_then(|f| f.extract::<f64>())
    {
        return Ok(toml::Value::Float(f));
    }
    Err(unsupported())
}

fn dict_to_table(d: &Bound<'_, PyDict>, path: &str) -> PyResult<toml::Table> {
    let mut t = toml::Table::new();
    for (k, v) in d.iter() {
        let key: String = k
            .extract()
            .map_err(|_| scene_err(format!("in scene: {path}: keys must be strings")))?;
        let here = if path.is_empty() {
            key.clone()
        } else {
            format!("{path}.{key}")
        };
        t.insert(key, py_to_toml(&v, &here)?);
    }
    Ok(t)
}

/// Load a scene (built-in name or TOML file) as `(name, dict)`: the file's values with its
/// `extends` chain merged in, defaults not filled in.
#[pyfunction]
fn load<'py>(py: Python<'py>, spec: &str) -> PyResult<(String, Bound<'py, PyDict>)> {
    let (name, table) = load_table(spec).map_err(scene_err)?;
    // Parse and validate now, so a bad file fails at load.
    scene::from_table(table.clone(), &name).map_err(scene_err)?;
    Ok((name, table_to_py(py, &table)?))
}

/// Validate a scene dict; raises `SceneError` naming the field.
#[pyfunction]
fn check(scene: &Bound<'_, PyDict>, name: &str) -> PyResult<()> {
    let table = dict_to_table(scene, "")?;
    scene::from_table(table, name).map_err(scene_err)?;
    Ok(())
}

fn column<'py>(py: Python<'py>, v: &[f64]) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, v)
}

/// The columns of `response.csv` (without units) and of `contact.csv`, as arrays.
fn response_columns<'py>(
    py: Python<'py>,
    r: &Response,
) -> PyResult<(Bound<'py, PyList>, Bound<'py, PyList>)> {
    let motion = PyList::empty(py);
    motion.append(("t", column(py, &r.times)))?;
    let (sim, ideal) = (r.motion.series(), r.ideal.series());
    for (k, q) in ["x", "y", "vx", "vy", "ax", "ay"].iter().enumerate() {
        let dev: Vec<f64> = sim[k].iter().zip(ideal[k]).map(|(a, b)| a - b).collect();
        motion.append((*q, column(py, sim[k])))?;
        motion.append((format!("ideal_{q}"), column(py, ideal[k])))?;
        motion.append((format!("dev_{q}"), column(py, &dev)))?;
    }
    let contact = PyList::empty(py);
    if !r.contact.is_empty() {
        contact.append(("t", column(py, &r.times)))?;
    }
    for c in &r.contact {
        let data: [(&str, &[f64]); 8] = [
            ("Fn", &c.normal_force),
            ("Ft", &c.friction_force),
            ("delta", &c.penetration),
            ("e", &c.eccentricity),
            ("ex", &c.ex),
            ("ey", &c.ey),
            ("ex_bearing", &c.ex_bearing),
            ("ey_bearing", &c.ey_bearing),
        ];
        for (q, v) in data {
            contact.append((format!("{}_{q}", c.name), column(py, v)))?;
        }
    }
    Ok((motion, contact))
}

/// A finished run kept on the Rust side, so its report is drawn only when asked for.
#[pyclass(frozen)]
struct Outcome(RunOutcome);

#[pymethods]
impl Outcome {
    /// The run's report as an HTML fragment (what a notebook displays), figures embedded.
    /// Releases the GIL while it draws.
    fn report_html(&self, py: Python<'_>) -> PyResult<String> {
        py.detach(|| output::artifacts::notebook_html(&self.0))
            .map_err(|e| RunError::new_err(e.to_string()))
    }
}

fn outcome_to_py<'py>(py: Python<'py>, o: RunOutcome) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    fill_outcome(&d, py, &o)?;
    d.set_item("outcome", Outcome(o))?;
    Ok(d)
}

fn fill_outcome(d: &Bound<'_, PyDict>, py: Python<'_>, o: &RunOutcome) -> PyResult<()> {
    let summary = serde_json::to_string_pretty(&o.summary)
        .map_err(|e| RunError::new_err(format!("summary: {e}")))?;
    d.set_item("summary_json", summary)?;
    d.set_item("scene_toml", o.scene.to_toml())?;
    let (motion, contact) = response_columns(py, &o.response)?;
    d.set_item("response", motion)?;
    d.set_item("contact", contact)?;
    if let Some(w) = &o.worn_response {
        let (motion, contact) = response_columns(py, w)?;
        d.set_item("worn_response", motion)?;
        d.set_item("worn_contact", contact)?;
    }
    let wear = PyDict::new(py);
    for joint in &o.wear {
        let j = PyDict::new(py);
        let cells = joint
            .stages
            .first()
            .map_or(0, |s| s.bearing().depth().len());
        let angle: Vec<f64> = (0..cells)
            .map(|c| sim::surfaces::cell_angle_deg(c, cells))
            .collect();
        j.set_item("angle_deg", column(py, &angle))?;
        let bearing: Vec<Vec<f64>> = joint
            .stages
            .iter()
            .map(|s| s.bearing().depth().to_vec())
            .collect();
        let pin: Vec<Vec<f64>> = joint
            .stages
            .iter()
            .map(|s| s.pin().depth().to_vec())
            .collect();
        let grid = |v: &[Vec<f64>]| {
            if v.is_empty() {
                Ok(PyArray2::<f64>::zeros(py, [0, cells], false))
            } else {
                PyArray2::from_vec2(py, v).map_err(|e| RunError::new_err(e.to_string()))
            }
        };
        j.set_item("bearing", grid(&bearing)?)?;
        j.set_item("pin", grid(&pin)?)?;
        j.set_item("bearing_radius", joint.bearing_radius)?;
        j.set_item("pin_radius", joint.pin_radius)?;
        wear.set_item(&joint.name, j)?;
    }
    d.set_item("wear", wear)?;
    // The life distribution as life_distribution.csv holds it (none without a limit reached).
    let life = PyList::empty(py);
    if let Some(lives) = o.summary.wear.as_ref().and_then(sim::life_distributions) {
        life.append(("cycles", column(py, &lives.cycles)))?;
        for c in &lives.curves {
            life.append((c.of.column(), column(py, &c.failed)))?;
        }
    }
    d.set_item("life_distribution", life)?;
    Ok(())
}

/// Run a scene like `wearsim run` (the same defaults: `cycles_per_stage` 2 on 2
/// `trajectories`; `threads` for them, default the machine's cores); returns a dict
/// of the summary (JSON text), response and contact columns and wear grids. `out` also
/// writes the files `wearsim run --out` writes. Releases the GIL while it runs.
#[pyfunction]
#[pyo3(signature = (scene, name, cycles=None, stages=None, rtol=None, surfaces=None,
    cycles_per_stage=None, max_steps=None, max_wall_time=None, out=None, trajectories=None,
    threads=None, wear_tolerance=None))]
#[allow(clippy::too_many_arguments)]
fn run<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    name: Option<String>,
    cycles: Option<u32>,
    stages: Option<u32>,
    rtol: Option<f64>,
    surfaces: Option<PathBuf>,
    cycles_per_stage: Option<u32>,
    max_steps: Option<usize>,
    max_wall_time: Option<f64>,
    out: Option<PathBuf>,
    trajectories: Option<u32>,
    threads: Option<usize>,
    wear_tolerance: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let (spec_name, table) = if let Ok(spec) = scene.extract::<String>() {
        load_table(&spec).map_err(scene_err)?
    } else if let Ok(d) = scene.cast::<PyDict>() {
        ("scene".to_string(), dict_to_table(d, "")?)
    } else {
        return Err(scene_err(
            "scene must be a built-in name, a file path or a dict from wornjoint.load",
        ));
    };
    let name = name.unwrap_or(spec_name);
    if cycles_per_stage == Some(0) {
        return Err(scene_err("cycles_per_stage = 0: must be at least 1"));
    }
    if trajectories == Some(0) {
        return Err(scene_err("trajectories = 0: must be at least 1"));
    }
    if threads == Some(0) {
        return Err(scene_err("threads = 0: must be at least 1"));
    }
    let scene = scene::from_table(table, &name).map_err(scene_err)?;
    let overrides = RunOverrides {
        cycles,
        stages,
        rtol,
        max_steps,
        max_wall_time,
        cycles_per_stage,
        trajectories,
        wear_tolerance,
        threads,
    };
    let scene = overrides
        .apply(scene, &format!("{name} with the run's arguments"))
        .map_err(scene_err)?;
    let options = sim::RunOptions {
        surfaces: surfaces.map(output::surfaces::folder),
        ..overrides.run_options()
    };
    let result = py.detach(|| {
        catch_unwind(AssertUnwindSafe(|| -> Result<RunOutcome, PyErrText> {
            let outcome = sim::run_scene(&name, &scene, &options, &mut ()).map_err(|e| {
                if e.is_bad_input() {
                    PyErrText::Scene(e.to_string())
                } else {
                    PyErrText::Run(e.to_string())
                }
            })?;
            if let Some(out) = &out {
                let write = || -> Result<(), output::files::OutputError> {
                    let staged = output::files::StagedDir::begin(out)?;
                    output::artifacts::write_run(&outcome, staged.path())?;
                    staged.commit()?;
                    Ok(())
                };
                write().map_err(|e| PyErrText::Run(e.to_string()))?;
            }
            Ok(outcome)
        }))
        .unwrap_or_else(|p| {
            Err(PyErrText::Run(format!(
                "internal error (panic): {}",
                panic_text(&*p)
            )))
        })
    });
    match result {
        Ok(outcome) => outcome_to_py(py, outcome),
        Err(PyErrText::Scene(m)) => Err(SceneError::new_err(m)),
        Err(PyErrText::Run(m)) => Err(RunError::new_err(m)),
    }
}

/// An error carried out of a GIL-free section (a `PyErr` is made after reattaching).
enum PyErrText {
    Scene(String),
    Run(String),
}

/// Read a sweep file: `(plan, name, samples)`; the plan rebuilds it anywhere.
#[pyfunction]
fn sweep_plan(path: PathBuf) -> PyResult<(String, String, usize)> {
    let s = Sweep::from_path(&path).map_err(|e| sweep_err(&e))?;
    Ok((s.plan(), s.name.clone(), s.samples()))
}

/// Run sample `index` of a plan (a Dask task): the row as JSON. Releases the GIL.
#[pyfunction]
fn sweep_sample(py: Python<'_>, plan: &str, index: usize) -> PyResult<String> {
    let row = py.detach(|| -> Result<Row, sweep::SweepError> {
        Sweep::from_plan(plan)?.try_run_sample(index)
    });
    row.map(|r| r.to_json()).map_err(|e| sweep_err(&e))
}

/// Samples still to run in `out` and, resuming, the rows kept (as JSON).
#[pyfunction]
fn sweep_pending(plan: &str, out: PathBuf, resume: bool) -> PyResult<(Vec<usize>, Vec<String>)> {
    let s = Sweep::from_plan(plan).map_err(|e| sweep_err(&e))?;
    let (todo, kept) = sweep::pending(&s, &out, resume).map_err(|e| sweep_err(&e))?;
    Ok((todo, kept.iter().map(Row::to_json).collect()))
}

/// Write rows (JSON, any order) into `out` as `wearsim sweep` does: `samples.csv`, and the
/// figures when `figures`. Returns the files written.
#[pyfunction]
#[pyo3(signature = (plan, rows, out, figures=true))]
fn sweep_write(
    py: Python<'_>,
    plan: &str,
    rows: Vec<String>,
    out: PathBuf,
    figures: bool,
) -> PyResult<Vec<PathBuf>> {
    let s = Sweep::from_plan(plan).map_err(|e| sweep_err(&e))?;
    let rows = rows
        .iter()
        .map(|r| Row::from_json(r))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| sweep_err(&e))?;
    py.detach(|| {
        if figures {
            sweep::write_outputs(&s, &rows, &out)
        } else {
            let mut rows = rows;
            rows.sort_by_key(|r| r.sample);
            sweep::table::write_rows(&s, &rows, &sweep::rows_path(&out))
                .map(|p| vec![p])
                .map_err(sweep::SweepError::from)
        }
    })
    .map_err(|e| sweep_err(&e))
}

/// Run a sweep file on local threads as `wearsim sweep` does; returns the rows file.
/// Releases the GIL; `on_row(done, total)`, if given, is called (with the GIL) as each sample
/// finishes, for progress.
#[pyfunction]
#[pyo3(signature = (path, out, resume=false, jobs=None, on_row=None))]
fn sweep_local(
    py: Python<'_>,
    path: PathBuf,
    out: PathBuf,
    resume: bool,
    jobs: Option<usize>,
    on_row: Option<Py<PyAny>>,
) -> PyResult<PathBuf> {
    let s = Sweep::from_path(&path).map_err(|e| sweep_err(&e))?;
    let mut options = LocalOptions {
        resume,
        ..LocalOptions::default()
    };
    if let Some(j) = jobs {
        options.jobs = j.max(1);
    }
    let report = |done: usize, total: usize| {
        if let Some(f) = &on_row {
            // Progress only: an error in the callback must not end the sweep.
            Python::attach(|py| {
                if let Err(e) = f.call1(py, (done, total)) {
                    e.print(py);
                }
            });
        }
    };
    py.detach(|| {
        sweep::run_local(&s, &out, &options, None, &mut |_, done, total| {
            report(done, total)
        })
    })
    .map_err(|e| sweep_err(&e))?;
    Ok(sweep::rows_path(&out))
}

/// The native module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("RunError", py.get_type::<RunError>())?;
    m.add("SweepError", py.get_type::<SweepError>())?;
    m.add_class::<Outcome>()?;
    m.add_function(wrap_pyfunction!(scenes, m)?)?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(sweep_plan, m)?)?;
    m.add_function(wrap_pyfunction!(sweep_sample, m)?)?;
    m.add_function(wrap_pyfunction!(sweep_pending, m)?)?;
    m.add_function(wrap_pyfunction!(sweep_write, m)?)?;
    m.add_function(wrap_pyfunction!(sweep_local, m)?)?;
    Ok(())
}
