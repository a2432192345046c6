//! `impact._impact`: the native half of the Python package `impact` (PyO3, abi3). Every
//! function is a thin call into the library the CLI uses (`impact`, the root crate): the
//! flags come as the CLI's own strings (`["--cells", "200"]`, parsed by
//! [`impact::flags`]), the scene as TOML text, and the outputs are the CLI's folders and
//! JSON files plus, for a run, the fields as NumPy arrays. The Python layer
//! (`python/impact/__init__.py`) turns keyword arguments into flags and wraps the
//! results. Stepping runs on a worker thread with the GIL released; a `KeyboardInterrupt`
//! sets the library's stop flag ([`impact::interrupt::stop_flag`]) and the run ends
//! between two steps, its staging folder removed.
use impact::fields::{Frame, MethodFields};
use impact::progress_feed::Feed;
use impact::{Overrides, Study};
use impact_core::Scene;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyKeyboardInterrupt, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;
use std::sync::atomic::Ordering;

pyo3::create_exception!(
    _impact,
    SceneError,
    PyValueError,
    "A scene, flag or option the CLI would refuse; the message is the CLI's."
);

/// The CLI's message of an error (`error: <this>` on its stderr) as a `SceneError`, or
/// `KeyboardInterrupt` for a run stopped by the stop flag.
fn to_py(e: anyhow::Error) -> PyErr {
    if e.downcast_ref::<impact::interrupt::Interrupted>().is_some() {
        return PyKeyboardInterrupt::new_err(format!("{e:#}"));
    }
    SceneError::new_err(format!("{e:#}"))
}

/// Run `work` on a worker thread with the GIL released; check Python's signals every
/// 20 ms, and on `KeyboardInterrupt` stop the run between two steps and re-raise.
fn detached<T: Send>(
    py: Python<'_>,
    work: impl FnOnce() -> anyhow::Result<T> + Send,
) -> PyResult<T> {
    detached_reporting(py, None, work)
}

/// Seconds between two calls of a progress callback (a few updates per second: a
/// notebook widget redraws on each).
const PROGRESS_EVERY_S: f64 = 0.2;

/// [`detached`], reporting progress to `on_progress` when given: the worker collects its
/// bars in a [`Feed`] (module [`impact::progress_feed`]), and this thread, which wakes
/// every 20 ms for the signals anyway and holds the GIL then, calls
/// `on_progress([(index, label, fraction, finished), ...])` with every bar created so far
/// when one changed, at most every [`PROGRESS_EVERY_S`], and once more at the end. The
/// step loop never waits on the GIL. A callback that raises stops the run as Ctrl-C does
/// and its exception propagates.
fn detached_reporting<T: Send>(
    py: Python<'_>,
    on_progress: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce() -> anyhow::Result<T> + Send,
) -> PyResult<T> {
    let flag = impact::interrupt::stop_flag();
    flag.store(false, Ordering::SeqCst);
    let feed = Feed::default();
    let mut reported = Vec::new();
    let mut last_report = std::time::Instant::now();
    let mut report = |final_call: bool| -> PyResult<()> {
        let Some(callback) = on_progress else {
            return Ok(());
        };
        let elapsed = last_report.elapsed().as_secs_f64();
        if !final_call && elapsed < PROGRESS_EVERY_S {
            return Ok(());
        }
        let states = feed.snapshot();
        if states == reported {
            return Ok(());
        }
        let updates: Vec<_> = states
            .iter()
            .enumerate()
            .map(|(i, s)| (i, s.label.clone(), s.fraction, s.finished))
            .collect();
        callback.call1((updates,))?;
        reported = states;
        last_report = std::time::Instant::now();
        Ok(())
    };
    std::thread::scope(|scope| {
        let worker_feed = feed.clone();
        let handle = scope.spawn(move || {
            let _installed = worker_feed.install();
            work()
        });
        while !handle.is_finished() {
            py.detach(|| std::thread::sleep(std::time::Duration::from_millis(20)));
            if let Err(stop) = py.check_signals().and_then(|()| report(false)) {
                flag.store(true, Ordering::SeqCst);
                let _ = py.detach(|| handle.join());
                flag.store(false, Ordering::SeqCst);
                return Err(stop);
            }
        }
        let result = match handle.join() {
            Ok(result) => result.map_err(to_py),
            Err(_) => Err(PyRuntimeError::new_err(
                "internal error: the run panicked (please report it with its scene)",
            )),
        };
        report(true)?;
        result
    })
}

