"""The compressed binary `.vtu` files (the default `--vtu binary`) read back by meshio and
pyvista: the same values as the ASCII files of the same run (to their 13 digits) and, when
impact was built with the `hdf5` feature, bit for bit the `.h5` series (1e-15 relative);
every frame carries its `TimeValue` and units; the `.pvd` collections start at t = 0;
meshio reads the `.xdmf` time series.
"""
import os
import subprocess
import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest
import pyvista as pv
from conftest import impact_bin

pv.OFF_SCREEN = True
METHODS = ["dgmpm", "mpm", "fem"]
HAS_HDF5 = os.environ.get("IMPACT_HAS_HDF5") == "1"


@pytest.fixture(scope="module")
def ascii_out(tmp_path_factory):
    out = tmp_path_factory.mktemp("plate-ascii")
    subprocess.run([impact_bin(), "run", "plate", "--quiet", "--vtu", "ascii", "--out", str(out)],
                   check=True, stdout=subprocess.DEVNULL)
    return out


def xml_header(path):
    """The XML part of a `.vtu` (its raw appended section is not XML)."""
    raw = path.read_bytes()
    cut = raw.find(b"<AppendedData")
    if cut < 0:
        return ET.fromstring(raw)
    return ET.fromstring(raw[:cut] + b"</VTKFile>")


def frames(folder, method):
    return [f"{method}_t{k}.vtu" for k in range(3)] + [f"{method}_grid_t{k}.vtu" for k in range(3)]


@pytest.mark.parametrize("method", METHODS)
def test_binary_files_hold_the_ascii_values(plate_out, ascii_out, method):
    for name in frames(plate_out, method):
        assert b'compressor="vtkZLibDataCompressor"' in (plate_out / name).read_bytes()[:400]
        binary, text = meshio.read(plate_out / name), meshio.read(ascii_out / name)
        np.testing.assert_allclose(binary.points, text.points, rtol=1e-12, atol=1e-14)
        for key in text.point_data:
            b, a = binary.point_data[key], text.point_data[key]
            np.testing.assert_allclose(b, a, rtol=1e-12, atol=1e-12 * max(np.abs(a).max(), 1e-300))
        for key in text.cell_data:
            b, a = binary.cell_data[key][0], text.cell_data[key][0]
            np.testing.assert_allclose(b, a, rtol=1e-12, atol=1e-12 * max(np.abs(a).max(), 1e-300))
        # pyvista (VTK's own reader) agrees with meshio exactly
        grid = pv.read(plate_out / name)
        np.testing.assert_array_equal(np.asarray(grid.points), binary.points)


@pytest.mark.parametrize("method", METHODS)
def test_frames_carry_time_and_units_and_the_pvd_starts_at_zero(plate_out, plate_summary, method):
    times = [t["t"] for t in next(r for r in plate_summary["runs"] if r["method"] == method)["times"]]
    for k, t in enumerate(times):
        for name in [f"{method}_t{k}.vtu", f"{method}_grid_t{k}.vtu"]:
            grid = pv.read(plate_out / name)
            assert abs(grid.field_data["TimeValue"][0] - t) <= 1e-15 * t
            root = xml_header(plate_out / name)
            units = {a.get("Name"): a.get("units") for a in root.iter("DataArray")}
            assert units["Points"] == "m" and units["cauchy_stress"] == "Pa"
            assert units["velocity"] == "m/s" and units["TimeValue"] == "s"
    for pvd in [f"{method}.pvd", f"{method}_grid.pvd"]:
        steps = [(float(d.get("timestep")), d.get("file"))
                 for d in ET.parse(plate_out / pvd).getroot().iter("DataSet")]
        assert steps[0][0] == 0.0 and "initial" in steps[0][1]
        np.testing.assert_allclose([s[0] for s in steps[1:]], times, rtol=1e-12)
        initial = pv.read(plate_out / steps[0][1])
        # unstressed before the impact (MPM already holds its impacted points at the
        # impact velocity)
        assert np.abs(np.asarray(initial["cauchy_stress"])).max() == 0.0


@pytest.mark.skipif(not HAS_HDF5, reason="impact built without the hdf5 feature")
@pytest.mark.parametrize("method", METHODS)
def test_binary_vtu_equals_the_hdf5_series_and_meshio_reads_the_xdmf(plate_out, method):
    import h5py

    with h5py.File(plate_out / f"{method}.h5", "r") as f:
        for k in range(3):
            samples = meshio.read(plate_out / f"{method}_t{k}.vtu")
            step = f[f"step_{k}"]
            assert step["cauchy_stress"].attrs["units"] == "Pa"
            for key, got in [("points", samples.points),
                             ("cauchy_stress", samples.point_data["cauchy_stress"]),
                             ("velocity", samples.point_data["velocity"])]:
                want = step[key][:]
                np.testing.assert_allclose(got, want, rtol=1e-15, atol=0)
    with meshio.xdmf.TimeSeriesReader(plate_out / f"{method}.xdmf") as reader:
        points, cells = reader.read_points_cells()
        assert cells[0].type == "vertex" and len(cells[0].data) == len(points)
        assert reader.num_steps == 3
        for k in range(reader.num_steps):
            t, point_data, _ = reader.read_data(k)
            samples = meshio.read(plate_out / f"{method}_t{k}.vtu")
            assert abs(t - float(pv.read(plate_out / f"{method}_t{k}.vtu").field_data["TimeValue"][0])) <= 1e-15 * t
            np.testing.assert_array_equal(point_data["cauchy_stress"], samples.point_data["cauchy_stress"])
