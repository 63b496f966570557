"""How the kernels are compiled (``moorline.core.jit``, ``moorline.core.features``).

* Every kernel goes through the one decorator ``kernel``, the only place that names numba's
  private ``_nrt`` option.
* ``_nrt=False`` still does what it is there for: a kernel passing a NamedTuple of arrays to
  another kernel compiles without reference-count updates. If a numba release drops the option,
  ``moorline.core.jit`` fails at import; if it keeps the name but ignores it, this test fails
  (the same function compiled with numba's defaults shows the updates, so the test can tell).
* Features: a system's kernels are compiled without the code of features it lacks (``when``), and
  with it when it has them.
* The derivative's fast-math flags keep inf and nan as values (an unstable run is caught by its
  non-finite state).
* The long lines' loops of the line kernel are vectorised (packed arithmetic), because they are
  compiled with LLVM's overlap-check limit raised; the limit is LLVM's default again afterwards,
  so nothing else is compiled under it; and a kernel compiled later links the vectorised code.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path
from typing import NamedTuple

import llvmlite.binding as llvm_binding
import numpy as np
import pytest
from numba import njit, typeof

import moorline
from moorline.core import features as F
from moorline.core import lines as core_lines
from moorline.core.features import RIGID, when
from moorline.core.jit import KERNEL_OPTIONS, SAFE_FASTMATH, VECTOR_WIDTH, derivative_kernel, overlap_checks
from moorline.core.jit import kernel as make_kernel
from moorline.core.lines import line_bending
from moorline.core.rhs import set_water
from moorline.core.rigid import rigid_dynamics, rod_loads
from moorline.system import System

CORE = Path(moorline.__file__).parent / "core"
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_every_kernel_goes_through_the_one_decorator():
    for p in sorted(CORE.glob("*.py")):
        if p.name == "jit.py":
            continue
        text = p.read_text()
        assert "_nrt" not in text, f"{p.name} names numba's private _nrt option: use core.jit.kernel"
        assert not re.search(r"@(numba\.)?n?jit\b", text), f"{p.name} compiles a kernel without core.jit.kernel"


class _Arrays(NamedTuple):
    a: np.ndarray
    b: np.ndarray


def _callee(t, x):
    return t.a[0] + t.b[0] + x


def _caller(t, x):
    return _callee_disp(t, x) + 1.0


_callee_disp = None


def _compiled_llvm(options) -> str:
    global _callee_disp
    _callee_disp = njit(**options)(_callee)
    caller = njit(**options)(_caller)
    t = _Arrays(np.ones(3), np.ones(3))
    assert caller(t, 1.0) == 4.0
    return "\n".join(caller.inspect_llvm().values())


def test_nrt_false_removes_reference_counting():
    without_cache = {**KERNEL_OPTIONS, "cache": False}
    assert without_cache["_nrt"] is False
    refcounts = re.compile(r"call\s+void\s+@NRT_(incref|decref)")
    assert refcounts.search(_compiled_llvm({"cache": False})), \
        "numba's default compilation no longer reference counts here: this test cannot tell the option's effect"
    assert not refcounts.search(_compiled_llvm(without_cache)), \
        "_nrt=False no longer removes the reference counting: numba changed its private option"


def _plain_sum(a):
    return a[0] * 3.0 + a[1] * 2.0 + a[2]


_flag_callee = None


def _fast_caller(a):
    return _flag_callee(a) + 1.0


def _flags_met_first_by_a_fast_caller(options) -> str:
    """LLVM of a callee made with ``options`` when a fast-math, forceinline caller is the first to
    compile it."""
    global _flag_callee
    _flag_callee = njit(**{**options, "cache": False})(_plain_sum)
    caller = njit(**{**KERNEL_OPTIONS, "cache": False, "fastmath": set(SAFE_FASTMATH), "forceinline": True})(
        _fast_caller)
    assert caller(np.ones(3)) == 7.0
    (llvm,) = _flag_callee.inspect_llvm().values()
    return llvm


def test_a_kernel_has_its_own_flags_whoever_compiles_it_first():
    """numba gives a function that leaves fastmath or forceinline unset the flags of the function
    being compiled when it first meets it; a kernel sets both, so its code does not depend on its
    first caller (core.jit.kernel)."""
    disp = make_kernel(_plain_sum)
    assert disp.targetoptions["fastmath"] is False and disp.targetoptions["forceinline"] is False
    options = {k: v for k, v in disp.targetoptions.items() if k not in ("nopython", "boundscheck")}
    llvm = _flags_met_first_by_a_fast_caller(options)
    assert "reassoc" not in llvm and "alwaysinline" not in llvm
    # without them, numba's inheritance shows (else this test could not tell)
    llvm = _flags_met_first_by_a_fast_caller({k: v for k, v in options.items() if k not in ("fastmath", "forceinline")})
    assert "reassoc" in llvm and "alwaysinline" in llvm
    fast = derivative_kernel(_plain_sum)
    assert fast.targetoptions["fastmath"] == set(SAFE_FASTMATH) and fast.targetoptions["forceinline"] is True


def _scaled_ratio(a):
    return a[0] * 3.0 / a[1]


def test_derivative_fast_math_keeps_inf_and_nan():
    assert not ({"nnan", "ninf", "afn", "fast"} & SAFE_FASTMATH)
    f = njit(**{**KERNEL_OPTIONS, "cache": False, "fastmath": set(SAFE_FASTMATH)})(_scaled_ratio)
    assert f(np.array([1.0, 0.0])) == np.inf
    assert np.isnan(f(np.array([0.0, 0.0])))
    assert np.isnan(f(np.array([np.nan, 1.0])))
    llvm = "\n".join(f.inspect_llvm().values())
    flags = re.findall(r"= f(?:mul|div) ((?:[a-z]+ )*)double", llvm)
    assert flags and all("reassoc" in fl and "nnan" not in fl and "ninf" not in fl for fl in flags), flags


_PACKED = re.compile(r"\bv(?:mul|add|sub|div|sqrt|fmadd\w*|fmsub\w*|fnmadd\w*|fnmsub\w*)pd\b")
_VECTOR_KERNELS = ("_segments_v", "_tangents_v", "_loads_v", "_accelerations_v")


def _asm(f):
    return "\n".join(f.inspect_asm().values())


@pytest.mark.parametrize("name", _VECTOR_KERNELS)
def test_long_line_loops_are_vectorised(name):
    disp = getattr(core_lines, name)
    (sig,) = disp.signatures
    opts = {**KERNEL_OPTIONS, "cache": False, "fastmath": set(SAFE_FASTMATH)}
    with overlap_checks():
        inside = njit(sig, **opts)(disp.py_func)
    assert _PACKED.search(_asm(inside)), f"{name}: no packed arithmetic, the loop is not vectorised"
    if name == "_loads_v":
        # two dozen arrays: beyond LLVM's default limit of overlap checks, so scalar without the
        # raised limit (the limit is what vectorises it, and it is not left raised)
        assert not _PACKED.search(_asm(njit(sig, **opts)(disp.py_func))), \
            "_loads_v vectorised with LLVM's default overlap-check limit: this test no longer tells"


def _many_arrays_source():
    ins = [f"a{i}" for i in range(16)]
    outs = [f"o{j}" for j in range(10)]
    src = f"def many(n, {', '.join(ins + outs)}):\n    for i in range(np.uint64(n)):\n"
    src += "        x = " + " + ".join(f"{a}[i]" for a in ins) + "\n"
    src += "".join(f"        {o}[i] = x * a{j}[i]\n" for j, o in enumerate(outs))
    ns = {"np": np}
    exec(src, ns)
    return ns["many"], "void(int64," + ",".join(["float64[::1]"] * 26) + ")"


def test_overlap_check_limit_is_left_at_llvms_default():
    """Other numba code compiled after moorline is imported (and after its vector kernels are
    compiled) sees LLVM's default limit: a loop over 26 arrays stays scalar; within
    ``overlap_checks`` it is vectorised."""
    fn, sig = _many_arrays_source()
    assert not _PACKED.search(_asm(njit(sig, error_model="numpy")(fn)))
    with overlap_checks():
        assert _PACKED.search(_asm(njit(sig, error_model="numpy")(fn)))
    assert not _PACKED.search(_asm(njit(sig, error_model="numpy")(fn)))


def _scale_add(n, a, b):
    for i in range(np.uint64(n)):
        a[i] += 2.0 * b[i] * a[i]


_PACKED_REG = re.compile(r"\bv(?:mul|add|fmadd\w*)pd\s+%?([xyz])mm")


def test_vector_width_is_forced_inside_and_llvms_choice_after():
    """Within ``overlap_checks`` LLVM vectorises VECTOR_WIDTH (4) doubles at a time, in 256-bit
    registers where the processor has them, never 512-bit ones; after it, the same loop is
    compiled with LLVM's own choice again (the same register widths as before the block)."""
    sig = "void(int64, float64[::1], float64[::1])"

    def widths():
        return set(_PACKED_REG.findall(_asm(njit(sig, error_model="numpy")(_scale_add))))

    before = widths()
    with overlap_checks():
        inside = widths()
    assert VECTOR_WIDTH == 4
    assert inside and "z" not in inside, inside
    if llvm_binding.get_host_cpu_features().get("avx", False):
        assert "y" in inside, inside
    assert widths() == before