/// The scene of TOML `text` with the overrides, validated as the CLI validates it.
fn study(text: &str, source: &str, overrides: Overrides) -> anyhow::Result<Study> {
    let scene = Scene::parse_toml(text, source)?;
    Ok(Study::new(scene, overrides)?)
}

/// The shipped scene names (`impact scenes`).
#[pyfunction]
fn scenes() -> Vec<&'static str> {
    impact_core::scene::BUILTIN.to_vec()
}

/// A shipped scene name or a scene file, validated: `(toml, name)`.
#[pyfunction]
fn scene_load(source: &str) -> PyResult<(String, String)> {
    let load = || -> anyhow::Result<(String, String)> {
        let scene = Study::load(source, Overrides::default())?.scene;
        Ok((toml::to_string(&scene)?, scene.name))
    };
    load().map_err(to_py)
}

/// The scene of TOML `text` as JSON (every default written out).
#[pyfunction]
fn scene_to_json(text: &str) -> PyResult<String> {
    let convert = || -> anyhow::Result<String> {
        Ok(serde_json::to_string(&Scene::parse_toml(text, "<scene>")?)?)
    };
    convert().map_err(to_py)
}

/// The scene of JSON `text` (from a dict) as TOML, validated: `(toml, name)`.
#[pyfunction]
fn scene_from_json(text: &str, origin: &str) -> PyResult<(String, String)> {
    let convert = || -> anyhow::Result<(String, String)> {
        let value: toml::Value = serde_json::from_str(text)?;
        let toml_text = toml::to_string(&value)?;
        let scene = Study::new(Scene::parse_toml(&toml_text, origin)?, Overrides::default())?.scene;
        Ok((toml::to_string(&scene)?, scene.name))
    };
    convert().map_err(to_py)
}

/// The scene of TOML `text` with the override `flags` applied, validated: `(toml, name)`.
#[pyfunction]
fn scene_with(text: &str, source: &str, flags: Vec<String>) -> PyResult<(String, String)> {
    let apply = || -> anyhow::Result<(String, String)> {
        let study = study(text, source, impact::flags::overrides_from_flags(&flags)?)?;
        Ok((toml::to_string(&study.scene)?, study.scene.name))
    };
    apply().map_err(to_py)
}

fn array<'py>(py: Python<'py>, v: Vec<f64>, shape: &[usize]) -> PyResult<Bound<'py, PyAny>> {
    let flat = PyArray1::from_vec(py, v);
    Ok(match shape.len() {
        1 => flat.into_any(),
        _ => flat.reshape(shape.to_vec())?.into_any(),
    })
}

fn frame_dict<'py>(py: Python<'py>, f: Frame) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let n = f.stress.len() / (f.dim * f.dim).max(1);
    let (dim, vector, tensor) = (f.dim, [n, f.dim], [n, f.dim, f.dim]);
    d.set_item("index", f.index)?;
    d.set_item("t", f.t)?;
    d.set_item("reference", array(py, f.reference, &vector)?)?;
    d.set_item("position", array(py, f.position, &vector)?)?;
    d.set_item("half_size", array(py, f.half_size, &vector)?)?;
    d.set_item("velocity", array(py, f.velocity, &vector)?)?;
    d.set_item("stress", array(py, f.stress, &tensor)?)?;
    let optional = |v: Vec<f64>| -> PyResult<Option<Bound<'py, PyAny>>> {
        (!v.is_empty()).then(|| array(py, v, &[n])).transpose()
    };
    d.set_item("stress_zz", optional(f.stress_zz)?)?;
    d.set_item("plastic_strain", optional(f.plastic_strain)?)?;
    d.set_item("reference_stress_xx", optional(f.reference_stress_xx)?)?;
    d.set_item("reference_velocity_x", optional(f.reference_velocity_x)?)?;
    let profile = PyDict::new(py);
    for (name, column) in f.profile.0.into_iter().zip(f.profile.1) {
        let len = column.len();
        profile.set_item(name, array(py, column, &[len])?)?;
    }
    d.set_item("profile", profile)?;
    let cells = f.map.len();
    d.set_item(
        "map",
        (dim > 1).then(|| array(py, f.map, &[cells])).transpose()?,
    )?;
    Ok(d)
}

