//! `pbdda._pbdda`, the Rust half of the Python package `pbdda` (the Python half, `pbdda/`,
//! wraps it): a simulation stepped from Python ([`pbdda::api::Simulation`]), its tables as
//! numpy columns, scenes from Python dicts, and the sweep plan's three steps (write the plan,
//! run cases, collect) that the Python `sweep` spreads over a Dask cluster.

use numpy::IntoPyArray;
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyList, PyString, PyTuple};
use std::path::PathBuf;

use pbdda::api::{ApiError, Simulation as Sim, Table};
use pbdda::cli::sweep::{Axis, Study, plan};
use pbdda::scene::Override;

create_exception!(pbdda, PbddaError, PyException, "Any error of pbdda.");
create_exception!(
    pbdda,
    SceneError,
    PbddaError,
    "An invalid scene; `file`, `line`, `column`, `key` and `message` say where and what."
);
create_exception!(pbdda, StepError, PbddaError, "A step that failed (the solver gave up).");
create_exception!(pbdda, OutputError, PbddaError, "Results that could not be written.");
create_exception!(pbdda, SweepError, PbddaError, "A sweep that could not be planned, run or collected.");

/// A scene error as a `SceneError` with its parts as attributes.
fn scene_error(py: Python<'_>, e: &pbdda::scene::SceneError) -> PyErr {
    let err = SceneError::new_err(e.to_string());
    let value = err.value(py);
    // setting an attribute on a fresh exception object cannot fail
    let _ = value.setattr("file", &e.file);
    let _ = value.setattr("line", e.line);
    let _ = value.setattr("column", e.column);
    let _ = value.setattr("key", &e.key);
    let _ = value.setattr("message", &e.message);
    err
}

/// A miette report as an exception of `kind`, with its whole chain of causes in the message;
/// a scene error inside it becomes a `SceneError` with its parts.
fn report_error(py: Python<'_>, e: &miette::Report, kind: fn(String) -> PyErr) -> PyErr {
    let message = e.chain().map(|c| c.to_string()).collect::<Vec<_>>().join(": ");
    match e.chain().find_map(|c| c.downcast_ref::<pbdda::scene::SceneError>()) {
        Some(scene) => {
            let err = scene_error(py, scene);
            // the outer context (`case 3 (k=v)`) first
            if let Ok(args) = PyTuple::new(py, [message]) {
                let _ = err.value(py).setattr("args", args);
            }
            err
        }
        None => kind(message),
    }
}

fn overrides(set: Vec<String>) -> PyResult<Vec<Override>> {
    set.iter().map(|s| Override::parse(s).map_err(|e| SceneError::new_err(format!("set {s}: {e}")))).collect()
}

/// A Python value as a TOML value: dict, list/tuple (or anything iterable that is not a
/// string), str, bool, int, float (numpy scalars and arrays too).
fn to_toml(v: &Bound<'_, PyAny>, key: &str) -> PyResult<toml::Value> {
    let bad = |what: &str| SceneError::new_err(format!("<dict>: {key}: {what}"));
    if v.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(v.extract()?));
    }
    if v.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(v.extract()?));
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(v.extract()?));
    }
    if let Ok(d) = v.extract::<Bound<'_, PyDict>>() {
        let mut table = toml::Table::new();
        for (k, item) in d.iter() {
            let k: String = k.extract().map_err(|_| bad("a table's keys must be strings"))?;
            let path = if key.is_empty() { k.clone() } else { format!("{key}.{k}") };
            if !item.is_none() {
                table.insert(k, to_toml(&item, &path)?);
            }
        }
        return Ok(toml::Value::Table(table));
    }
    if let Ok(i) = v.extract::<i64>() {
        return Ok(toml::Value::Integer(i));
    }
    if let Ok(x) = v.extract::<f64>() {
        return Ok(toml::Value::Float(x));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() || v.hasattr("__iter__")? {
        let mut items = Vec::new();
        for (i, item) in v.try_iter()?.enumerate() {
            items.push(to_toml(&item?, &format!("{key}[{i}]"))?);
        }
        return Ok(toml::Value::Array(items));
    }
    Err(bad(&format!("cannot write a {} in a scene", v.get_type().name()?)))
}

/// The TOML text of a scene given as a dict (the keys and tables of a scene file).
#[pyfunction]
fn to_toml_text(scene: &Bound<'_, PyDict>) -> PyResult<String> {
    let value = to_toml(scene.as_any(), "")?;
    toml::to_string(&value).map_err(|e| SceneError::new_err(format!("<dict>: {e}")))
}

