"""``moorline statics --quasi-static`` (text and the JSON format of issue 15) and the studies
(solution Dataset, offset curves, watch circle)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from moorline.cli import main
from moorline.quasistatic import QuasiStaticModel
from moorline.quasistatic.studies import displace_coupled, offset_curve, solution_dataset, watch_circle

from .conftest import CONFORMANCE, SYSTEMS, deck


def _json(capsys, *argv):
    code = main(["statics", *map(str, argv), "--quasi-static", "--json"])
    out = capsys.readouterr().out
    assert code == 0
    return json.loads(out)


def test_json_format_body_deck(capsys):
    """Keys exactly lines / points / bodies / stiffness; lines keyed by deck number with the
    fairlead (end B) and anchor (end A) tensions; free points; bodies [m, rad]; the coupled
    stiffness as a nested list in deck order."""
    path = SYSTEMS["oc3_bridle"][0]
    out = _json(capsys, path)
    assert set(out) == {"lines", "points", "bodies", "stiffness"}
    sol = QuasiStaticModel(deck("oc3_bridle")).solve()
    assert list(out["lines"]) == [str(k) for k in range(1, 10)]
    for k, v in out["lines"].items():
        assert set(v) == {"fairlead_tension", "anchor_tension"}
        assert v["fairlead_tension"] == pytest.approx(sol.tensions[int(k) - 1, 1], rel=1e-9)
        assert v["anchor_tension"] == pytest.approx(sol.tensions[int(k) - 1, 0], rel=1e-9)
    assert list(out["points"]) == ["4", "5", "6"]  # the free junctions only
    assert np.allclose(out["points"]["4"], sol.points[3], atol=1e-6)
    assert list(out["bodies"]) == ["1"] and len(out["bodies"]["1"]) == 6
    K = np.array(out["stiffness"])
    assert K.shape == (6, 6) and np.all(np.diag(K) > 0)  # restoring positive on the diagonal
    assert np.allclose(K, sol.stiffness, rtol=1e-9, atol=1e-9 * np.max(np.abs(K)))


def test_offset_moves_the_coupled_body(capsys):
    path = SYSTEMS["oc3_spar"][0]
    out = _json(capsys, path, "--offset", "10,0,0,0,0,5")
    assert out["bodies"]["1"] == pytest.approx([10.0, 0.0, 0.0, 0.0, 0.0, math.radians(5.0)], abs=1e-12)
    qs = QuasiStaticModel(deck("oc3_spar"))
    sol = qs.solve(np.r_[10.0, 0.0, 0.0, 0.0, 0.0, math.radians(5.0)])
    assert out["lines"]["1"]["fairlead_tension"] == pytest.approx(sol.tensions[0, 1], rel=1e-9)


def test_offset_moves_coupled_points_rigidly(capsys):
    """Coupled fairlead points move as one floater about the origin: translated, then turned."""
    path = CONFORMANCE / "catenary_3line" / "lines.txt"
    if not path.exists():
        pytest.skip("../shared is not available")
    out = _json(capsys, path, "--offset", "10,-4,0,0,0,5")
    qs = QuasiStaticModel(deck("catenary_3line/lines.txt"))
    x = qs.deck_coupled_positions().reshape(3, 3)
    psi = math.radians(5.0)
    Rz = np.array([[math.cos(psi), -math.sin(psi), 0.0], [math.sin(psi), math.cos(psi), 0.0], [0.0, 0.0, 1.0]])
    moved = (x @ Rz.T + np.array([10.0, -4.0, 0.0])).ravel()
    sol = qs.solve(moved)
    assert out["points"] == {} and out["bodies"] == {}
    for k in range(3):
        assert out["lines"][str(k + 1)]["fairlead_tension"] == pytest.approx(sol.tensions[k, 1], rel=1e-9)
    assert np.allclose(out["stiffness"], sol.stiffness, rtol=1e-8, atol=1e-8 * np.max(np.abs(sol.stiffness)))


def test_text_output_and_errors(capsys, tmp_path):
    path = SYSTEMS["buoyed_line"][0]
    assert main(["statics", str(path), "--quasi-static"]) == 0
    text = capsys.readouterr().out
    assert "line 2: fairlead tension" in text and "point 2 (free)" in text and "P3_x" in text
    rod = tmp_path / "rod.dat"
    rod.write_text(path.read_text().replace("---------------------- POINTS", """---------------------- ROD TYPES ----
