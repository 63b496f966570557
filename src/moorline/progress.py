"""Progress indications on stderr: the one notice that kernels are being compiled.

The compiled kernels are built by numba the first time a machine runs them (a deck of a new
kind, a new moorline version) and loaded from numba's cache afterwards. A first run therefore
spends most of its time compiling, which without a word looks like a frozen program.
:class:`CompileWatch` follows numba's compile events while it is active: it measures the time
spent compiling (so that it can be kept out of a run's real-time factor) and, when asked, says once
on stderr that kernels are being compiled, with a count of the functions done and the time spent.
"""

from __future__ import annotations

import sys
import time

from numba.core import event
from tqdm.auto import tqdm

#: the notice shown when compiling starts
NOTICE = "compiling kernels for this machine, first run only"


class CompileWatch(event.Listener):
    """Context manager that measures numba compilation (and announces it on stderr).

    Parameters
    ----------
    announce : bool or None
        True: say on stderr that kernels are being compiled (a live count on a terminal, one
        line at the start and one at the end otherwise); False: silent; None: only when stderr
        is a terminal.

    Attributes
    ----------
    seconds : float
        Wall time spent compiling while the watch was active [s] (nested compilations counted
        once).
    functions : int
        Number of function specialisations compiled.
    """

    def __init__(self, announce: bool | None = None):
        super().__init__()
        tty = hasattr(sys.stderr, "isatty") and sys.stderr.isatty()
        self.announce = tty if announce is None else bool(announce)
        self._live = self.announce and tty
        self.seconds = 0.0
        self.functions = 0
        self._depth = 0
        self._t0 = 0.0
        self._bar = None
        self._ctx = None

    # numba's listener interface
    def on_start(self, ev) -> None:
        if self._depth == 0:
            self._t0 = time.perf_counter()
            if self.announce and self._bar is None and self.functions == 0:
                if self._live:
                    self._bar = tqdm(total=None, desc=NOTICE, unit=" functions", file=sys.stderr, leave=True,
                                     bar_format="{desc}: {n} functions compiled [{elapsed}]")
                else:
                    print(f"moorline: {NOTICE} ...", file=sys.stderr, flush=True)
        self._depth += 1

    def on_end(self, ev) -> None:
        self._depth -= 1
        self.functions += 1
        if self._bar is not None:
            self._bar.update(1)
        if self._depth == 0:
            self.seconds += time.perf_counter() - self._t0

    def __enter__(self) -> CompileWatch:
        self._ctx = event.install_listener("numba:compile", self)
        self._ctx.__enter__()
        return self

    def __exit__(self, *exc) -> None:
        self._ctx.__exit__(*exc)
        if self._bar is not None:
            self._bar.close()
            self._bar = None
        elif self.announce and self.functions:
            print(f"moorline: compiled {self.functions} kernel functions in {self.seconds:.1f} s (kept in numba's "
                  f"cache for the next runs)", file=sys.stderr, flush=True)