/// A simulation: a scene's world, stepped from Python.
#[pyclass(unsendable, module = "pbdda._pbdda")]
struct Simulation {
    sim: Sim,
}

fn step_error(e: ApiError) -> PyErr {
    match e {
        ApiError::Step(e) => StepError::new_err(e.to_string()),
        ApiError::Output(e) => OutputError::new_err(e.to_string()),
    }
}

#[pymethods]
impl Simulation {
    /// The scene file at `path`, with `set` overrides (`KEY=VALUE` strings, as `--set`).
    #[staticmethod]
    #[pyo3(signature = (path, set = Vec::new()))]
    fn load(py: Python<'_>, path: PathBuf, set: Vec<String>) -> PyResult<Simulation> {
        let set = overrides(set)?;
        let sim = Sim::load(&path, &set).map_err(|e| scene_error(py, &e))?;
        Ok(Simulation { sim })
    }

    /// The scene text `text`, named `file` in errors (relative paths are those of its folder).
    #[staticmethod]
    #[pyo3(signature = (text, file = "<scene>".to_owned(), set = Vec::new()))]
    fn parse(py: Python<'_>, text: &str, file: String, set: Vec<String>) -> PyResult<Simulation> {
        let set = overrides(set)?;
        let sim = Sim::parse(text, &file, &set).map_err(|e| scene_error(py, &e))?;
        Ok(Simulation { sim })
    }

    /// Writes every step from now on into `out`, as `pbdda run --out` does.
    #[pyo3(signature = (out, overwrite = false))]
    fn write_to(&mut self, out: PathBuf, overwrite: bool) -> PyResult<()> {
        self.sim.write_to(&out, overwrite).map_err(OutputError::new_err)
    }

    /// Takes up to `n` steps (fewer at the end of the run); returns how many it took.
    fn step(&mut self, py: Python<'_>, n: usize) -> PyResult<usize> {
        let mut taken = 0;
        while taken < n && self.sim.step().map_err(step_error)? {
            taken += 1;
            if taken % 64 == 0 {
                py.check_signals()?;
            }
        }
        Ok(taken)
    }

    /// Writes run.log's closing line now (the last step does it at the end of the run).
    fn close(&mut self) -> PyResult<()> {
        self.sim.close().map_err(|e| OutputError::new_err(e.to_string()))
    }

    /// Simulated time [s].
    #[getter]
    fn time(&self) -> f64 {
        self.sim.world.time
    }

    /// Steps taken.
    #[getter]
    fn step_index(&self) -> usize {
        self.sim.world.step_index
    }

    /// Steps of the run (`time.steps`).
    #[getter]
    fn steps(&self) -> usize {
        self.sim.world.model.time.steps
    }

    /// The time step [s] the next step starts with.
    #[getter]
    fn dt(&self) -> f64 {
        self.sim.world.dt()
    }

    #[getter]
    fn finished(&self) -> bool {
        self.sim.finished()
    }

    /// The results folder, if the simulation writes one.
    #[getter]
    fn output_dir(&self) -> Option<PathBuf> {
        self.sim.output_dir().map(PathBuf::from)
    }

    /// The table (`bodies`, `contacts`, `connectors`) as its CSV text.
    fn table_csv(&self, name: &str) -> PyResult<String> {
        Ok(self.sim.table(table(name)?))
    }

    /// The table as (column names, columns): numpy int64 for integer columns, float64 for
    /// numbers (NaN where the CSV cell is empty), lists of str for text.
    fn table(&self, py: Python<'_>, name: &str) -> PyResult<(Vec<String>, Vec<Py<PyAny>>)> {
        let text = self.sim.table(table(name)?);
        columns(py, &text)
    }
}

fn table(name: &str) -> PyResult<Table> {
    Table::named(name)
        .ok_or_else(|| PbddaError::new_err(format!("no table `{name}`: bodies, contacts, connectors or monitors")))
}

/// Integer columns of the CSV contract; text columns are the others in [`TEXT`].
const INTEGER: [&str; 4] = ["step", "contacts", "outer_iterations", "inner_iterations"];
const TEXT: [&str; 10] =
    ["body", "body_a", "body_b", "kind", "state", "monitor", "connector", "interface", "stage", "method"];