fn fields_list<'py>(py: Python<'py>, fields: Vec<MethodFields>) -> PyResult<Bound<'py, PyList>> {
    let out = PyList::empty(py);
    for m in fields {
        let d = PyDict::new(py);
        d.set_item("method", m.method)?;
        d.set_item("stress_name", m.stress_name)?;
        let frames = PyList::empty(py);
        for f in m.frames {
            frames.append(frame_dict(py, f)?)?;
        }
        d.set_item("frames", frames)?;
        out.append(d)?;
    }
    Ok(out)
}

/// `impact run`: the scene (TOML `text`, `source` as given) with the run `flags`, into
/// `out`; returns `{reference, failures, fields}`.
#[pyfunction]
#[pyo3(signature = (text, source, flags, out, files, reference, ascii, progress))]
#[allow(clippy::too_many_arguments)]
fn run<'py>(
    py: Python<'py>,
    text: &str,
    source: &str,
    flags: Vec<String>,
    out: PathBuf,
    files: bool,
    reference: bool,
    ascii: bool,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    use impact::run::{run_study_keeping, RunOptions};
    let (overrides, methods) = impact::flags::run_flags(&flags).map_err(|e| to_py(e.into()))?;
    let study = study(text, source, overrides).map_err(to_py)?;
    let options = RunOptions {
        out,
        quiet: progress.is_none(),
        no_files: !files,
        no_reference: !reference,
        vtu: match ascii {
            true => impact_io::vtu::VtuEncoding::Ascii,
            false => impact_io::vtu::VtuEncoding::Binary,
        },
        source: source.to_string(),
        allow_unstable: study.overrides.allow_unstable,
    };
    let (report, fields) = detached_reporting(py, progress.as_ref(), || match study.dim() {
        1 => run_study_keeping::<1>(&study, &methods, &options, true),
        2 => run_study_keeping::<2>(&study, &methods, &options, true),
        3 => run_study_keeping::<3>(&study, &methods, &options, true),
        d => anyhow::bail!("dim = {d} is not supported (allowed: 1, 2 or 3)"),
    })?;
    let d = PyDict::new(py);
    d.set_item("reference", report.reference)?;
    d.set_item("failures", report.failures)?;
    d.set_item("fields", fields_list(py, fields)?)?;
    Ok(d)
}