def _calls_loads_v(n0, nN, s0, l0, wf, T, Td, q, v, U, Ud, Fb, F, H, W, M):
    core_lines._loads_v(n0, nN, s0, l0, wf, T, Td, q, v, U, Ud, Fb, F, H, W, M, 1025.0, 9.81, 100.0, 0.01, 0.1,
                        1.2, 0.4, 1.0, 0.5)


def test_a_caller_compiled_later_gets_the_vectorised_loop():
    """A kernel compiled after the vector kernels (loaded from numba's cache or compiled at import)
    links their vectorised code, under LLVM's default limit."""
    f = njit(**{**KERNEL_OPTIONS, "cache": False})(_calls_loads_v)
    n = 30
    arrs2 = [np.random.default_rng(k).random((n, 3)) for k in range(11)]
    l0, wf = np.ones(n), np.ones(n)
    f(0, n - 1, 0, l0, wf, *arrs2)
    assert _PACKED.search(_asm(f))


@pytest.fixture
def per_deck(monkeypatch):
    """Kernels specialised to each deck's features, as outside the test suite (tests/conftest.py)."""
    monkeypatch.delenv(F.ALL_FEATURES_ENV, raising=False)


def test_features_of_the_examples(per_deck):
    cat = System.from_file(EXAMPLES / "catenary_3line" / "catenary_3line.dat")
    assert cat.work.features == F.Features()
    cable = System.from_file(EXAMPLES / "wec_cable" / "wec_cable.dat")
    assert cable.work.features == F.Features.of(F.RIGID, F.BENDING)
    slope = System.from_file(EXAMPLES / "slope_friction" / "slope_chain.dat")
    assert slope.work.features == F.Features.of(F.STICKSLIP)
    fixed_point = System.from_file(EXAMPLES / "catenary_3line" / "catenary_3line.dat", scheme="BEuler3")
    assert fixed_point.work.features == F.Features.of(F.FIXED_POINT)
    from moorline.model.water import Waves

    wavy = System.from_file(EXAMPLES / "catenary_3line" / "catenary_3line.dat")
    wavy.model.env.waves = Waves.regular(2.0, 8.0)
    assert System(wavy.model).work.features == F.Features.of(F.WATER)


