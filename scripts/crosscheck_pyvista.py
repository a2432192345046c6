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
        ref = np.asarray(points["reference"])
        bottom = ref[:, 1] <= ref[:, 1].min() + 1e-9
        order = np.argsort(ref[bottom, 0])
        sxx = np.asarray(points["cauchy_stress"])[bottom, 0][order]
        profile = read_csv(plate_out / f"{method}_t{k}.csv")
        np.testing.assert_allclose(ref[bottom, 0][order], profile["x"], rtol=0, atol=1e-12)
        np.testing.assert_allclose(sxx, profile["cauchy_stress_xx"], rtol=1e-11, atol=1e-3)


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
