"""The Python package against the CLI: the same scene gives the same fields and metrics
bit for bit, bad input the same message, an interrupted run no half-written folder, and
the examples run. Needs the package installed (`maturin develop --release -m
crates/impact-py/Cargo.toml`) and the CLI built (`IMPACT_BIN`, default
target/release/impact); scripts/test.sh does both."""
import json
import re
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import meshio
import numpy as np
import pytest

import impact

ROOT = Path(__file__).resolve().parents[3]
BIN = os.environ.get("IMPACT_BIN", str(ROOT / "target" / "release" / "impact"))


def cli(*args, check=True):
    done = subprocess.run([BIN, *args], capture_output=True, text=True)
    if check and done.returncode != 0:
        raise AssertionError(f"impact {' '.join(args)}: {done.stderr}")
    return done


def without_timing(summary):
    """summary.json without what differs from one run to the next (wall times, memory)."""
    summary = dict(summary)
    summary.pop("peak_rss_mib", None)
    summary["runs"] = [{k: v for k, v in r.items() if k != "wall_s"} for r in summary["runs"]]
    return summary


def pad3(a):
    out = np.zeros((a.shape[0], 3))
    out[:, : a.shape[1]] = a
    return out


def tensor9(s, zz=None):
    n, d = s.shape[0], s.shape[1]
    out = np.zeros((n, 3, 3))
    out[:, :d, :d] = s
    return out.reshape(n, 9)


def assert_same_as_cli(res, folder):
    """Every frame of `res` equals the CLI's files in `folder`: the samples' .vtu arrays
    bit for bit (binary VTU holds the float64 bits), the CSV profile at the file's 13
    significant digits, summary.json's metrics exactly."""
    with open(folder / "summary.json") as f:
        assert without_timing(res.summary) == without_timing(json.load(f))
    for m in res:
        assert m.frames, m.method
        for frame in m.frames:
            mesh = meshio.read(folder / f"{m.method}_t{frame.index}.vtu")
            assert np.array_equal(mesh.points, pad3(frame.position))
            assert np.array_equal(mesh.point_data["velocity"], pad3(frame.velocity))
            stress = mesh.point_data[m.stress_name]
            d = frame.stress.shape[1]
            for r in range(d):
                for c in range(d):
                    assert np.array_equal(stress[:, 3 * r + c], frame.stress[:, r, c])
            if frame.plastic_strain is not None:
                cli_eps = mesh.point_data["equivalent_plastic_strain"]
                assert np.array_equal(cli_eps.ravel(), frame.plastic_strain)
            if frame.map is not None:  # 2D: the map is the grid file's cell σ_xx where filled
                grid = meshio.read(folder / f"{m.method}_grid_t{frame.index}.vtu")
                cell_sxx = grid.cell_data[m.stress_name][0][:, 0]
                filled = ~np.isnan(frame.map)
                assert filled.any() and np.array_equal(frame.map[filled], cell_sxx[filled])
            table = np.genfromtxt(
                folder / f"{m.method}_t{frame.index}.csv", delimiter=",", names=True
            )
            assert list(table.dtype.names) == list(frame.profile)
            for name, column in frame.profile.items():
                printed = np.array([float(f"{v:.12e}") for v in column])
                assert np.array_equal(np.atleast_1d(table[name]), printed), name


@pytest.mark.parametrize(
    "scene,flags",
    [
        ("bar", []),
        ("ep-bar", ["--cells", "60"]),
        ("svk-bar", ["--cells", "60"]),
        ("plate-wave", ["--cells", "16"]),
    ],
)
def test_run_equals_the_cli_bit_for_bit(tmp_path, scene, flags):
    cli("run", scene, *flags, "--quiet", "--out", str(tmp_path / "cli"))
    overrides = {flags[i][2:].replace("-", "_"): flags[i + 1] for i in range(0, len(flags), 2)}
    res = impact.run(scene, out=tmp_path / "py", **overrides)
    assert res.failures == []
    assert set(res.methods) == {"dgmpm", "mpm", "fem"}
    assert_same_as_cli(res, tmp_path / "cli")
    # the exact solution is there, and DGMPM at Courant 1 on the bar is on it (the paper)
    if scene == "bar":
        f = res["dgmpm"].frames[-1]
        assert np.max(np.abs(f.stress[:, 0, 0] - f.reference_stress_xx)) < 1e-3 * 1e9