def test_a_system_without_rods_waves_or_bending_does_not_compile_their_code(per_deck):
    s = System.from_file(EXAMPLES / "catenary_3line" / "catenary_3line.dat")
    s.init(solve_ic=False)
    s.step(s.deck_coupled_positions(), np.zeros(s.n_coupled_dof), 0.0, 0.01)
    W = typeof(s.work)
    for kernel in (rod_loads, rigid_dynamics, set_water, line_bending):
        assert not any(W in sig for sig in kernel.signatures), f"{kernel.__name__} compiled for {W}"


class _Work(NamedTuple):
    features: F.Features
    x: np.ndarray


def _bump(x):
    x[0] += 1.0


def _gated(W):
    when(W, RIGID, _bump_disp, (W.x,))  # (a module attribute F.RIGID would not be a literal)
    return W.x[0]


_bump_disp = njit(cache=False)(_bump)


def test_when_calls_only_with_the_feature():
    gated = njit(**{**KERNEL_OPTIONS, "cache": False})(_gated)
    assert gated(_Work(F.Features(), np.zeros(1))) == 0.0
    assert not _bump_disp.signatures, "the callee was compiled for a system without the feature"
    assert gated(_Work(F.Features.of(F.RIGID), np.zeros(1))) == 1.0


def test_stale_cache_logic_finds_numbas_cache_folder(tmp_path):
    """With NUMBA_CACHE_DIR set, numba keeps the kernels' cache in the folder core/__init__ drops
    when the kernel sources change (checked by compiling one kernel in a fresh process)."""
    code = ("from moorline.core import kernel_cache_dirs\nfrom moorline.core.integrate import _axpy\n"
            "import numpy as np\n_axpy(np.zeros(2), np.ones(2), 1.0, np.ones(2))\nprint(kernel_cache_dirs()[-1])")
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    folder = Path(out.stdout.strip().splitlines()[-1])
    assert folder.parent == tmp_path
    assert list(folder.glob("integrate._axpy-*.nbi")), f"numba did not cache _axpy in {folder}"
    assert (folder / "kernel-sources.sha256").is_file()


