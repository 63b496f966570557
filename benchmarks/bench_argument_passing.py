"""What numba's unboxing of the time loop's NamedTuples of arrays costs per call, against one
int64 table of addresses, shapes and strides from which compiled code rebuilds them.

    python benchmarks/bench_argument_passing.py [--calls 20000] [--rounds 7] [DECK ...]

A measurement for a design not adopted (benchmarks/RESULTS.md, section 6, session 16): each call
of the coupling step's kept entry point (``System.step``'s fast path) passes the 9 NamedTuples of
its arguments (some 135 arrays for a chain without rods, bodies or waves), and numba unboxes every
array on every call. The alternative timed here writes every leaf of those tuples (array: address,
shape, strides; float: its bits; int and bool) into one int64 table once, and rebuilds the tuples
inside the compiled call from it (``rebuild``, an ``numba.extending.intrinsic``: array structs
with no owner, pointing at the same memory).

For each deck two no-op kernels are timed, per call, minimum over the rounds:

- ``the tuples``: a kernel taking the fast path's NamedTuples as they are;
- ``one table``: a kernel taking the table and the tuples' numba types (``TypeRef``, which cost
  nothing to pass), rebuilding every tuple.

Both return a float, so the difference is the unboxing alone. Default decks: the README example
and MoorDyn's WD0050_Chain and ``lines`` test decks (../shared/public_decks, skipped if absent).
Not a test: timings on a shared machine are noisy.
"""

from __future__ import annotations

import argparse
import struct
import time
from pathlib import Path

import numpy as np
from llvmlite import ir
from numba import njit, typeof, types
from numba.core import cgutils
from numba.extending import intrinsic

from moorline import System
from moorline.core.jit import KERNEL_OPTIONS, compile_for

ROOT = Path(__file__).resolve().parents[1]
MOORING = ROOT.parent / "shared" / "public_decks" / "FloatingArrayDesign+MoorDyn" / "tests" / "Mooring"
DECKS = [ROOT / "examples" / "catenary_3line" / "catenary_3line.dat", MOORING / "WD0050_Chain.txt",
         MOORING / "lines.txt"]


def _table(a, tab: list) -> list:
    """Append the leaves of ``a`` (arrays, floats, ints, bools, None) to ``tab`` as int64s."""
    if isinstance(a, np.ndarray):
        tab.append(a.ctypes.data)
        tab.extend(a.shape)
        tab.extend(a.strides)
    elif isinstance(a, tuple):
        for e in a:
            _table(e, tab)
    elif isinstance(a, (float, np.floating)):
        tab.append(struct.unpack("<q", struct.pack("<d", float(a)))[0])
    elif isinstance(a, (bool, np.bool_, int, np.integer)):
        tab.append(int(a))
    elif a is not None:
        raise TypeError(f"no table entry for {type(a).__name__}")
    return tab


@intrinsic
def rebuild(typingctx, tab, start, tyref):
    """The value of numba type ``tyref`` whose leaves are ``tab[start:]`` (as :func:`_table` wrote them)."""
    ty = tyref.instance_type
    sig = ty(tab, start, tyref)

    def codegen(context, builder, sig, args):
        i64 = ir.IntType(64)
        data = context.make_array(sig.args[0])(context, builder, args[0]).data
        base = builder.gep(data, [args[1]])
        pos = [0]

        def nxt():
            v = builder.load(builder.gep(base, [ir.Constant(i64, pos[0])]))
            pos[0] += 1
            return v

        def build(t):
            if isinstance(t, types.Array):
                ary = context.make_array(t)(context, builder)
                addr = nxt()
                shape = [nxt() for _ in range(t.ndim)]
                strides = [nxt() for _ in range(t.ndim)]
                dtype = context.get_data_type(t.dtype)
                itemsize = context.get_constant(types.intp, context.get_abi_sizeof(dtype))
                context.populate_array(ary, data=builder.inttoptr(addr, dtype.as_pointer()),
                                       shape=cgutils.pack_array(builder, shape),
                                       strides=cgutils.pack_array(builder, strides), itemsize=itemsize, meminfo=None)
                return ary._getvalue()
            if isinstance(t, types.BaseTuple):
                return context.make_tuple(builder, t, [build(e) for e in t])
            if isinstance(t, types.Float):
                return builder.bitcast(nxt(), ir.DoubleType())
            if isinstance(t, types.Boolean):
                return builder.icmp_signed("!=", nxt(), ir.Constant(i64, 0))
            if isinstance(t, types.Integer):
                v = nxt()
                return v if t.bitwidth == 64 else builder.trunc(v, ir.IntType(t.bitwidth))
            if isinstance(t, types.NoneType):
                return context.get_dummy_value()
            raise TypeError(f"rebuild: no table layout for {t}")

        return build(ty)

    return sig, codegen


