"""Progress of long work: a callback, tqdm bars, or plain lines on stderr."""

from __future__ import annotations

import contextlib
import sys
from typing import Callable, Dict, Iterator, Optional, Union

ProgressCallback = Callable[[str, float], object]
"""Called as progress(task, fraction): task names the step ("maps[0] phong_eye.exr", "fit
garnet_red.astm"), fraction is the part of it done, in [0, 1]; each task ends with 1.0."""

Progress = Union[ProgressCallback, bool, None]


class _Bars:
    """One tqdm bar per task, or, without tqdm, a line on stderr at each tenth of a task."""

    def __init__(self, tqdm: Optional[Callable[..., object]]) -> None:
        self._tqdm = tqdm
        self._bars: Dict[str, object] = {}
        self._tenths: Dict[str, int] = {}

    def __call__(self, task: str, fraction: float) -> None:
        if self._tqdm is None:
            tenth = int(fraction * 10 + 1e-9)
            if tenth > self._tenths.get(task, -1):
                self._tenths[task] = tenth
                print(f"brdfbake: {task}: {int(round(fraction * 100))}%", file=sys.stderr, flush=True)
            return
        bar = self._bars.get(task)
        if bar is None:
            bar = self._tqdm(total=100, desc=task, unit="%", leave=True)
            self._bars[task] = bar
        bar.n = min(100.0, round(fraction * 100, 1))  # type: ignore[attr-defined]
        bar.refresh()  # type: ignore[attr-defined]
        if fraction >= 1.0:
            bar.close()  # type: ignore[attr-defined]
            del self._bars[task]

    def close(self) -> None:
        for bar in self._bars.values():
            bar.close()  # type: ignore[attr-defined]
        self._bars.clear()


def _find_tqdm() -> Optional[Callable[..., object]]:
    try:
        from tqdm.auto import tqdm  # type: ignore[import-not-found]
    except ImportError:
        return None
    return tqdm  # type: ignore[no-any-return]


@contextlib.contextmanager
def progress_callback(progress: Progress) -> Iterator[Optional[ProgressCallback]]:
    """The callback the extension calls for `progress`, one of:

    - a callable progress(task, fraction), called on the calling thread while the work runs;
    - None (the default): tqdm bars on stderr when tqdm is installed and stderr is a terminal, else nothing;
    - True: tqdm bars when tqdm is installed, else a line on stderr at each tenth of each task;
    - False: nothing.
    """
    if progress is False:
        yield None
        return
    if callable(progress) and not isinstance(progress, bool):
        yield progress
        return
    if progress is not None and progress is not True:
        raise TypeError(f"progress: expected a callable (task, fraction), True, False or None, got {progress!r}")
    tqdm = _find_tqdm()
    if progress is None and (tqdm is None or not _stderr_is_terminal()):
        yield None
        return
    bars = _Bars(tqdm)
    try:
        yield bars
    finally:
        bars.close()


def _stderr_is_terminal() -> bool:
    try:
        return sys.stderr is not None and sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False
