"""Cross-check of the per-rank pieces (issue 27) with pyvista and meshio.

DGMPM, MPM and FEM on the plate (and the J2 plate, whose pieces carry the plastic strain)
under `mpirun -np N`, N = 2 and 3, write each samples frame as N pieces
`<method>_t<k>_r<r>.vtu` listed in rank order by `<method>_t<k>.pvtu`, and `<method>.pvd`
lists the `.pvtu` files. The
pieces' arrays concatenated in rank order (meshio, piece by piece) and the `.pvtu` read
whole (pyvista, VTK's reader) must equal the serial run's `<method>_t<k>.vtu` arrays exactly
(every method's default path is bit for bit on slabs: docs/mpi.md). Skipped without
`mpirun` or when the binary was built without the `mpi` feature (its summary.json then
has no `ranks`).
"""
import json
import os
import re
import shutil
import subprocess

import meshio
import numpy as np
import pytest
import pyvista as pv
from conftest import impact_bin

pv.OFF_SCREEN = True
MPIRUN = ["mpirun", "--oversubscribe", "--allow-run-as-root"]
ENV = dict(os.environ, RAYON_NUM_THREADS="1")


def piece_arrays(mesh):
    """A VTK piece as meshio-like points and point data (NumPy arrays)."""

    class Piece:
        points = np.asarray(mesh.points)
        point_data = {name: np.asarray(mesh.point_data[name]) for name in mesh.point_data}

    return Piece


def run(scene, out, ranks=None, method="dgmpm"):
    command = [impact_bin(), "run", scene, "--method", method, "--quiet", "--out", str(out)]
    if ranks is not None:
        command = [*MPIRUN, "-np", str(ranks), *command]
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, env=ENV, timeout=300)
    return json.loads((out / "summary.json").read_text())


@pytest.fixture(scope="module")
def mpi_ok(tmp_path_factory):
    if shutil.which("mpirun") is None:
        pytest.skip("no mpirun")
    out = tmp_path_factory.mktemp("probe")
    summary = run("bar", out, ranks=2)
    if summary["runs"][0].get("ranks") != 2:
        pytest.skip("impact built without the mpi feature")
    return True


@pytest.mark.parametrize("scene", ["plate", "ep-plate"])
@pytest.mark.parametrize("ranks", [2, 3])
@pytest.mark.parametrize("method", ["dgmpm", "mpm", "fem"])
def test_pieces_concatenated_equal_the_serial_frames(mpi_ok, tmp_path, scene, ranks, method):
    serial = tmp_path / "serial"
    split = tmp_path / f"np{ranks}"
    run(scene, serial, method=method)
    run(scene, split, ranks=ranks, method=method)
    frames = sorted(p.stem for p in serial.glob(f"{method}_t*.vtu"))
    assert len(frames) >= 3, frames
    pvd = (split / f"{method}.pvd").read_text()
    listed = re.findall(r'file="([^"]+)"', pvd)
    assert listed == [f"{method}_initial.pvtu"] + [f"{f}.pvtu" for f in frames], listed
    for frame in frames:
        whole = meshio.read(serial / f"{frame}.vtu")
        pvtu = (split / f"{frame}.pvtu").read_text()
        sources = re.findall(r'Source="([^"]+)"', pvtu)
        assert sources == [f"{frame}_r{r}.vtu" for r in range(ranks)], sources
        assert not (split / f"{frame}.vtu").exists()
        # (VTK's reader: meshio 5.3 refuses some valid zlib raw-appended pieces, which VTK
        # and ParaView read; the serial file is read with both below)
        pieces = [piece_arrays(pv.read(split / s)) for s in sources]
        assert all(len(p.points) > 0 for p in pieces)
        assert sum(len(p.points) for p in pieces) == len(whole.points)
        np.testing.assert_array_equal(np.concatenate([p.points for p in pieces]), whole.points)
        assert set(pieces[0].point_data) == set(whole.point_data)
        for name, values in whole.point_data.items():
            joined = np.concatenate([p.point_data[name] for p in pieces])
            np.testing.assert_array_equal(
                joined.reshape(values.shape), values, err_msg=f"{scene} {frame} {name}"
            )
        # VTK's parallel reader sees the same points and arrays, in the same order
        merged = pv.read(split / f"{frame}.pvtu")
        reference = pv.read(serial / f"{frame}.vtu")
        assert merged.n_points == reference.n_points
        np.testing.assert_array_equal(np.asarray(merged.points), np.asarray(reference.points))
        for name in reference.point_data:
            np.testing.assert_array_equal(np.asarray(merged[name]), np.asarray(reference[name]))
