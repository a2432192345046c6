"""Cross-check of impact's VTK (and HDF5) output with pyvista (off-screen) and h5py.

pyvista reads the grid files (the FEM mesh and the DGMPM/MPM Eulerian grid cells), samples
sigma_xx over a line through the bottom row of cells (`sample_over_line`) and must find the
CSV profiles; the sample files must hold the same values. When impact was built with the
`hdf5` feature (IMPACT_HAS_HDF5=1), the `.h5` time series read by h5py must match the
`.vtu` samples and the `.xdmf` must list every step.
"""
import os

import numpy as np
import pytest
import pyvista as pv
from conftest import read_csv

pv.OFF_SCREEN = True
L, H, NX, NY = 4.0, 3.0, 33, 25
METHODS = ["dgmpm", "mpm", "fem"]


@pytest.mark.parametrize("method", METHODS)
def test_grid_sampled_over_the_bottom_row_matches_the_csv(plate_out, method):
    dx, dy = L / NX, H / NY
    for k in range(3):
        grid = pv.read(plate_out / f"{method}_grid_t{k}.vtu")
        assert grid.n_cells == NX * NY
        line = grid.sample_over_line((0.5 * dx, 0.5 * dy, 0.0), (L - 0.5 * dx, 0.5 * dy, 0.0),
                                     resolution=NX - 1)
        sampled = np.asarray(line["cauchy_stress"])[:, 0]
        profile = read_csv(plate_out / f"{method}_t{k}.csv")
        scale = np.abs(profile["cauchy_stress_xx"]).max()
        assert scale > 1e7
        np.testing.assert_allclose(sampled, profile["cauchy_stress_xx"], rtol=0, atol=1e-10 * scale)


@pytest.mark.parametrize("method", METHODS)
def test_sample_files_match_the_csv(plate_out, method):
    for k in range(3):
        points = pv.read(plate_out / f"{method}_t{k}.vtu")
        ref = np.asarray(points["reference_position"])
        bottom = ref[:, 1] <= ref[:, 1].min() + 1e-9
        order = np.argsort(ref[bottom, 0])
        sxx = np.asarray(points["cauchy_stress"])[bottom, 0][order]
        profile = read_csv(plate_out / f"{method}_t{k}.csv")
        np.testing.assert_allclose(ref[bottom, 0][order], profile["x"], rtol=0, atol=1e-12)
        np.testing.assert_allclose(sxx, profile["cauchy_stress_xx"], rtol=1e-11, atol=1e-3)
        # every component and the coordinates of the measured line, and the reference solution
        # under the same name in both files
        np.testing.assert_allclose(ref[bottom, 1][order], profile["y"], rtol=0, atol=1e-12)
        syy = np.asarray(points["cauchy_stress"])[bottom, 4][order]
        np.testing.assert_allclose(syy, profile["cauchy_stress_yy"], rtol=1e-11, atol=1e-3)
        vy = np.asarray(points["velocity"])[bottom, 1][order]
        np.testing.assert_allclose(vy, profile["velocity_y"], rtol=1e-11, atol=1e-12)
        exact = np.asarray(points["reference_cauchy_stress_xx"])[bottom][order]
        np.testing.assert_allclose(exact, profile["reference_cauchy_stress_xx"], rtol=1e-11, atol=1e-3)


@pytest.mark.skipif(os.environ.get("IMPACT_HAS_HDF5") != "1", reason="impact built without the hdf5 feature")
@pytest.mark.parametrize("method", METHODS)
def test_hdf5_series_matches_the_vtu_samples(plate_out, plate_summary, method):
    import h5py

    h5 = plate_out / f"{method}.h5"
    xdmf = (plate_out / f"{method}.xdmf").read_text()
    times = [t["t"] for t in next(r for r in plate_summary["runs"] if r["method"] == method)["times"]]
    with h5py.File(h5, "r") as f:
        assert len([k for k in f.keys() if k.startswith("step_")]) == len(times)
        for k, t in enumerate(times):
            step = f[f"step_{k}"]
            assert abs(step.attrs["time"] - t) <= 1e-12 * t
            points = pv.read(plate_out / f"{method}_t{k}.vtu")
            np.testing.assert_allclose(step["points"][:], np.asarray(points.points), rtol=1e-11, atol=1e-12)
            np.testing.assert_allclose(step["cauchy_stress"][:], np.asarray(points["cauchy_stress"]), rtol=1e-11, atol=1e-3)
            np.testing.assert_allclose(step["velocity"][:], np.asarray(points["velocity"]), rtol=1e-11, atol=1e-12)
            assert f"{h5.name}:/step_{k}/cauchy_stress" in xdmf


def _grid_series_matches_the_vtu_grids(out, method, cell_type, cells):
    """`<method>_grid.xdmf` read by meshio's XDMF reader: every step's cells (of the XDMF
    topology `cell_type`), points and cell fields equal the `<method>_grid_t<k>.vtu` ones."""
    import meshio

    reader = meshio.xdmf.TimeSeriesReader(out / f"{method}_grid.xdmf")
    points, blocks = reader.read_points_cells()
    assert [b.type for b in blocks] == [cell_type]
    assert len(blocks[0].data) == cells
    assert reader.num_steps >= 1
    for k in range(reader.num_steps):
        _, _, cell_data = reader.read_data(k)
        vtu = pv.read(out / f"{method}_grid_t{k}.vtu")
        np.testing.assert_array_equal(blocks[0].data.ravel(), vtu.cells.reshape(-1, blocks[0].data.shape[1] + 1)[:, 1:].ravel())
        if k == 0:
            np.testing.assert_allclose(points, np.asarray(vtu.points), rtol=1e-12, atol=1e-12)
        stress = cell_data["cauchy_stress"][0]
        scale = max(np.abs(stress).max(), 1.0)
        assert scale > 1e6, "the grid carries the wave's stress"
        np.testing.assert_allclose(stress, np.asarray(vtu.cell_data["cauchy_stress"]), rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(cell_data["velocity"][0], np.asarray(vtu.cell_data["velocity"]), rtol=0, atol=1e-12)


@pytest.mark.skipif(os.environ.get("IMPACT_HAS_HDF5") != "1", reason="impact built without the hdf5 feature")
@pytest.mark.parametrize("method", METHODS)
def test_hdf5_grid_series_of_the_plate_is_quadrilaterals(plate_out, method):
    _grid_series_matches_the_vtu_grids(plate_out, method, "quad", NX * NY)


@pytest.mark.skipif(os.environ.get("IMPACT_HAS_HDF5") != "1", reason="impact built without the hdf5 feature")
@pytest.mark.parametrize("method", METHODS)
def test_hdf5_grid_series_of_a_block_is_hexahedra(tmp_path_factory, method):
    import subprocess

    from conftest import impact_bin

    out = tmp_path_factory.mktemp(f"block_{method}")
    subprocess.run([impact_bin(), "run", "block-wave", "--quiet", "--method", method, "--out", str(out)],
                   check=True, stdout=subprocess.DEVNULL)
    _grid_series_matches_the_vtu_grids(out, method, "hexahedron", 32 * 4 * 4)
