"""The compilation of the suite's big kernels, shared by its pytest-xdist workers.

Every worker of a whole-suite run needs the same kernels compiled with every feature
(tests/conftest.py): the derivative (``rhs_call``, which Newton statics calls from Python, with the
derivative ``rhs`` and all it calls), the explicit time loop (``advance``) and the implicit one
(``advance_implicit``). From an empty cache that is some 310 s of CPU on the machine of
benchmarks/RESULTS.md (rhs_call 153 s, advance 85 s, advance_implicit 66 s; each loop compiled
after the derivative, which it calls). Left alone, both workers compiled all of it at the same
time, each for itself, in the tests that first needed it.

Here the workers split it, each writing numba's cache for the other, under one file lock per part
(``fcntl.flock``, released by the system if a worker dies): the worker that holds a part's lock
compiles it; one that then takes the lock finds it in the cache and loads it in a fraction of a
second. The even workers compile the derivative; meanwhile the odd ones compile the kernels the
derivative calls late (those of bodies and floating bodies, some 45 s of its 153), so that it
finds them in the cache when it gets there, two the time loops call after a step, and the
quasi-static network solve (about 20 s, independent of the derivative), then wait for the
derivative. Then the even workers compile the explicit loop and the odd ones the implicit loop, at
the same time, and each loads the other's. A part whose lock is free when a worker reaches it is
compiled by that worker, so a worker with no other to wait for (one worker, or the other gone)
compiles everything itself, as before.

A kernel compiled on its own is the kernel compiled for its caller because every kernel sets its
own fast-math and inlining flags (:func:`moorline.core.jit.kernel`): numba gives a function that
leaves them unset those of the function being compiled when it first meets it, and before they
were set, compiling the floating bodies' kernels here ahead of the derivative changed their code
and results in the last bit (tests/verification/test_water_kinematics.py
``test_single_point_and_batch_kernels_agree`` failed). A kernel loaded from numba's cache is the
one compiled (its object code, and its bitcode for the kernels that call it).

Only for a run of most of the suite (:data:`MIN_TESTS` tests or more): a run of a few tests
compiles only what those need.
"""

from __future__ import annotations

import contextlib
import fcntl
import logging
import os
import time
from pathlib import Path

log = logging.getLogger(__name__)

#: a run of fewer tests than this compiles what its tests need, when they need it
MIN_TESTS = 400

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
DECK = EXAMPLES / "catenary_3line" / "catenary_3line.dat"


def worker_index() -> int | None:
    """0, 1, ... on a pytest-xdist worker of a run with two or more; None otherwise."""
    name = os.environ.get("PYTEST_XDIST_WORKER", "")
    if int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1")) < 2 or not name.startswith("gw"):
        return None
    return int(name[2:])


@contextlib.contextmanager
def _held(folder: Path, part: str):
    with open(folder / f"{part}.lock", "w") as fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


def _system(scheme: str | None = None):
    from moorline import System

    return System.from_file(DECK, **({"scheme": scheme} if scheme else {}))


def _derivative_args(s):
    import numpy as np  # (not at import: tests/conftest.py sets the BLAS threads first)

    L, R, P, E, B, W, F, FW = s._kernel_arrays()
    return (0.0, s.y, np.zeros_like(s.y), L, R, P, E, B, s._motion, W, F, FW, 1.0, np.int64(-1))


def _derivative() -> None:
    from moorline.core.jit import compile_for
    from moorline.core.rhs import rhs_call

    compile_for(rhs_call, _derivative_args(_system()))


def _callees() -> None:
    """Kernels of the bodies and floating bodies that ``rhs`` calls, with the arguments it passes
    them (core/rhs.py), then the floating bodies' and line states' kernels of the end of a time
    step (core/integrate.py, core/implicit.py). Arguments of other types would only compile
    specialisations nobody uses."""
    from moorline.core.floating import floating_after_step, floating_loads, floating_motion
    from moorline.core.jit import compile_for
    from moorline.core.linestates import store_line_states
    from moorline.core.rigid import body_motion, rigid_dynamics

    t, y, dy, L, R, P, E, B, Mo, W, F, FW, cd, _ = _derivative_args(_system())
    for kernel, args in ((rigid_dynamics, (y, dy, R, P, E, W)), (floating_loads, (t, y, dy, R, E, W, F, FW)),
                         (floating_motion, (R, W, F, FW)), (body_motion, (y, dy, R, W, F)),
                         (floating_after_step, (t, y, R, W, F, FW)), (store_line_states, (y, L, R, W, t, True))):
        compile_for(kernel, args)


def _quasistatic() -> None:
    """The quasi-static network solve and its tension gradients (one specialisation: they take
    plain arrays), independent of the derivative: the odd workers compile them while the even
    ones compile the derivative, in what was 27 s of waiting."""
    from moorline.io import read_deck
    from moorline.quasistatic import QuasiStaticModel

    qs = QuasiStaticModel(read_deck(Path(__file__).parent / "quasistatic" / "data" / "oc3_bridle.dat"))
    qs.solve(gradients=True)


def _explicit() -> None:
    _system().warm_up()


def _implicit() -> None:
    _system("GenAlpha").warm_up()


def compile_shared(n_tests: int, run_folder: Path) -> None:
    """Compile (or load) the suite's big kernels on this worker, split with the other workers as
    the module docstring says; nothing outside a pytest-xdist run of :data:`MIN_TESTS` tests or
    more. ``run_folder``: a folder of this run that every worker sees (the parent of the
    workers' pytest base temporary folders), for the lock files."""
    w = worker_index()
    if w is None or n_tests < MIN_TESTS:
        return
    folder = run_folder / "shared-compile"
    folder.mkdir(exist_ok=True)
    t0 = time.perf_counter()
    if w % 2 == 0:
        order = [("derivative", _derivative), ("explicit", _explicit), ("implicit", _implicit)]
    else:
        order = [("callees", _callees), ("quasistatic", _quasistatic), ("derivative", _derivative),
                 ("implicit", _implicit), ("explicit", _explicit)]
    for part, work in order:
        with _held(folder, part):
            t = time.perf_counter()
            work()
            log.info("worker %d: %s in %.1f s", w, part, time.perf_counter() - t)
    log.info("worker %d: shared compilation done in %.1f s", w, time.perf_counter() - t0)
