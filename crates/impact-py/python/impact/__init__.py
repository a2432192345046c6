"""impact from Python: DGMPM, MPM and explicit FEM on the same stress-wave problems.

A façade over the library the ``impact`` command line uses (no second implementation):
scenes are validated by the same code, keyword overrides are the CLI's flags
(``cells=200`` is ``--cells 200``) parsed by the CLI's own definitions, runs write the
CLI's folder and return the fields as NumPy arrays. SI units throughout: m, s, Pa, m/s,
kg/m³.

    >>> import impact
    >>> res = impact.run("bar", methods=["dgmpm", "mpm"], cells=100)
    >>> f = res["dgmpm"].frames[-1]
    >>> f.position[:, 0], f.stress[:, 0, 0]      # x (m), σ_xx (Pa)

See docs/python.md for the whole reference.
"""
from __future__ import annotations

import json
import os
import shutil
import tempfile
import weakref
from pathlib import Path
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Union

from . import _impact
from ._progress import Reporter, reporting
from ._impact import SceneError, __version__

__all__ = [
    "Frame",
    "MethodResult",
    "Result",
    "Scene",
    "SceneError",
    "check",
    "convergence",
    "run",
    "scenes",
    "stability",
    "work_precision",
    "__version__",
]

METHODS = ("dgmpm", "mpm", "fem")


def scenes() -> List[str]:
    """The shipped scene names (as ``impact scenes`` prints them)."""
    return list(_impact.scenes())


def _text(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float) or type(value).__name__.startswith("float"):
        return repr(float(value))
    if isinstance(value, (list, tuple)):
        return ",".join(_text(v) for v in value)
    return str(value)


def _flags(overrides: Mapping[str, Any]) -> List[str]:
    """The CLI flags of keyword overrides: ``points_per_cell=2`` → ``--points-per-cell=2``,
    ``allow_unstable=True`` → ``--allow-unstable`` (``False`` and ``None`` leave a flag out),
    lists comma-separated (``output_times=[1e-4, 2e-4]``)."""
    flags: List[str] = []
    for key, value in overrides.items():
        if value is None or value is False:
            continue
        flag = "--" + key.replace("_", "-")
        flags.append(flag if value is True else f"{flag}={_text(value)}")
    return flags


def _no_none(value: Any) -> Any:
    """A dict without its ``None`` entries (``None`` is an absent key, as in TOML)."""
    if isinstance(value, Mapping):
        return {k: _no_none(v) for k, v in value.items() if v is not None}
    if isinstance(value, (list, tuple)):
        return [_no_none(v) for v in value]
    return value


class Scene:
    """A validated scene: a shipped one (``Scene.load("bar")``), a scene file
    (``Scene.load("my.toml")``) or a dict (``Scene.from_dict(d)``) with the same keys as
    the TOML schema (docs/scenes.md). Every default is written out in :meth:`to_dict`."""

    def __init__(self, toml: str, name: str, source: str):
        self._toml = toml
        self.name = name
        self.source = source

    @classmethod
    def load(cls, name_or_path: Union[str, "os.PathLike[str]"]) -> "Scene":
        """A shipped scene name (:func:`scenes`) or a path to a ``.toml`` scene file.

        Raises :class:`SceneError` with the CLI's message on an unknown name or a bad field."""
        source = os.fspath(name_or_path)
        toml, name = _impact.scene_load(source)
        return cls(toml, name, source)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], origin: str = "<dict>") -> "Scene":
        """A scene from a dict shaped like the TOML file; validated as a file is (errors
        name the field, the value and what is allowed)."""
        toml, name = _impact.scene_from_json(json.dumps(_no_none(data)), origin)
        return cls(toml, name, origin)

    def to_dict(self) -> Dict[str, Any]:
        """The scene as a dict, every default written out (a deep copy: edit it and
        :meth:`from_dict` it back)."""
        return json.loads(_impact.scene_to_json(self._toml))

    def to_toml(self) -> str:
        """The scene as TOML text (what ``scene.toml`` of a run folder holds)."""
        return self._toml

    def with_overrides(self, **overrides: Any) -> "Scene":
        """The scene with the CLI's scene flags applied (``cells``, ``t_end`` (s),
        ``load_magnitude`` (Pa or m/s), ...) and validated again; method options are
        kept by :func:`run`, not by the scene."""
        toml, name = _impact.scene_with(self._toml, self.source, _flags(overrides))
        return Scene(toml, name, self.source)

    @property
    def dim(self) -> int:
        """Dimension (1, 2 or 3)."""
        return int(self.to_dict()["dim"])

    def __repr__(self) -> str:
        return f"Scene({self.name!r}, source={self.source!r})"