TypeName   Diam    Mass/m    Cd     Ca    CdEnd    CaEnd
(name)     (m)     (kg/m)    (-)    (-)   (-)      (-)
can        2.0     100.0     0.0    0.0   0.0      0.0
---------------------- RODS ----
ID   RodType  Attachment  Xa    Ya    Za    Xb    Yb    Zb    NumSegs  RodOutputs
(#)  (name)   (#/key)     (m)   (m)   (m)   (m)   (m)   (m)   (-)      (-)
1    can      fixed       0.0   0.0   -50   0.0   0.0   -60   2        -
---------------------- POINTS"""))
    assert main(["statics", str(rod), "--quasi-static"]) == 2
    assert "cannot represent rods" in capsys.readouterr().err
    assert main(["statics", str(path), "--quasi-static", "--offset", "1,2,3"]) == 2
    assert "expected six numbers" in capsys.readouterr().err
    assert main(["statics", str(path), "--json"]) == 2
    assert "--json needs --quasi-static" in capsys.readouterr().err


def test_friction_option_lowers_the_anchor_tension(capsys):
    path = SYSTEMS["oc3_spar"][0]
    base = _json(capsys, path)
    fr = json.loads((main(["statics", str(path), "--quasi-static", "--json", "--friction", "0.5"]),
                     capsys.readouterr().out)[1])
    for k in base["lines"]:
        assert fr["lines"][k]["anchor_tension"] < base["lines"][k]["anchor_tension"] - 1e4
        assert fr["lines"][k]["fairlead_tension"] == pytest.approx(base["lines"][k]["fairlead_tension"], rel=0.05)


def test_solution_dataset_dims_and_units():
    qs = QuasiStaticModel(deck("oc3_bridle"))
    ds = solution_dataset(qs)
    assert ds.tension.dims == ("line", "end") and ds.tension.attrs["units"] == "N"
    assert list(ds.coupled_dof.values) == qs.coupled_dof_labels
    assert ds.stiffness.dims == ("coupled_dof", "coupled_dof_j")
    assert ds.tension_gradient.dims == ("line", "end", "coupled_dof")
    assert ds.point_position.sel(point=4, xyz="z") < -70.0


def test_offset_curve_restoring_force_is_the_integral_of_the_stiffness():
    """Along an offset curve the restoring force's slope is the analytic stiffness along the offset:
    the trapezoid integral of the stiffness over 100 points reproduces the force to the trapezoid
    error (h^2/12 max|k'| L ~ 1e-4 relative here, bound 1e-3)."""
    qs = QuasiStaticModel(deck("oc3_bridle"))
    a = np.linspace(0.0, 30.0, 100)
    ds = offset_curve(qs, a, heading=30.0)  # its speed: benchmarks/bench_quasistatic.py
    F = ds.restoring.values
    k = ds.stiffness.values
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (k[1:] + k[:-1]) * np.diff(a))])
    assert np.max(np.abs(F - F[0] - integral)) <= 1e-3 * np.max(np.abs(F))
    assert np.all(np.diff(F) > 0)  # restoring grows with the offset
    assert ds.max_tension.dims == ("offset",)


def test_yaw_offset_curve_and_headings():
    qs = QuasiStaticModel(deck("oc3_spar"))
    ds = offset_curve(qs, np.radians([-5.0, 0.0, 5.0]), dof="yaw")
    assert ds.restoring.values[0] == pytest.approx(-ds.restoring.values[2], rel=1e-6)  # symmetric pattern
    # three lines at 120 deg: the surge stiffness does not depend on the heading (isotropic 2x2 block);
    # the deck's rounded coordinates (4.5 for 5.2 sin 60) break the symmetry at ~1e-4
    k0 = offset_curve(qs, [0.0], heading=0.0).stiffness.values[0]
    k60 = offset_curve(qs, [0.0], heading=60.0).stiffness.values[0]
    assert k60 == pytest.approx(k0, rel=1e-3)


def test_watch_circle_balances_the_force():
    qs = QuasiStaticModel(deck("oc3_bridle"))
    F = 1.5e6
    wc = watch_circle(qs, F, [0.0, 45.0, 180.0])
    for h in (0.0, 45.0, 180.0):
        c = wc.sel(heading=h)
        x = displace_coupled(qs, [float(c.offset_x), float(c.offset_y), 0.0, 0.0, 0.0, 0.0])
        loads = qs.solve(x).loads
        f = F * np.array([math.cos(math.radians(h)), math.sin(math.radians(h))])
        assert np.allclose(loads[:2], -f, atol=1e-6 * F)  # the balance the watch circle was solved to
    # the offset points along the force
    assert float(wc.sel(heading=0.0).offset_x) > 10.0
    assert float(wc.sel(heading=180.0).offset_x) < -10.0


def test_figures_draw_the_study_data():
    import matplotlib

    matplotlib.use("Agg")
    from moorline import plot

    qs = QuasiStaticModel(deck("oc3_bridle"))
    ds = offset_curve(qs, np.linspace(0.0, 10.0, 11))
    axes = plot.offset_curve(ds, lines=[1, 4])
    assert np.allclose(axes[0].lines[0].get_ydata(), ds.restoring.values * 1e-3)
    assert np.allclose(axes[1].lines[1].get_ydata(), ds.tension.sel(line=4, end="B").values * 1e-3)
    wc = watch_circle(qs, 1.0e6, [0.0, 120.0, 240.0])
    ax = plot.watch_circle(wc)
    x = ax.lines[0].get_xdata()
    assert x[0] == x[-1] and np.allclose(x[:3], wc.offset_x.values)  # a closed polygon of the offsets