def _kernels(n: int, starts: list[int]):
    """Two no-op kernels over ``n`` tuples: one taking them, one rebuilding them from the table."""
    opts = {**KERNEL_OPTIONS, "cache": False}
    names = [f"a{i}" for i in range(n)]
    ns: dict = {"rebuild": rebuild}
    exec(f"def plain({', '.join(names)}):\n    return 1.0\n", ns)
    src = "def via_table(tab, " + ", ".join(f"t{i}" for i in range(n)) + "):\n"
    src += "".join(f"    a{i} = rebuild(tab, {starts[i]}, t{i})\n" for i in range(n))
    src += "    return " + " + ".join(f"float(len(a{i}))" for i in range(n)) + "\n"
    exec(src, ns)
    return njit(**opts)(ns["plain"]), njit(**opts)(ns["via_table"])


def _per_call(fn, args, calls: int, rounds: int) -> float:
    fn(*args)
    best = float("inf")
    for _ in range(rounds):
        t0 = time.perf_counter()
        for _ in range(calls):
            fn(*args)
        best = min(best, (time.perf_counter() - t0) / calls)
    return best


def run(deck: Path, calls: int, rounds: int) -> tuple[int, int, float, float]:
    s = System.from_file(deck)
    s.init(solve_ic=False)
    x = s.deck_coupled_positions()
    s.step(x, np.zeros_like(x), 0.0, 0.01)  # (builds the fast path's plan)
    p = s._plan
    if p is None or p.fn is None:
        raise RuntimeError(f"{deck.name}: step() took its general path, no kept arguments to time")
    tuples = tuple(a for a in (*p.head, *p.tail) if isinstance(a, tuple))
    tab: list = []
    starts = []
    for a in tuples:
        starts.append(len(tab))
        _table(a, tab)
    table = np.array(tab, dtype=np.int64)
    tys = tuple(typeof(a) for a in tuples)
    plain, via_table = _kernels(len(tuples), starts)
    f_plain = compile_for(plain, tuples)
    f_table = compile_for(via_table, (table, *tys))
    n_arrays = sum(1 for a in _leaves(tuples) if isinstance(a, np.ndarray))
    return (len(tuples), n_arrays, _per_call(f_plain, tuples, calls, rounds),
            _per_call(f_table, (table, *tys), calls, rounds))


def _leaves(a):
    if isinstance(a, tuple):
        for e in a:
            yield from _leaves(e)
    else:
        yield a


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("decks", nargs="*", type=Path)
    ap.add_argument("--calls", type=int, default=20000)
    ap.add_argument("--rounds", type=int, default=7)
    a = ap.parse_args()
    decks = a.decks or [d for d in DECKS if d.is_file()]
    print("| deck | NamedTuples | arrays | the tuples [us] | one table [us] |")
    print("|---|---:|---:|---:|---:|")
    for deck in decks:
        n, na, t_plain, t_table = run(deck, a.calls, a.rounds)
        print(f"| {deck.name} | {n} | {na} | {t_plain * 1e6:.2f} | {t_table * 1e6:.2f} |")


if __name__ == "__main__":
    main()