def test_scene_from_a_dict_runs_as_the_file(tmp_path):
    data = impact.Scene.load("bar").to_dict()
    assert impact.Scene.from_dict(data).to_dict() == data
    data["domain"]["cells"] = [40]
    res = impact.run(data, methods=["dgmpm"], out=tmp_path / "py")
    # the same scene as a file for the CLI (editing `cells` in the scene counts its
    # output_transits on the new grid, unlike the `--cells` flag that keeps the times)
    path = tmp_path / "forty.toml"
    path.write_text(impact.Scene.from_dict(data).to_toml())
    cli("run", str(path), "--method", "dgmpm", "--quiet", "--out", str(tmp_path / "cli"))
    assert_same_as_cli(res, tmp_path / "cli")


def test_write_gives_the_cli_folder(tmp_path):
    res = impact.run("bar", methods=["dgmpm", "fem"])
    target = res.write(tmp_path / "copy")
    names = sorted(p.name for p in target.iterdir())
    cli("run", "bar", "--method", "dgmpm,fem", "--quiet", "--out", str(tmp_path / "cli"))
    # the CLI built with the hdf5 feature also writes <method>.h5 and .xdmf files
    cli_names = [p.name for p in (tmp_path / "cli").iterdir()]
    assert names == sorted(n for n in cli_names if not n.endswith((".h5", ".xdmf")))
    assert_same_as_cli(res, target)
    with pytest.raises(impact.SceneError, match="not an impact output folder|refus"):
        (tmp_path / "mine").mkdir()
        (tmp_path / "mine" / "notes.txt").write_text("keep me")
        res.write(tmp_path / "mine")
    assert (tmp_path / "mine" / "notes.txt").read_text() == "keep me"


def cli_message(*args):
    done = cli(*args, check=False)
    assert done.returncode == 2, done.stderr
    # the message: up to the first blank line (clap's tips and usage follow)
    lines = done.stderr.splitlines()
    return "\n".join(lines[: lines.index("")] if "" in lines else lines)


@pytest.mark.parametrize(
    "flags,overrides",
    [
        (["--cells", "abc"], {"cells": "abc"}),
        (["--courant", "-1"], {"courant": -1.0}),
        (["--courant", "2.5"], {"courant": 2.5}),
        (["--integrator", "rk9"], {"integrator": "rk9"}),
        (["--points-per-cell", "0"], {"points_per_cell": 0}),
        (["--no-such-flag", "1"], {"no_such_flag": 1}),
        (["--output-times", "1,-2"], {"output_times": [1.0, -2.0]}),
        (["--vtu", "xml"], {"vtu": "xml"}),
    ],
)
def test_bad_input_raises_the_cli_message(tmp_path, flags, overrides):
    expected = cli_message("run", "bar", *flags, "--quiet", "--out", str(tmp_path / "cli"))
    with pytest.raises(impact.SceneError) as e:
        impact.run("bar", out=tmp_path / "py", **overrides)
    assert expected == f"error: {e.value}"
    assert isinstance(e.value, ValueError)
    assert not (tmp_path / "py").exists()


def test_bad_scene_raises_the_cli_message(tmp_path):
    expected = cli_message("run", "no-such-scene")
    with pytest.raises(impact.SceneError) as e:
        impact.Scene.load("no-such-scene")
    assert expected == f"error: {e.value}"
    bad = impact.Scene.load("bar").to_dict()
    bad["material"]["density"] = -1.0
    path = tmp_path / "bad.toml"
    text = impact.Scene.load("bar").to_toml()
    path.write_text(re.sub(r"(?m)^density = .*$", "density = -1.0", text, count=1))
    expected = cli_message("run", str(path))
    with pytest.raises(impact.SceneError) as e:
        impact.Scene.load(path)
    assert expected == f"error: {e.value}"
    with pytest.raises(impact.SceneError, match="density"):
        impact.Scene.from_dict(bad)


def test_interrupt_leaves_no_half_written_folder(tmp_path):
    out = tmp_path / "plate"
    main = threading.main_thread().ident
    # SIGINT from another thread once the stepping has begun (the first progress update),
    # not after a fixed delay: a fast machine could finish the run before the signal
    timer = threading.Timer(0.05, lambda: signal.pthread_kill(main, signal.SIGINT))

    def on_progress(updates):
        if not timer.is_alive() and not timer.finished.is_set():
            timer.start()

    # Python's own handler, as in a terminal or notebook (a process started in the
    # background by a non-interactive shell inherits SIGINT ignored, and Python then
    # installs none)
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    started = time.time()
    try:
        with pytest.raises(KeyboardInterrupt):
            impact.run("plate", out=out, cells=300, reference=False, progress=on_progress)
        timer.join()
    finally:
        signal.signal(signal.SIGINT, previous)
    assert time.time() - started < 20, "the run did not stop at the interrupt"
    assert not out.exists()
    assert [p.name for p in tmp_path.iterdir() if p.name != ".plate.lock"] == []
    # the next run is unaffected by the stop flag
    assert impact.run("bar", methods=["dgmpm"], files=False).failures == []