@pytest.mark.parametrize("deck, scheme, ic", [
    ("catenary_3line/catenary_3line.dat", None, None),
    pytest.param("catenary_3line/catenary_3line.dat", "BEuler3", None, marks=pytest.mark.slow),
    pytest.param("wec_cable/wec_cable.dat", None, None, marks=pytest.mark.slow),
    pytest.param("catenary_3line/catenary_3line.dat", "GenAlpha", "newton", marks=pytest.mark.slow),
    pytest.param("catenary_3line/catenary_3line.dat", "LEuler", "stationary", marks=pytest.mark.slow),
    pytest.param("catenary_3line/catenary_3line.dat", "Heun", "dynamic", marks=pytest.mark.slow),
], ids=["RK2", "BEuler3", "cable", "GenAlpha-newton", "LEuler-stationary", "Heun-dynamic"])
def test_per_deck_and_all_feature_kernels_agree_to_round_off(monkeypatch, deck, scheme, ic):
    """The kernels compiled for a deck's own features and those compiled with every feature (the
    test suite's) compute the same, to round-off: a feature only adds code the deck never reaches.

    Round-off, not bits: compiled in one process the two agree bit for bit, but not always when
    numba's cache was filled by several processes (a two-worker test run). numba names a compiled
    function after a per-process counter and its fast-math set in hash order, so the cached
    ``integrate.advance`` of each process links the shared kernels under other names, and LLVM
    optimises the two differently: the cached all-feature ``advance`` of such a run differed from a
    freshly compiled one in the fast-math flags of a few multiplications of the inlined derivative,
    where the integrator's plain arithmetic meets the derivative's fast-math arithmetic, and 143 of
    702 state values in the last bit (2.2e-16 m) after these 5 steps (session 16, with
    core.jit.VECTOR_WIDTH). A missing or extra feature term is many orders above the tolerance.

    Per deck, a system without rods, floating bodies or water kinematics passes its kernels none of
    their arrays (core.features.kernel_parts, kernel_env): every kernel it reaches, initial-condition
    solvers included (``ic``), must compile without them."""
    runs = []
    for value in ("0", "1"):
        monkeypatch.setenv(F.ALL_FEATURES_ENV, value)
        s = System.from_file(EXAMPLES / deck, **({"scheme": scheme} if scheme else {}))
        if ic is None:
            s.init(solve_ic=False)
        else:
            opts = s.model.options
            opts.ICNewton = 1 if ic == "newton" else 0
            opts.ICgenDynamic = 1 if ic == "dynamic" else 0
            opts.TmaxIC = 2.0  # (the kernels' arithmetic is compared, not the equilibrium)
            s = System(s.model, **({"scheme": scheme} if scheme else {}))
            s.init()
        x = s.deck_coupled_positions()
        for k in range(5):
            s.step(x + 0.01 * k, np.full(s.n_coupled_dof, 0.1), 0.02 * k, 0.02)
        runs.append((s.work.features, s.y.copy(), s.work.F.copy()))
    assert runs[0][0] != runs[1][0]
    for a, b in ((runs[0][1], runs[1][1]), (runs[0][2], runs[1][2])):
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12 * np.abs(b).max())