def _scene(scene: Union[str, "os.PathLike[str]", Scene, Mapping[str, Any]]) -> Scene:
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, Mapping):
        return Scene.from_dict(scene)
    return Scene.load(scene)


from ._result import Frame, MethodResult, Result  # noqa: E402


def run(
    scene: Union[str, "os.PathLike[str]", Scene, Mapping[str, Any]],
    methods: Sequence[str] = METHODS,
    *,
    out: Optional[Union[str, "os.PathLike[str]"]] = None,
    files: bool = True,
    reference: bool = True,
    vtu: str = "binary",
    progress: Union[bool, Reporter] = False,
    **overrides: Any,
) -> Result:
    """Run ``scene`` with ``methods`` (``"dgmpm"``, ``"mpm"``, ``"fem"``), as
    ``impact run <scene> --method <methods> [flags]`` does, in this process.

    ``overrides`` are the CLI's scene and method flags with underscores: ``cells``,
    ``courant``, ``points_per_cell``, ``integrator``, ``shape``, ``order``, ``t_end`` (s),
    ``output_times`` (s), ``load_magnitude``, ``yield_stress`` (Pa), ``allow_unstable``, ...
    (docs/cli.md). ``out``: the output folder (default: a temporary folder kept while the
    result lives; :meth:`Result.write` copies it). ``files=False`` is ``--no-files`` (only
    summary.json, provenance.json, scene.toml); ``reference=False`` is ``--no-reference``;
    ``vtu`` is ``"binary"`` or ``"ascii"``; ``progress=True`` shows a bar per method (and
    the reference): tqdm's (a widget in a notebook) when tqdm is installed, else a line on
    stderr per tenth; ``progress=<callable>`` receives the updates
    ``[(index, label, fraction, finished), ...]`` a few times a second instead.

    The stepping runs with the GIL released; Ctrl-C (``KeyboardInterrupt``) stops it between
    two steps and leaves ``out`` as it was. A run the stability guard stopped returns its
    result with ``failures`` set (the CLI exits 3). Bad input raises :class:`SceneError`
    with the CLI's message."""
    if vtu not in ("binary", "ascii"):
        raise SceneError(
            f"invalid value '{vtu}' for '--vtu <VTU>'\n  [possible values: binary, ascii]"
        )
    the_scene = _scene(scene)
    flags = _flags(overrides)
    methods = [methods] if isinstance(methods, str) else list(methods)
    flags.append("--method=" + ",".join(methods))
    keep: Optional[str] = None
    if out is None:
        keep = tempfile.mkdtemp(prefix="impact-")
        folder = Path(keep) / the_scene.name
    else:
        folder = Path(out)
    try:
        with reporting(progress) as drawer:
            raw = _impact.run(
                the_scene._toml,
                the_scene.source,
                flags,
                str(folder),
                files,
                reference,
                vtu == "ascii",
                drawer,
            )
    except BaseException:
        if keep is not None:
            shutil.rmtree(keep, ignore_errors=True)
        raise
    result = Result(the_scene, raw, folder)
    if keep is not None:
        weakref.finalize(result, shutil.rmtree, keep, True)
    return result


def _json_in(folder: Path, name: str) -> Any:
    with open(folder / name, encoding="utf-8") as f:
        return json.load(f)


class _Folder:
    """The output folder of a command: ``out`` or a temporary one removed on exit."""

    def __init__(self, out: Optional[Union[str, "os.PathLike[str]"]], name: str):
        self.keep = None if out is not None else tempfile.mkdtemp(prefix="impact-")
        self.path = Path(out) if out is not None else Path(self.keep) / name

    def __enter__(self) -> "_Folder":
        return self

    def __exit__(self, *exc: Any) -> None:
        if self.keep is not None:
            shutil.rmtree(self.keep, ignore_errors=True)