def test_check_returns_the_cli_json(tmp_path):
    py = impact.check("bar", cells=100)
    cli("check", "bar", "--cells", "100", "--quiet", "--json", str(tmp_path / "c.json"))
    with open(tmp_path / "c.json") as f:
        doc = json.load(f)
    assert py["pass"] is True and doc["pass"] is True
    for a, b in zip(py["reports"], doc["reports"]):
        assert a["rows"] == b["rows"]
        assert a["dgmpm_times"] == b["dgmpm_times"]
    with pytest.raises(impact.SceneError) as e:
        impact.check("bar", against="quadratic")
    assert cli_message("check", "bar", "--against", "quadratic") == f"error: {e.value}"


def test_stability_returns_the_cli_rows(tmp_path):
    py = impact.stability("bar", steps_1d=300)
    cli("stability", "--scene", "bar", "--steps-1d", "300",
        "--out", str(tmp_path / "s"))
    lines = (tmp_path / "s" / "stability.csv").read_text().splitlines()
    assert len(lines) - 1 == len(py["rows"]) > 0
    assert py["table"][0].split()[:3] == ["dim", "method", "ppc"]


def test_convergence_returns_the_cli_json(tmp_path):
    py = impact.convergence("smooth-bar", levels=2)
    cli("bench", "convergence", "--scene", "smooth-bar", "--levels", "2",
        "--out", str(tmp_path / "c"))
    with open(tmp_path / "c" / "convergence.json") as f:
        doc = json.load(f)
    strip = lambda levels: [{k: v for k, v in l.items() if "wall" not in k} for l in levels]
    assert strip(py["levels"]) == strip(doc)


def test_to_pandas_has_a_row_per_method_and_time():
    pd = pytest.importorskip("pandas")
    res = impact.run("bar", files=False)
    df = res.to_pandas()
    assert len(df) == sum(len(r["times"]) for r in res.metrics)
    assert set(df["method"]) == {"dgmpm", "mpm", "fem"}


def test_stubs_name_every_native_function():
    stub = (Path(impact.__file__).parent / "_impact.pyi").read_text()
    native = [n for n in dir(impact._impact) if not n.startswith("_")]
    for name in native:
        assert f"def {name}(" in stub or f"class {name}(" in stub, name


EXAMPLES = sorted((ROOT / "examples").glob("[0-9][0-9]_*.py"))


@pytest.mark.parametrize("example", EXAMPLES, ids=[e.stem for e in EXAMPLES])
def test_example_runs(tmp_path, example):
    started = time.time()
    done = subprocess.run(
        [sys.executable, str(example), str(tmp_path)], capture_output=True, text=True,
        env={**os.environ, "MPLBACKEND": "Agg"},
    )
    assert done.returncode == 0, done.stderr
    assert list(tmp_path.glob("*.png")), "the example wrote no figure"
    assert time.time() - started < 60


def test_work_precision_returns_the_cli_json(tmp_path):
    py = impact.work_precision("bar", levels=1, exe=BIN)
    cli("bench", "work-precision", "--scene", "bar", "--levels", "1", "--out", str(tmp_path / "w"))
    with open(tmp_path / "w" / "work_precision.json") as f:
        doc = json.load(f)
    keep = ("config", "cells", "steps", "l1_rel")
    assert [{k: p[k] for k in keep} for p in py["points"]] == [{k: p[k] for k in keep} for p in doc]
    assert py["summary"].startswith("bar: L1 error")


def test_the_stepping_releases_the_gil():
    ticks, stop = [0], threading.Event()

    def count():
        while not stop.is_set():
            ticks[0] += 1
            time.sleep(0.001)

    counter = threading.Thread(target=count)
    counter.start()
    started = time.time()
    impact.run("plate", cells=400, reference=False, files=False, methods=["dgmpm"])
    elapsed = time.time() - started
    stop.set()
    counter.join()
    # a thread that waited on the GIL for the whole run would have counted ~once
    assert ticks[0] > max(3, elapsed / 0.01), (ticks[0], elapsed)
