"""Progress of a run in Python: the native layer calls a reporter a few times a second
(at most every 0.2 s, on the thread that called ``impact.run``, never from the step loop)
with the state of every bar the run has created so far:
``[(index, label, fraction, finished), ...]``, ``label`` a method name or
``"reference"``, ``fraction`` in [0, 1] (``t / t_end``), ``finished`` once that part
ended.

``progress=True`` draws them with tqdm when it is importable (``tqdm.auto``: the widget in
a Jupyter notebook, a text bar in a terminal), else prints a line to ``sys.stderr`` when a
bar starts, passes each tenth and finishes (indicatif, the CLI's bars, draws nothing when
stderr is not a terminal, as in a notebook). ``progress=<callable>`` receives the updates
itself."""
from __future__ import annotations

import contextlib
import sys
from typing import Any, Callable, Dict, Iterator, List, Optional, Set, Tuple, Union

Update = Tuple[int, str, float, bool]
Reporter = Callable[[List[Update]], None]

#: ticks of a tqdm bar (the native bars count t / t_end in thousandths)
_TICKS = 1000


class _Tqdm:
    """One tqdm bar per native bar, closed when it finishes."""

    def __init__(self, tqdm: Any):
        self.tqdm = tqdm
        self.bars: Dict[int, Any] = {}
        self.closed: Set[int] = set()

    def __call__(self, updates: List[Update]) -> None:
        for index, label, fraction, finished in updates:
            if index in self.closed:
                continue
            bar = self.bars.get(index)
            if bar is None:
                bar = self.tqdm(total=_TICKS, desc=f"{label:>9}", file=sys.stderr)
                self.bars[index] = bar
            ticks = int(round(fraction * _TICKS))
            if ticks > bar.n:
                bar.update(ticks - bar.n)
            if finished:
                bar.close()
                self.closed.add(index)

    def close(self) -> None:
        """Close the bars of a run that stopped early (interrupted, failed)."""
        for index, bar in self.bars.items():
            if index not in self.closed:
                bar.close()
                self.closed.add(index)


class _Lines:
    """A plain line on ``sys.stderr`` when a bar starts, passes a tenth, and finishes."""

    def __init__(self) -> None:
        self.tenths: Dict[int, int] = {}

    def __call__(self, updates: List[Update]) -> None:
        for index, label, fraction, finished in updates:
            tenth = 10 if finished else int(fraction * 10)
            if self.tenths.get(index) == tenth:
                continue
            self.tenths[index] = tenth
            state = "done" if finished else f"{int(fraction * 100):3d}%"
            print(f"{label:>9} {state}", file=sys.stderr, flush=True)


def reporter(progress: Union[bool, Reporter, None]) -> Optional[Reporter]:
    """The native layer's callback for ``progress``: ``None`` (no progress) for a false
    value, the callable itself, or a tqdm or line drawer for ``True``."""
    if not progress:
        return None
    if callable(progress):
        return progress
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return _Lines()
    return _Tqdm(tqdm)


@contextlib.contextmanager
def reporting(progress: Union[bool, Reporter, None]) -> Iterator[Optional[Reporter]]:
    """:func:`reporter` for one call, its tqdm bars closed however the call ends."""
    drawer = reporter(progress)
    try:
        yield drawer
    finally:
        if isinstance(drawer, _Tqdm):
            drawer.close()
