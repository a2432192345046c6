"""Shared fixtures: run `impact run plate` once and hand its output folder to the tests."""
import json
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent


def impact_bin() -> str:
    return os.environ.get("IMPACT_BIN", str(ROOT / "target" / "release" / "impact"))


@pytest.fixture(scope="session")
def plate_out(tmp_path_factory) -> pathlib.Path:
    out = tmp_path_factory.mktemp("plate")
    subprocess.run([impact_bin(), "run", "plate", "--quiet", "--out", str(out)], check=True,
                   stdout=subprocess.DEVNULL)
    return out


@pytest.fixture(scope="session")
def plate_summary(plate_out) -> dict:
    return json.loads((plate_out / "summary.json").read_text())


def read_csv(path: pathlib.Path) -> dict:
    import numpy as np
    lines = path.read_text().splitlines()
    header = lines[0].split(",")
    data = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    return {name: data[:, k] for k, name in enumerate(header)}