/// The CSV text `text` (header, rows) as columns.
fn columns(py: Python<'_>, text: &str) -> PyResult<(Vec<String>, Vec<Py<PyAny>>)> {
    let mut lines = text.lines();
    let names: Vec<String> = lines.next().unwrap_or("").split(',').map(str::to_owned).collect();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let mut out = Vec::new();
    for (j, name) in names.iter().enumerate() {
        let cells = rows.iter().map(|r| r.get(j).copied().unwrap_or(""));
        let column: Py<PyAny> = if INTEGER.contains(&name.as_str()) {
            let v: Vec<i64> = cells.map(|c| c.parse().unwrap_or(-1)).collect();
            v.into_pyarray(py).into_any().unbind()
        } else if TEXT.contains(&name.as_str()) {
            let v: Vec<String> = cells.map(str::to_owned).collect();
            PyList::new(py, v)?.into_any().unbind()
        } else {
            let v: Vec<f64> = cells.map(|c| c.parse().unwrap_or(f64::NAN)).collect();
            v.into_pyarray(py).into_any().unbind()
        };
        out.push(column);
    }
    Ok((names, out))
}

/// Writes the plan of a sweep into `dir` (as `pbdda sweep --plan DIR`): `scene`, fixed
/// `set` overrides, the swept `(key, values)` and the options of `pbdda sweep`.
#[pyfunction]
#[pyo3(signature = (dir, scene, sweep, set = Vec::new(), zip = false, reference = None, exact = None, sizes = None))]
#[allow(clippy::too_many_arguments)]
fn plan_sweep(
    py: Python<'_>,
    dir: PathBuf,
    scene: String,
    sweep: Vec<(String, Vec<String>)>,
    set: Vec<String>,
    zip: bool,
    reference: Option<String>,
    exact: Option<String>,
    sizes: Option<Vec<f64>>,
) -> PyResult<usize> {
    let study = Study {
        scene,
        out: None,
        set,
        zip,
        reference,
        exact,
        sizes,
        sweep: sweep.into_iter().map(|(key, values)| Axis { key, values }).collect(),
    };
    plan::write_plan(&dir, &study).map_err(|e| report_error(py, &e, SweepError::new_err))?;
    plan::cases(&dir).map_err(|e| report_error(py, &e, SweepError::new_err))
}

/// Number of cases of the plan in `dir`.
#[pyfunction]
fn plan_cases(py: Python<'_>, dir: PathBuf) -> PyResult<usize> {
    plan::cases(&dir).map_err(|e| report_error(py, &e, SweepError::new_err))
}

/// Runs shard `i` of `n` of the plan in `dir` (`pbdda sweep --run-plan DIR --shard I/N`).
#[pyfunction]
#[pyo3(signature = (dir, i, n, quiet = true))]
fn run_shard(py: Python<'_>, dir: PathBuf, i: usize, n: usize, quiet: bool) -> PyResult<()> {
    if n == 0 || i >= n {
        return Err(SweepError::new_err(format!("shard {i}/{n}: expected 0 <= I < N")));
    }
    plan::run_plan(&dir, (i, n), quiet).map_err(|e| report_error(py, &e, SweepError::new_err))
}

/// Merges the results of the plan in `dir` into `out`/sweep.csv (and sweep.png), as
/// `pbdda sweep --collect DIR --out OUT`; returns sweep.csv's text.
#[pyfunction]
fn collect_sweep(py: Python<'_>, dir: PathBuf, out: PathBuf) -> PyResult<String> {
    let report = plan::collect(&dir).map_err(|e| report_error(py, &e, SweepError::new_err))?;
    pbdda::cli::sweep::write_files(&report, &out).map_err(|e| report_error(py, &e, SweepError::new_err))?;
    Ok(report.csv())
}

#[pymodule]
fn _pbdda(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<Simulation>()?;
    m.add_function(wrap_pyfunction!(to_toml_text, m)?)?;
    m.add_function(wrap_pyfunction!(plan_sweep, m)?)?;
    m.add_function(wrap_pyfunction!(plan_cases, m)?)?;
    m.add_function(wrap_pyfunction!(run_shard, m)?)?;
    m.add_function(wrap_pyfunction!(collect_sweep, m)?)?;
    m.add("PbddaError", py.get_type::<PbddaError>())?;
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("StepError", py.get_type::<StepError>())?;
    m.add("OutputError", py.get_type::<OutputError>())?;
    m.add("SweepError", py.get_type::<SweepError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