def test_the_kernels_of_a_plain_deck_take_no_arrays_of_features_it_lacks(per_deck):
    """numba unboxes every array of every argument of a call from Python (30-40 ns each, empty or
    not): a chain with no rods, floating bodies or waves passes its kernels none of theirs; a system
    with rods passes the rods' arrays, and the layout keeps the full arrays for Python."""
    from moorline.core.features import NoExcitation, NoFloating, NoFloatWork, NoRigid, NoWater
    from moorline.core.layout import FloatArrays, RigidArrays

    cat = System.from_file(EXAMPLES / "catenary_3line" / "catenary_3line.dat")
    _, R, _, E, _, _, Fl, FW = cat._kernel_arrays()
    assert (type(R), type(Fl), type(FW), type(E.water), type(E.exc)) == (NoRigid, NoFloating, NoFloatWork, NoWater,
                                                                          NoExcitation)
    assert R.dims is cat.layout.rigid.dims and isinstance(cat.layout.fl, FloatArrays)
    assert type(cat._kernel_env_ic().water) is NoWater
    cable = System.from_file(EXAMPLES / "wec_cable" / "wec_cable.dat")
    assert type(cable._kernel_arrays()[1]) is RigidArrays and cable._kernel_arrays()[1] is cable.layout.rigid


def test_work_with_features_dispatches_fast():
    """numba's dispatcher types the arguments of every call; Work must stay on its fast path (a
    Features class of its own once cost 1 ms per call of the time loop, on a coupling step of a few
    microseconds): the dispatcher must never fall back to its Python typeof for a Work. Counted,
    not timed: the fallback is the dispatcher's ``typeof_pyval``, which the first call with a
    tuple of a new type does reach (the control, which shows the counter sees the fallback)."""
    s = System.from_file(EXAMPLES / "catenary_3line" / "catenary_3line.dat")
    s.init(solve_ic=False)
    W = s.work
    x = s.y[:1]
    _first_row(x, W)
    seen = []
    fallback = _first_row.typeof_pyval
    _first_row.typeof_pyval = lambda v: (seen.append(type(v).__name__), fallback(v))[1]
    try:
        for _ in range(20):
            _first_row(x, W)
        assert seen == []
        _first_row(x, (x, 1.0, 7))  # a type not met before: typed once by the fallback
        assert seen, "the control call did not reach the counted fallback: the test cannot see it"
    finally:
        del _first_row.typeof_pyval


@njit(cache=False)
def _first_row(x, w):
    return x[0]


