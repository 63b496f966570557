"""Cost of the water-kinematics kernels per node evaluation [ns].

    python benchmarks/bench_waterkin.py [--nodes 1000] [--repeat 5]

For each sea, the batch kernel ``fluid_at_points`` is called from a compiled loop on ``--nodes``
points spread along a 400 m line in 50 m of water, at a new time each call (as at every derivative
evaluation of a simulation); the best of ``--repeat`` runs of about 0.2 s each is reported as
nanoseconds per node evaluation (U, dU/dt, zeta, p_dyn). The single-point kernel ``fluid_at`` is
timed the same way, one call per point. Times are CPU times of this process (``process_time``),
so that other work on a shared machine inflates them less. The cost of one call from Python
(unboxing the tuple) is printed at the end. Seas: still water (the default of every run), a uniform current, a depth
profile, summed regular / 50 / 200-component JONSWAP waves (Wheeler stretching), and the
200-component sea precomputed on a grid covering the nodes, with and without a current.

Not part of the test suite: timings depend on the machine and on what else runs on it.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from numba import njit

from moorline.core.waterkin import build_water_kinematics, fluid_at, fluid_at_points
from moorline.model.water import Current, WaveGrid, Waves

DEPTH, G, RHO = 50.0, 9.80665, 1025.0


@njit(cache=False)
def _batch_loop(t0, dt, calls, r, K, out):
    """fluid_at_points ``calls`` times at advancing times (compiled loop: no Python overhead)."""
    for c in range(calls):
        fluid_at_points(t0 + c * dt, r, K, out)


@njit(cache=False)
def _single_point_loop(t0, dt, calls, r, K, out):
    """fluid_at on every point, ``calls`` times (compiled loop: no Python overhead)."""
    for c in range(calls):
        t = t0 + c * dt
        for i in range(r.shape[0]):
            fluid_at(t, r[i, 0], r[i, 1], r[i, 2], K, out)


def _best_ns(loop, K, r, out, repeat: int) -> float:
    """Best time per node evaluation [ns] of ``loop`` over about 0.2 s runs."""
    loop(0.0, 0.1, 1, r, K, out)  # compile / load
    calls = 1
    while True:
        t0 = time.process_time()
        loop(0.0, 0.1, calls, r, K, out)
        if time.process_time() - t0 > 0.2 or calls > 1e6:
            break
        calls *= 2
    best = np.inf
    for _ in range(repeat):
        t0 = time.process_time()
        loop(0.0, 0.1, calls, r, K, out)
        best = min(best, time.process_time() - t0)
    return best / (calls * r.shape[0]) * 1e9


def _python_call_us(K, r, out) -> float:
    """Time of one fluid_at_points call from Python [us] (dominated by unboxing the tuple)."""
    fluid_at_points(0.0, r, K, out)
    t0 = time.perf_counter()
    for c in range(200):
        fluid_at_points(0.1 * c, r, K, out)
    return (time.perf_counter() - t0) / 200 * 1e6


def _nodes(n: int) -> np.ndarray:
    s = np.linspace(0.0, 1.0, n)
    return np.ascontiguousarray(np.c_[-400.0 * (1 - s), 2.0 * np.sin(6 * s), -50.0 + 48.0 * s**2])


def _seas():
    jonswap = dict(Hs=3.5, Tp=8.0, gamma=3.3, heading=20.0, seed=1)
    profile = Current.profile([-50.0, -20.0, 0.0], [0.1, 0.5, 0.8], [0.0, 0.1, 0.2])
    # 2 m x 4 m x 2.5 m x 0.89 s (242 MiB): the cost per point hardly depends on the grid's size
    grid = WaveGrid(x=np.linspace(-410, 10, 211), y=[-4.0, 0.0, 4.0], z=np.linspace(-50, 0, 21), nt=512)
    yield "still water", None, None, None
    yield "uniform current", None, Current.uniform(1.0, heading=180.0), None
    yield "current profile", None, profile, None
    yield "1 component (sum)", Waves.regular(2.0, 9.0, heading=20.0), None, None
    yield "50 components (sum)", Waves.jonswap(n_components=50, **jonswap), None, None
    yield "200 components (sum)", Waves.jonswap(n_components=200, **jonswap), None, None
    yield "200 components (grid)", Waves.jonswap(n_components=200, evaluation="grid", grid=grid, **jonswap), None, None
    yield "grid + current profile", Waves.jonswap(n_components=200, evaluation="grid", grid=grid, **jonswap), \
        profile, None


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--nodes", type=int, default=1000, help="points per call (default 1000)")
    ap.add_argument("--repeat", type=int, default=5, help="timed runs, best kept (default 5)")
    args = ap.parse_args(argv)
    r = _nodes(args.nodes)
    out = np.empty((args.nodes, 8))
    one = np.empty(8)
    head = f"{'sea':<26}{'batch ns/node':>15}{'single ns/node':>16}{'build s':>9}{'grid MiB':>10}"
    print(f"{args.nodes} nodes, best of {args.repeat}, timed from compiled loops")
    print(head)
    print("-" * len(head))
    for name, waves, current, bbox in _seas():
        t0 = time.perf_counter()
        K = build_water_kinematics(waves, current, depth=DEPTH, g=G, rho=RHO, bbox=bbox)
        build = time.perf_counter() - t0
        mib = (K.wg_kin.nbytes + K.wg_zeta.nbytes) / 2**20
        batch = _best_ns(_batch_loop, K, r, out, args.repeat)
        single = _best_ns(_single_point_loop, K, r, one, args.repeat)
        print(f"{name:<26}{batch:>15.1f}{single:>16.1f}{build:>9.2f}{mib:>10.1f}")
    print(f"\none fluid_at_points call from Python (still water, {args.nodes} nodes): "
          f"{_python_call_us(build_water_kinematics(None, None, depth=DEPTH, g=G, rho=RHO), r, out):.1f} us")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
