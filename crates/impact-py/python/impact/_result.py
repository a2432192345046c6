"""The result of :func:`impact.run`: fields per method and output time as NumPy arrays,
the metrics of ``summary.json``, and the run's folder."""
from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any, Dict, Iterator, List, Optional, Union

import numpy as np

from . import _impact


class Frame:
    """One method's fields at one output time. ``n`` samples (material points for DGMPM
    and MPM, element centres for FEM); SI units.

    Attributes:
        index: output index (the CLI's ``<method>_t<index>`` files).
        t: time (s).
        reference_position: ``(n, dim)`` reference (material) position X (m).
        position: ``(n, dim)`` current position x (m).
        half_size: ``(n, dim)`` half-size of each sample's region in the reference
            configuration (m).
        velocity: ``(n, dim)`` velocity (m/s).
        stress: ``(n, dim, dim)`` stress (Pa): Cauchy σ in small strain, first
            Piola–Kirchhoff Π under Saint-Venant–Kirchhoff (``stress_name`` says which).
        stress_zz: ``(n,)`` out-of-plane σ_zz (Pa) where the model sets it (J2 in 2D), else None.
        plastic_strain: ``(n,)`` equivalent plastic strain (J2), else None.
        reference_stress_xx, reference_velocity_x: ``(n,)`` the reference solution (exact,
            or converged in 2D) averaged over each sample's region: σ_xx (Pa), v_x (m/s);
            None when run with ``reference=False``.
        profile: the CSV profile along the measuring line, ``{column: array}`` with the
            CLI's column names (``x``, ``x_current``, ``cauchy_stress_xx``, ...).
        map: 2D and 3D: σ_xx (Pa) averaged per grid cell of the map's plane (NaN where no
            sample lies), flat in the grid's cell order; None in 1D.
    """

    def __init__(self, raw: Dict[str, Any], stress_name: str):
        self.index: int = raw["index"]
        self.t: float = raw["t"]
        self.stress_name = stress_name
        self.reference_position: np.ndarray = raw["reference"]
        self.position: np.ndarray = raw["position"]
        self.half_size: np.ndarray = raw["half_size"]
        self.velocity: np.ndarray = raw["velocity"]
        self.stress: np.ndarray = raw["stress"]
        self.stress_zz: Optional[np.ndarray] = raw["stress_zz"]
        self.plastic_strain: Optional[np.ndarray] = raw["plastic_strain"]
        self.reference_stress_xx: Optional[np.ndarray] = raw["reference_stress_xx"]
        self.reference_velocity_x: Optional[np.ndarray] = raw["reference_velocity_x"]
        self.profile: Dict[str, np.ndarray] = dict(raw["profile"])
        self.map: Optional[np.ndarray] = raw["map"]

    def __repr__(self) -> str:
        return f"Frame(t={self.t:.6e} s, samples={len(self.stress)})"


class MethodResult:
    """One method's run: ``frames`` (one :class:`Frame` per output time reached) and
    ``metrics`` (its record of ``summary.json``: options, steps, wall time (s) and per time
    errors, front width (m), overshoot (%), energy (J))."""

    def __init__(self, raw: Dict[str, Any], metrics: Dict[str, Any]):
        self.method: str = raw["method"]
        self.stress_name: str = raw["stress_name"]
        self.frames: List[Frame] = [Frame(f, self.stress_name) for f in raw["frames"]]
        self.metrics = metrics

    @property
    def times(self) -> List[float]:
        """The output times reached (s)."""
        return [f.t for f in self.frames]

    def __repr__(self) -> str:
        return f"MethodResult({self.method!r}, frames={len(self.frames)})"


class Result:
    """What :func:`impact.run` returns. ``result["dgmpm"]`` is a :class:`MethodResult`;
    ``result.metrics`` the ``runs`` records of ``summary.json``; ``result.summary`` the
    whole file; ``result.reference`` the reference in words; ``result.failures`` the
    blow-ups that stopped runs (empty when all completed); ``result.folder`` the run's
    folder."""

    def __init__(self, scene: Any, raw: Dict[str, Any], folder: Path):
        self.scene = scene
        self.folder = Path(folder)
        with open(self.folder / "summary.json", encoding="utf-8") as f:
            self.summary: Dict[str, Any] = json.load(f)
        self.metrics: List[Dict[str, Any]] = self.summary["runs"]
        self.reference: str = raw["reference"]
        self.failures: List[str] = list(raw["failures"])
        by_method = {m["method"]: m for m in self.metrics}
        self.methods: Dict[str, MethodResult] = {
            m["method"]: MethodResult(m, by_method.get(m["method"], {})) for m in raw["fields"]
        }

    def __getitem__(self, method: str) -> MethodResult:
        return self.methods[method]

    def __iter__(self) -> Iterator[MethodResult]:
        return iter(self.methods.values())

    def to_pandas(self) -> Any:
        """The metrics as a pandas DataFrame: one row per method and output time, the
        method's options and the time's metrics as columns (nested keys joined by ``.``).
        Needs pandas (``pip install pandas``)."""
        try:
            import pandas as pd
        except ImportError as e:  # pragma: no cover - depends on the environment
            raise ImportError("Result.to_pandas needs pandas: pip install pandas") from e
        rows = []
        for record in self.metrics:
            base = {k: v for k, v in record.items() if k not in ("times", "options")}
            base.update({f"options.{k}": v for k, v in record.get("options", {}).items()})
            for time in record.get("times", []):
                rows.append({**base, **time})
        return pd.json_normalize(rows)

    def write(self, folder: Union[str, "os.PathLike[str]"]) -> Path:
        """Write the run's files (what ``impact run`` writes with the same options) into
        ``folder``, as one complete output folder: an existing impact folder is replaced
        as a whole, any other existing folder is refused."""
        target = Path(folder)
        if target.resolve() != self.folder.resolve():
            _impact.publish(str(self.folder), str(target))
        return target

    def __repr__(self) -> str:
        return f"Result({self.scene.name!r}, methods={list(self.methods)})"
