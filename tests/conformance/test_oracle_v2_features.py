"""MoorDyn v2 features that moorline gained for issue 18, side by side with MoorDyn-C (``moordyn``
2.7.2) as a live oracle on MoorDyn's own public test decks (``../shared/public_decks``), plus the
analytic checks of the initial conditions.

* viscoelastic ropes (``EA_s|EA_d|...``, polyester/visco.txt and simple.txt) and the Syrope model
  (syrope/{linear,quadratic,exp}_wc/line.txt, with their SYROPE IC section);
* MoorDyn's time schemes other than Euler/RK2/RK4 (local_euler/hanging.txt: LEuler, Heun, AB3,
  ACA3, Wilson5);
* the initial conditions: MoorDyn's pendulum.txt (a 1e5 kg free point on one line: the line
  carries the point's weight, analytic) and MoorPy's case8.dat start at rest (residual
  acceleration below 1 mm/s^2).

Each dynamic case imposes a small smooth surge on the first coupled DOF (``AMP`` m, ramped in
over ``RAMP`` s) through both codes' coupling calls and compares the fairlead tension of every
line at every outer step (MoorDyn's convention: loads of the last derivative evaluation,
``loads_at='last_stage'``). The tolerances are stated next to the figures measured when the test
was written.
"""

from __future__ import annotations

import math
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

md = pytest.importorskip("moordyn")

from moorline.io import read_deck  # noqa: E402
from moorline.system import System  # noqa: E402

pytestmark = pytest.mark.oracle

ROOT = Path(__file__).resolve().parents[2]
MOORING = Path(os.environ.get("MOORLINE_SHARED", ROOT.parent / "shared")) / "public_decks" / \
    "FloatingArrayDesign+MoorDyn" / "tests" / "Mooring"
MOORPY = MOORING.parents[2] / "NREL+MoorPy" / "tests"


def deck(path: Path, tmp: Path, scheme: str | None = None, options: dict[str, str] | None = None,
         up: int = 0) -> Path:
    """A scratch copy of ``path`` (MoorDyn writes its outputs next to the deck), with the files
    beside it (and ``up`` folders above: Syrope decks read ``../owc.dat``), optionally with another
    time scheme and other option values."""
    if not path.is_file():
        pytest.skip(f"public deck {path} not available")
    root = path.parents[up]
    shutil.copytree(root, tmp / root.name, dirs_exist_ok=True,
                    ignore=shutil.ignore_patterns("*.out", "*.log", "*.vtk", "*.vtp"))
    dest = tmp / root.name / path.parent.relative_to(root)
    out = dest / path.name
    options = dict(options or {})
    if scheme is not None:
        options["tScheme"] = scheme
    if options:
        lines = out.read_text(errors="replace").splitlines()
        for key, value in options.items():
            hit = [i for i, ln in enumerate(lines) if len(ln.split()) > 1 and ln.split()[1].lower() == key.lower()]
            assert hit, f"{path}: no option {key}"
            lines[hit[0]] = f"{value}  {key}"
        out = dest / f"{path.stem}_{'_'.join(options.values())}{path.suffix}"
        out.write_text("\n".join(lines) + "\n")
    return out


def side_by_side(path: Path, duration: float, dt: float, amp: float, ramp: float) -> tuple[np.ndarray, np.ndarray]:
    """Fairlead tensions of every line at every outer step [N], (steps, lines), MoorDyn then moorline."""
    cwd = os.getcwd()
    os.chdir(path.parent)
    try:
        sys_ = System(read_deck(path), loads_at="last_stage")
        x0 = sys_.deck_coupled_positions()
        n = x0.size

        def X(t):
            x = x0.copy()
            if n:
                x[0] += amp * (1.0 - math.cos(math.pi * min(t / ramp, 1.0))) / 2.0 * math.sin(2 * math.pi * t / ramp)
            return x

        steps = int(round(duration / dt))
        s = md.Create(str(path))
        assert md.NCoupledDOF(s) == n
        md.Init(s, x0.tolist(), [0.0] * n)
        nl = md.GetNumberLines(s)
        lines = [md.GetLine(s, i + 1) for i in range(nl)]
        ref = []
        for k in range(steps):
            t = k * dt
            xk = X(t)
            md.Step(s, xk.tolist(), ((X(t + dt) - xk) / dt).tolist(), t, dt)
            ref.append([md.GetLineFairTen(ln) for ln in lines])
        md.Close(s)

        sys_.init(x0, np.zeros(n))
        ours = []
        for k in range(steps):
            t = k * dt
            xk = X(t)
            sys_.step(xk, (X(t + dt) - xk) / dt, t, dt)
            ours.append([ln.fairlead_tension() for ln in sys_.lines])
    finally:
        os.chdir(cwd)
    return np.array(ref), np.array(ours)


def rms_rel(ref: np.ndarray, ours: np.ndarray) -> float:
    """Largest over lines of the RMS difference relative to the RMS of MoorDyn's tension."""
    return float(np.max(np.sqrt(np.mean((ours - ref) ** 2, axis=0)) / np.sqrt(np.mean(ref ** 2, axis=0))))