def test_compile_returns_the_entry_point_that_fastcall_relies_on():
    """``Dispatcher.compile`` returns the compiled entry point (FastCall calls it directly); if a
    numba release changes that, this fails rather than FastCall silently falling back."""
    from moorline.core.jit import compile_for

    f = njit(cache=False)(lambda a, x: a[0] * x)
    fn = compile_for(f, (np.ones(2), 2.0))
    assert callable(fn) and fn is not f
    assert fn(np.full(2, 3.0), 2.0) == 6.0


def test_fast_typeof_is_numbas_typeof():
    """compile_for looks types up by the structure of the arguments (``jit.fast_typeof``): it must
    give numba's own ``typeof`` for every kind of value a kernel takes, and a value that differs
    only in what numba's type holds (layout, read-only, dtype, tuple class) must not get the type
    of one met before."""
    from moorline.core.jit import fast_typeof

    a = np.zeros((4, 3))
    ro = np.zeros(3)
    ro.flags.writeable = False
    values = [a, a.T, a[:, 1], a[::2], np.zeros(3, dtype=np.int64), np.zeros(0), np.zeros(()), ro, np.zeros((1, 1)),
              1.0, 2, -(2 ** 62), True, None, np.int64(3), np.float64(1.0), np.float32(1.0),
              (a, 1.0), _Arrays(np.ones(3), np.ones(2)), _Arrays(np.ones(3), ro), (), ((a, None), (True, 2))]
    for _ in range(2):  # the second time from the kept types
        for v in values:
            assert fast_typeof(v) == typeof(v), v
    assert fast_typeof(2 ** 63) == typeof(2 ** 63)  # (not kept: typed by numba each time)
    s = System.from_file(EXAMPLES / "wec_cable" / "wec_cable.dat")
    for _ in range(2):
        for arg in s._kernel_arrays():
            assert fast_typeof(arg) == typeof(arg)


def test_fastcall_retypes_when_an_argument_changes_type():
    from moorline.core.jit import FastCall

    f = njit(cache=False)(lambda t, x: t.a.sum() + x)
    call = FastCall()
    t1 = _Arrays(np.ones(3), np.ones(2))
    assert call(f, (t1, 1.0)) == 4.0
    assert call(f, (t1, 2.0)) == 5.0  # same objects, new scalar value: kept entry point
    kept = call._fn
    assert call(f, (t1, 2)) == 5.0  # an int where a float was: typed afresh
    t2 = _Arrays(np.ones((2, 2)), np.ones(2))  # a 2-d array where a 1-d one was
    assert call(f, (t2, 1.0)) == 5.0
    assert call._fn is not kept
    assert len(f.signatures) == 3


def test_step_out_and_fast_path_give_the_dispatcher_s_answer():
    """``System.step`` (FastCall, in-place trajectory, ``out=``) against the same steps through
    numba's ordinary dispatch: bitwise equal."""
    deck = EXAMPLES / "catenary_3line" / "catenary_3line.dat"
    a = System.from_file(deck)
    b = System.from_file(deck)
    x0 = a.deck_coupled_positions()
    a.init(x0)
    b.init(x0)
    out = np.empty(a.n_coupled_dof)
    from moorline.core.layout import step_motion
    for k in range(5):
        x = x0 + 0.1 * k
        xd = np.full_like(x0, 10.0)
        fa = a.step(x, xd, 0.01 * k, 0.01, out=out)
        assert fa is out
        mo = step_motion(x, xd, b.t, 0.01)
        b._motion = mo
        kernel, args = b._advance_call(mo, b.t + 0.01)
        b.t = kernel(*args)[0]
        np.testing.assert_array_equal(fa, b.coupled_forces())
    np.testing.assert_array_equal(a.y, b.y)
    with pytest.raises(ValueError, match="coupled DOF"):
        a.step(x0[:-1], None, a.t, 0.01)
