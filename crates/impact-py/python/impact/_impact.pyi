# Type stubs of the native module `impact._impact` (crates/impact-py/src/lib.rs). The
# public API is `impact` (python/impact/__init__.py); these are its building blocks.
from typing import Any, Callable, Dict, List, Optional, Tuple

__version__: str

class SceneError(ValueError):
    """A scene, flag or option the CLI would refuse; the message is the CLI's."""

def scenes() -> List[str]: ...
def scene_load(source: str) -> Tuple[str, str]: ...
def scene_to_json(text: str) -> str: ...
def scene_from_json(text: str, origin: str) -> Tuple[str, str]: ...
def scene_with(text: str, source: str, flags: List[str]) -> Tuple[str, str]: ...
def run(
    text: str,
    source: str,
    flags: List[str],
    out: str,
    files: bool,
    reference: bool,
    ascii: bool,
    progress: Optional[Callable[[List[Tuple[int, str, float, bool]]], None]],
) -> Dict[str, Any]: ...
def check(
    text: str,
    source: str,
    flags: List[str],
    json: str,
    progress: Optional[Callable[[List[Tuple[int, str, float, bool]]], None]],
) -> bool: ...
def convergence(text: str, source: str, flags: List[str], levels: int, out: str) -> str: ...
def work_precision(
    exe: str, text: str, source: str, flags: List[str], levels: Optional[int], out: str
) -> str: ...
def stability(
    scene: Optional[str],
    dim: Optional[List[int]],
    flags: List[str],
    steps_1d: int,
    steps_2d: int,
    out: str,
    layout: Optional[str],
    shift: Optional[float],
    positions: Optional[List[float]],
) -> Tuple[List[str], str]: ...
def publish(from_: str, to: str) -> None: ...