#: (deck, options changed, duration [s], outer step [s], surge amplitude [m], ramp [s], tolerance
#: on rms_rel). visco.txt starts from its deck geometry in both codes (TmaxIC 0): MoorDyn's
#: initial-condition solve leaves a one-segment line's viscoelastic state where it started (half
#: the static tension) while moorline's puts it at rest (test_viscoelastic_start_at_rest).
ROPES = [
    ("polyester/visco.txt", {"TmaxIC": "0"}, 5.0, 0.05, 0.01, 2.0, 1e-4),
    ("polyester/simple.txt", None, 5.0, 0.05, 0.5, 2.0, 1e-3),
    ("syrope/linear_wc/line.txt", None, 10.0, 0.1, 0.01, 5.0, 1e-4),
    ("syrope/quadratic_wc/line.txt", None, 10.0, 0.1, 0.01, 5.0, 1e-4),
    ("syrope/exp_wc/line.txt", None, 10.0, 0.1, 0.01, 5.0, 1e-4),
]


@pytest.mark.parametrize("rel,options,duration,dt,amp,ramp,tol", ROPES, ids=[r[0] for r in ROPES])
def test_viscoelastic_and_syrope_ropes(tmp_path, rel, options, duration, dt, amp, ramp, tol):
    path = deck(MOORING / rel, tmp_path, options=options, up=1 if rel.startswith("syrope") else 0)
    ref, ours = side_by_side(path, duration, dt, amp, ramp)
    assert np.all(np.isfinite(ours))
    err = rms_rel(ref, ours)
    assert err <= tol, f"{rel}: fairlead tension RMS difference {err:.3g} of MoorDyn's RMS"


def test_viscoelastic_start_at_rest(tmp_path):
    """visco.txt (one segment, 1 m unstretched between points 2 m apart, g 0): at rest the
    viscoelastic segment carries the static branch's tension EA_s * strain (analytic)."""
    path = deck(MOORING / "polyester" / "visco.txt", tmp_path)
    model = read_deck(path)
    sys_ = System(model)
    sys_.init()
    lt = model.line_types[model.lines[0].line_type]
    strain = (2.0 - model.lines[0].L) / model.lines[0].L
    assert strain == pytest.approx(1.0)
    assert sys_.lines[0].fairlead_tension() == pytest.approx(lt.EA * strain, rel=1e-6)


#: MoorDyn's schemes on its own local-Euler deck (two hanging lines between two coupled points,
#: joined by a free point), both codes from the same catenary start (TmaxIC 0: MoorDyn's
#: initial-condition solve stops on this deck with 4.9 m/s^2 left, moorline's Newton reaches
#: 5e-8 m/s^2, which would dominate the comparison) and the free point released at rest.
#: Measured when written: LEuler 4.7e-7, ACA3 4.6e-7. MoorDyn 2.7.2 stops with "error integrating"
#: on this deck with Heun, AB3 and Wilson5, so those are not compared here.
SCHEMES = ["LEuler", "ACA3"]


@pytest.mark.parametrize("scheme", SCHEMES)
def test_time_schemes(tmp_path, scheme):
    path = deck(MOORING / "local_euler" / "hanging.txt", tmp_path, scheme, options={"TmaxIC": "0"})
    ref, ours = side_by_side(path, 5.0, 0.1, 0.0, 2.5)
    err = rms_rel(ref, ours)
    assert err <= 1e-5, f"{scheme}: fairlead tension RMS difference {err:.3g} of MoorDyn's RMS"


def test_viv(tmp_path):
    """MoorDyn's viv.txt (a riser in a uniform current, lift coefficient 0.7, 100 segments, RK4 at
    0.1 ms), both codes from the same catenary start (TmaxIC 0), 1 s. Measured when written: 4.4e-4
    RMS over 10 s; the lift force is a few percent of the tension, so a code without VIV differs by
    more than the tolerance."""
    path = deck(MOORING / "viv" / "viv.txt", tmp_path, options={"TmaxIC": "0"})
    ref, ours = side_by_side(path, 1.0, 0.01, 0.0, 1.0)
    err = rms_rel(ref, ours)
    assert err <= 2e-3, f"viv.txt: fairlead tension RMS difference {err:.3g} of MoorDyn's RMS"


def test_pendulum_starts_at_rest(tmp_path):
    """MoorDyn's pendulum.txt: the free point (1e5 kg) hangs on a neutrally buoyant line (7.85398
    kg/m, 0.1 m, water 1000 kg/m^3); at rest the line's end B carries the point's weight, m g
    (analytic; measured 980665 N, residual 7.5e-8 m/s^2; MoorDyn 2.7.2 stops at 975258 N)."""
    path = deck(MOORING / "pendulum.txt", tmp_path)
    model = read_deck(path)
    sys_ = System(model)
    sys_.init()
    free = [p for p in model.points if p.kind.name == "FREE"]
    assert len(free) == 1 and free[0].V == 0.0
    weight = free[0].m * model.env.g
    lt = model.line_types[model.lines[0].line_type]
    wet = (lt.w - model.env.rho * math.pi * lt.d ** 2 / 4.0) * model.lines[0].L * model.env.g
    assert abs(wet) < 1e-4 * weight  # the line weighs nothing in water
    assert sys_.ic_report["converged"] is not False and sys_.ic_report["residual"] < 1e-3
    ten = sys_.lines[0].fairlead_tension()
    assert abs(ten - weight) <= 1e-4 * weight, (ten, weight)


def test_moorpy_case8_starts_at_rest():
    path = MOORPY / "case8.dat"
    if not path.is_file():
        pytest.skip(f"public deck {path} not available")
    sys_ = System.from_file(path)
    sys_.init()
    assert sys_.ic_report["residual"] < 1e-3, sys_.ic_report
