# SPDX-License-Identifier: Apache-2.0
"""The progress keyword of okid's long calls (identify, Identifier.push, refine): a callback
progress(done, total), or True for a bar on stderr (tqdm's when tqdm is installed, else one plain
line), or None. A call decorated with @reported checks the keyword and turns True into a Reporter;
the code inside asks for each phase's callback (phase()), so that a bar says what is running.
Also the choice of settings from the data, one C call without chunks (run_unchunked)."""
from __future__ import annotations

import functools
import sys
import time
from typing import IO, Any, Callable, Optional, TypeVar, Union

#: progress(done, total) of a long call: samples fed so far and the most it can take (for a
#: refinement samples x max_passes: it usually converges sooner), called after each chunk of
#: some 10-50 ms of work (16384 samples for the paper's case, fewer for larger models).
ProgressCallback = Callable[[int, int], Any]
#: the progress keyword: a ProgressCallback, True for a bar on stderr, False or None for nothing
ProgressArg = Union[ProgressCallback, bool, None]

F = TypeVar("F", bound=Callable[..., Any])

#: warnings.warn's stacklevel for the caller of a @reported function, from its body (the body,
#: the wrapper, the caller)
CALLER = 3

#: seconds between two lines of the plain bar when stderr is not a terminal (a log file)
LOG_INTERVAL = 5.0
#: seconds between two redraws of a bar on a terminal
REDRAW_INTERVAL = 0.1


class _LineBar:
    """One phase as a plain stderr line: redrawn in place on a terminal, else a line every
    LOG_INTERVAL seconds and one at the end."""

    def __init__(self, label: str, stream: IO[str]):
        self.label, self.stream = label, stream
        self.tty = bool(getattr(stream, "isatty", lambda: False)())
        self.start = time.monotonic()
        self.shown = -1.0
        self.done, self.total = 0, 0
        self.updated = False

    def _text(self) -> str:
        share = f"{100.0 * self.done / self.total:3.0f} % " if self.total > 0 else ""
        return (f"okid: {self.label} {share}({self.done}/{self.total} samples, "
                f"{time.monotonic() - self.start:.1f} s)")

    def update(self, done: int, total: int) -> None:
        self.done, self.total, self.updated = done, total, True
        now = time.monotonic()
        if self.tty and (now - self.shown >= REDRAW_INTERVAL or done >= total):
            self.stream.write("\r" + self._text())
            self.stream.flush()
            self.shown = now
        elif not self.tty and self.shown >= 0 and now - self.shown >= LOG_INTERVAL:
            self.stream.write(self._text() + "\n")
            self.shown = now
        elif not self.tty and self.shown < 0:
            self.shown = now  # the first line after LOG_INTERVAL, the last one at close()

    def close(self) -> None:
        if not self.updated:
            return
        self.stream.write(("\r" if self.tty else "") + self._text() + "\n")
        self.stream.flush()


class _TqdmBar:
    """One phase as a tqdm bar, made at its first update (when the total is known)."""

    def __init__(self, label: str, stream: IO[str], tqdm: Any):
        self.label, self.stream, self.tqdm = label, stream, tqdm
        self.bar: Any = None

    def update(self, done: int, total: int) -> None:
        if self.bar is None:
            self.bar = self.tqdm(total=total, desc=f"okid: {self.label}", unit="sample", unit_scale=True,
                                 file=self.stream, leave=True)
        elif self.bar.total != total:
            self.bar.total = total
        self.bar.update(done - self.bar.n)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def _tqdm() -> Any:
    try:
        from tqdm import tqdm
    except ImportError:
        return None
    return tqdm


class Reporter:
    """progress=True for one call: phase(label) gives each phase's callback, a fresh bar's;
    close() ends the last bar."""

    def __init__(self) -> None:
        self.current: Optional[Any] = None

    def phase(self, label: str) -> ProgressCallback:
        self.close()
        tqdm = _tqdm()  # sys.stderr as it is now (a test's capture, a notebook's)
        self.current = _TqdmBar(label, sys.stderr, tqdm) if tqdm is not None else _LineBar(label, sys.stderr)
        return self.current.update

    def close(self) -> None:
        if self.current is not None:
            bar, self.current = self.current, None
            bar.close()


def phase(progress: Any, label: str) -> Optional[ProgressCallback]:
    """The callback for one phase of a call: a Reporter's fresh bar (progress=True), the caller's
    own callback as it is, or None."""
    if isinstance(progress, Reporter):
        return progress.phase(label)
    return progress if callable(progress) else None


def reported(f: F) -> F:
    """f's progress keyword (ProgressArg) checked, and True made a Reporter for the call, its bar
    closed when f returns or raises. A Reporter passed on by another reported call stays that call's."""

    @functools.wraps(f)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        progress = kwargs.get("progress")
        if progress is not True:
            if not (progress is None or isinstance(progress, (bool, Reporter)) or callable(progress)):
                raise TypeError(f"progress = {progress!r}: a callable progress(done, total), True for a progress "
                                f"bar on stderr, or None")
            return f(*args, **kwargs)
        kwargs["progress"] = report = Reporter()
        try:
            return f(*args, **kwargs)
        finally:
            report.close()

    return wrapper  # type: ignore[return-value]


def run_unchunked(call: Callable[..., Any], args: tuple, progress: Any, label: str, total: int) -> Any:
    """call(*args), a C call without chunks (it releases the GIL), in this thread: the phase's
    callback sees (0, total) before and (total, total) after; Ctrl-C takes effect when it returns.
    Not in a thread to be waited on: a call dropped on Ctrl-C ran on beside the caller's next okid
    call, and OpenBLAS's buffers are not safe for two callers at once ("Bad memory unallocation!")."""
    callback = phase(progress, label)
    if callback is not None:
        callback(0, total)
    value = call(*args)
    if callback is not None:
        callback(total, total)
    return value