def check(
    scene: Union[str, "os.PathLike[str]", Scene, Mapping[str, Any]],
    *,
    against: Optional[str] = None,
    dgmpm_courant: Optional[float] = None,
    mpm_courant: Optional[float] = None,
    dgmpm_points_per_cell: Optional[int] = None,
    mpm_points_per_cell: Optional[int] = None,
    min_width_ratio: float = 1.0,
    max_overshoot: Optional[float] = None,
    progress: Union[bool, Reporter] = False,
    **overrides: Any,
) -> Dict[str, Any]:
    """``impact check``: DGMPM against MPM at every output time. Returns the document the
    CLI writes with ``--json`` (``pass``, ``thresholds``, ``reports`` with each time's front
    widths (m) and overshoots (% of the jump), ``provenance``). ``progress`` as in
    :func:`run`."""
    the_scene = _scene(scene)
    gate = dict(
        against=against,
        dgmpm_courant=dgmpm_courant,
        mpm_courant=mpm_courant,
        dgmpm_points_per_cell=dgmpm_points_per_cell,
        mpm_points_per_cell=mpm_points_per_cell,
        min_width_ratio=min_width_ratio,
        max_overshoot=max_overshoot,
    )
    flags = _flags(overrides) + _flags(gate)
    with _Folder(None, "check") as folder:
        folder.path.mkdir()
        path = folder.path / "check.json"
        with reporting(progress) as drawer:
            _impact.check(the_scene._toml, the_scene.source, flags, str(path), drawer)
        return _json_in(folder.path, "check.json")


def convergence(
    scene: Union[str, "os.PathLike[str]", Scene, Mapping[str, Any]] = "smooth-bar",
    *,
    levels: int = 4,
    out: Optional[Union[str, "os.PathLike[str]"]] = None,
    **overrides: Any,
) -> Dict[str, Any]:
    """``impact bench convergence``: observed orders on a smooth exact solution. Returns
    ``{"table": <the printed table>, "levels": <convergence.json>}``; ``out`` keeps the
    CLI's folder (convergence.{csv,json,png,txt})."""
    the_scene = _scene(scene)
    with _Folder(out, "convergence") as folder:
        table = _impact.convergence(
            the_scene._toml, the_scene.source, _flags(overrides), levels, str(folder.path)
        )
        return {"table": table, "levels": _json_in(folder.path, "convergence.json")}


def work_precision(
    scene: Union[str, "os.PathLike[str]", Scene, Mapping[str, Any]] = "bar",
    *,
    levels: Optional[int] = None,
    out: Optional[Union[str, "os.PathLike[str]"]] = None,
    exe: Optional[Union[str, "os.PathLike[str]"]] = None,
    **overrides: Any,
) -> Dict[str, Any]:
    """``impact bench work-precision``: wall time against error over a refinement ladder.
    Each point is a separate ``impact run`` process (its own timing and peak memory), so
    the ``impact`` executable is needed: ``exe``, else ``$IMPACT_BIN``, else ``impact`` on
    the PATH. Returns ``{"summary": <sentence>, "points": <work_precision.json>}``."""
    program = exe or os.environ.get("IMPACT_BIN") or shutil.which("impact")
    if not program:
        raise SceneError(
            "work_precision needs the `impact` executable (each point is a timed `impact "
            "run` process): pass exe=..., set IMPACT_BIN, or `cargo install --path .`"
        )
    the_scene = _scene(scene)
    with _Folder(out, "work-precision") as folder:
        sentence = _impact.work_precision(
            str(program), the_scene._toml, the_scene.source, _flags(overrides), levels,
            str(folder.path),
        )
        return {"summary": sentence, "points": _json_in(folder.path, "work_precision.json")}


def stability(
    scene: Optional[Union[str, "os.PathLike[str]"]] = None,
    *,
    dim: Optional[Iterable[int]] = None,
    steps_1d: int = 20000,
    steps_2d: int = 3000,
    layout: Optional[str] = None,
    shift: Optional[float] = None,
    positions: Optional[Sequence[float]] = None,
    out: Optional[Union[str, "os.PathLike[str]"]] = None,
    **overrides: Any,
) -> Dict[str, Any]:
    """``impact stability``: critical Courant numbers (empirical, von Neumann, monotone)
    of every configuration. ``scene`` is a shipped name or a file (default: the sweep
    scenes). Returns ``{"table": <printed lines>, "rows": [...], "provenance": {...}}``."""
    source = None if scene is None else os.fspath(scene)
    with _Folder(out, "stability") as folder:
        lines, rows = _impact.stability(
            source,
            None if dim is None else list(dim),
            _flags(overrides),
            steps_1d,
            steps_2d,
            str(folder.path),
            layout,
            shift,
            None if positions is None else [float(p) for p in positions],
        )
        return {
            "table": lines,
            "rows": json.loads(rows),
            "provenance": _json_in(folder.path, "provenance.json"),
        }
