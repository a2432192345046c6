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


def grid_cells(f, step):
    """The grid cells of `step` of an impact `.h5` series, keyed by their corners'
    positions (bits, sorted): each with its cell arrays and its corners' nodal velocity
    (FEM), as bits, so that equal is bit for bit."""
    group = f[step]
    points = group["grid_points"][:].view(np.uint64)
    connectivity = f["grid_connectivity"][:]
    stress = group["grid_cauchy_stress"][:].view(np.uint64)
    velocity = group["grid_velocity"][:].view(np.uint64)
    nodal = group["grid_nodal_velocity"][:].view(np.uint64) if "grid_nodal_velocity" in group else None
    cells = {}
    for c, vertices in enumerate(connectivity):
        corners = sorted(
            (tuple(points[v]), () if nodal is None else tuple(nodal[v])) for v in vertices
        )
        key = tuple(p for p, _ in corners)
        assert key not in cells, f"{step}: cell {c} twice"
        cells[key] = (tuple(stress[c]), tuple(velocity[c]), tuple(corners))
    return cells


@pytest.mark.skipif(os.environ.get("IMPACT_HAS_HDF5") != "1", reason="impact built without the hdf5 feature")
@pytest.mark.parametrize("ranks", [2, 3])
@pytest.mark.parametrize("method", ["dgmpm", "fem"])
def test_hdf5_grid_pieces_together_equal_the_serial_grid(mpi_ok, tmp_path, method, ranks):
    """With the `hdf5` feature every rank's `<method>_r<rank>.h5` holds its grid piece
    (FEM: its owned elements and their nodes, the node layer of a cut in both pieces
    beside it): at every step the pieces' cells together are the serial `.h5`'s, bit for
    bit, each in one piece; each rank's `<method>_r<rank>_grid.xdmf` describes its piece
    (meshio reads it: its cells and, for FEM, its nodes' velocity)."""
    import h5py

    serial = tmp_path / "serial"
    split = tmp_path / f"np{ranks}"
    run("plate", serial, method=method)
    run("plate", split, ranks=ranks, method=method)
    assert not (split / f"{method}.h5").exists()
    with h5py.File(serial / f"{method}.h5", "r") as whole:
        steps = sorted(k for k in whole if k.startswith("step_"))
        assert len(steps) >= 3, steps
        pieces = [h5py.File(split / f"{method}_r{r}.h5", "r") for r in range(ranks)]
        try:
            for step in steps:
                want = grid_cells(whole, step)
                got = {}
                for r, piece in enumerate(pieces):
                    part = grid_cells(piece, step)
                    assert part, f"rank {r}: no cell at {step}"
                    assert not got.keys() & part.keys(), f"rank {r}: a cell of another piece"
                    got.update(part)
                assert got.keys() == want.keys(), f"{step}: the pieces' cells are not the grid's"
                assert got == want, f"{step}: a cell differs"
            for r, piece in enumerate(pieces):
                cells = piece["grid_connectivity"].shape[0]
                vertices = piece["step_0/grid_points"].shape[0]
                with meshio.xdmf.TimeSeriesReader(split / f"{method}_r{r}_grid.xdmf") as reader:
                    points, blocks = reader.read_points_cells()
                    assert reader.num_steps == len(steps)
                    assert blocks[0].type == "quad" and len(blocks[0].data) == cells
                    assert len(points) == vertices
                    _, point_data, cell_data = reader.read_data(len(steps) - 1)
                    last = piece[steps[-1]]
                    np.testing.assert_array_equal(cell_data["cauchy_stress"][0], last["grid_cauchy_stress"][:])
                    if method == "fem":
                        np.testing.assert_array_equal(point_data["nodal_velocity"], last["grid_nodal_velocity"][:])
        finally:
            for piece in pieces:
                piece.close()