/// `impact check --json <json>`: returns whether the gate passes.
#[pyfunction]
fn check(
    py: Python<'_>,
    text: &str,
    source: &str,
    flags: Vec<String>,
    json: PathBuf,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<bool> {
    use impact::check::check_study;
    let clock = impact::provenance::Clock::start();
    let (overrides, gate) = impact::flags::check_flags(&flags).map_err(|e| to_py(e.into()))?;
    let options = gate.options(progress.is_some()).map_err(to_py)?;
    let study = study(text, source, overrides).map_err(to_py)?;
    detached_reporting(py, progress.as_ref(), || {
        let reports = match study.dim() {
            1 => check_study::<1>(&study, &options)?,
            2 => check_study::<2>(&study, &options)?,
            3 => check_study::<3>(&study, &options)?,
            d => anyhow::bail!("dim = {d} is not supported (allowed: 1, 2 or 3)"),
        };
        impact::check_report::write_outcome(&json, (&study, source), &options, &reports, &clock)?;
        Ok(reports.iter().all(|r| r.pass))
    })
}

/// `impact bench convergence` on the scene into `out`.
#[pyfunction]
fn convergence(
    py: Python<'_>,
    text: &str,
    source: &str,
    flags: Vec<String>,
    levels: usize,
    out: PathBuf,
) -> PyResult<String> {
    let overrides = impact::flags::overrides_from_flags(&flags).map_err(|e| to_py(e.into()))?;
    let study = study(text, source, overrides).map_err(to_py)?;
    detached(py, || {
        impact::convergence::run((&study, source), levels, &out, |_| {})
    })
}

/// `impact bench work-precision` on the scene into `out` (each run is `exe run`).
#[pyfunction]
#[pyo3(signature = (exe, text, source, flags, levels, out))]
fn work_precision(
    py: Python<'_>,
    exe: PathBuf,
    text: &str,
    source: &str,
    flags: Vec<String>,
    levels: Option<usize>,
    out: PathBuf,
) -> PyResult<String> {
    let overrides = impact::flags::overrides_from_flags(&flags).map_err(|e| to_py(e.into()))?;
    let study = study(text, source, overrides).map_err(to_py)?;
    let levels = levels.unwrap_or_else(|| impact::ladder::default_levels(&study));
    detached(py, || {
        let (_, sentence) =
            impact::work_precision::run(&exe, (&study, source), levels, &out, |_| {}, |_| {})?;
        Ok(sentence)
    })
}

/// `impact stability` into `out`; returns the table's lines and the rows as JSON.
#[pyfunction]
#[pyo3(signature = (scene, dim, flags, steps_1d, steps_2d, out, layout, shift, positions))]
#[allow(clippy::too_many_arguments)]
fn stability(
    py: Python<'_>,
    scene: Option<String>,
    dim: Option<Vec<usize>>,
    flags: Vec<String>,
    steps_1d: usize,
    steps_2d: usize,
    out: PathBuf,
    layout: Option<String>,
    shift: Option<f64>,
    positions: Option<Vec<f64>>,
) -> PyResult<(Vec<String>, String)> {
    use clap::ValueEnum as _;
    let overrides = impact::flags::overrides_from_flags(&flags).map_err(|e| to_py(e.into()))?;
    let layout = layout
        .map(|l| {
            impact_core::method::LayoutKind::from_str(&l, false).map_err(|e| {
                SceneError::new_err(format!("invalid value '{l}' for '--layout <LAYOUT>': {e}"))
            })
        })
        .transpose()?;
    let options = impact::stability_run::StabilityOptions {
        scene,
        dim,
        overrides,
        steps_1d,
        steps_2d,
        out,
        layout,
        shift,
        positions,
    };
    detached(py, || {
        let mut lines = Vec::new();
        let rows = impact::stability_run::run(&options, |l| lines.push(l.to_string()))?;
        Ok((lines, serde_json::to_string(&rows)?))
    })
}

/// Copy the run folder `from` into `to` as one complete output folder (the CLI's
/// replace-as-a-whole rule: an existing impact folder is replaced, anything else refused).
#[pyfunction]
fn publish(from: PathBuf, to: PathBuf) -> PyResult<()> {
    let copy = || -> anyhow::Result<()> {
        let folder = impact_io::folder::OutputFolder::open(&to)?;
        for entry in std::fs::read_dir(&from)? {
            let entry = entry?;
            if entry.file_type()?.is_file() {
                std::fs::copy(entry.path(), folder.path().join(entry.file_name()))?;
            }
        }
        folder.commit(concat!("impact ", env!("CARGO_PKG_VERSION")))?;
        Ok(())
    };
    copy().map_err(to_py)
}

#[pymodule]
fn _impact(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("SceneError", m.py().get_type::<SceneError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(scenes, m)?)?;
    m.add_function(wrap_pyfunction!(scene_load, m)?)?;
    m.add_function(wrap_pyfunction!(scene_to_json, m)?)?;
    m.add_function(wrap_pyfunction!(scene_from_json, m)?)?;
    m.add_function(wrap_pyfunction!(scene_with, m)?)?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(convergence, m)?)?;
    m.add_function(wrap_pyfunction!(work_precision, m)?)?;
    m.add_function(wrap_pyfunction!(stability, m)?)?;
    m.add_function(wrap_pyfunction!(publish, m)?)?;
    Ok(())
}
