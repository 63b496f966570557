"""Validation gallery II: each study's ``--quick`` run in a subprocess, then its results_quick.json.

The checks are physics, with tolerances stated: what a run that went wrong (a mooring that does not hold,
a decay that does not decay, friction that does nothing) would fail.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
SHARED = ROOT.parent / "shared" / "data"
CONFIGS = ("qs_single", "qs_bridle", "dyn_single", "dyn_bridle", "dyn_bridle_implicit")


def _run(study: str) -> dict:
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src") + os.pathsep + os.environ.get("PYTHONPATH", ""))
    script = ROOT / "validation" / study / "run.py"
    out = ROOT / "validation" / study / "results_quick.json"
    out.unlink(missing_ok=True)
    proc = subprocess.run([sys.executable, str(script), "--quick"], cwd=ROOT, env=env, capture_output=True,
                          text=True, timeout=1800)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    return json.loads(out.read_text())


@pytest.mark.slow
def test_oc3_hywind_quick():
    pytest.importorskip("capytaine")
    r = _run("oc3_hywind")
    for key in ("natural_period_s", "damping_ratio"):
        assert set(r[key]) == {"surge", "heave", "pitch", "yaw"}
        for dof in r[key]:
            assert set(r[key][dof]) == set(CONFIGS)
    T, z = r["natural_period_s"], r["damping_ratio"]
    # the same platform on five mooring models: surge, heave and pitch periods within 10 % of each other (the
    # full run: within 2 %); the quick runs fit one cycle
    for dof in ("surge", "heave", "pitch"):
        v = np.array([T[dof][c] for c in CONFIGS])
        assert np.all(np.isfinite(v)) and v.max() / v.min() < 1.10, (dof, v)
    # heave: hydrostatics plus the taut lines, T = 2 pi sqrt((m + A33) / (C33 + K33)) is about 28.6 s
    assert 25.0 < T["heave"]["dyn_bridle"] < 32.0
    # yaw: the bridles are stiffer than single lines (quasi-static stiffness about 3x, period about 0.6x)
    ky = r["yaw_stiffness_nm_per_rad"]
    assert ky["bridle"] > 2.0 * ky["single"]
    assert T["yaw"]["dyn_bridle"] < 0.8 * T["yaw"]["dyn_single"]
    # quasi-static single lines have no yaw damping at all (no drag on the lines, none on the hull in yaw):
    # below 0.5 %; the dynamic bridles' drag damps yaw by several %
    assert z["yaw"]["qs_single"] < 0.005
    assert z["yaw"]["dyn_bridle"] > 0.02
    # ours against MoorPy at the same pose: yaw stiffness within 1 % (measured 1e-12)
    for lay in ("single", "bridle"):
        mp = r["statics"][lay]["moorpy"]
        if mp is not None:
            assert ky[lay] == pytest.approx(mp["yaw_stiffness"], rel=0.01)
    # the anchor tension in the 15 deg yaw decay is above its still-water value (the lines stretch), finite
    for c in CONFIGS:
        assert r["anchor_tension_max_n"][c] > r["anchor_tension_release_n"][c] * 0.999
        assert 1.0e5 < r["anchor_tension_max_n"][c] < 1.0e7


@pytest.mark.slow
def test_volturnus_seabed_quick():
    if not (SHARED / "volturnus_s" / "IEA-15-240-RWT-UMaineSemi.1").exists():
        pytest.skip("../shared/data/volturnus_s (the public VolturnUS-S set) is not present")
    r = _run("volturnus_seabed")
    f = r["fairlead_tension_mean_n"]
    for b in f:
        assert set(f[b]) == {"wind", "waves"}
        for load in f[b]:
            assert set(f[b][load]) == {"with", "without"}
            assert 1.0e5 < f[b][load]["with"] < 1.0e7
    # the thrust pushes along +x, away from line 1's anchor: its fairlead tension rises over the wave case's
    # (no mean load) by at least 30 % on the flat seabed
    assert f["flat"]["wind"]["without"] > 1.3 * f["flat"]["waves"]["without"]
    # upslope (line 1's anchor 141 m shallower, lines 2 and 3 106 m deeper): the deeper lines pull the platform
    # about 116 m towards them, stretching line 1: its tension rises over the flat seabed's (measured +60 %)
    assert f["upslope"]["waves"]["without"] > 1.2 * f["flat"]["waves"]["without"]
    # the single-line friction cases, steady sliding: the axial pull equals mu_kA sum(N) over the chain's nodes
    # within 5 % (measured +1.3 %: the suspended line's drag at 0.2 m/s adds to the friction); the transverse
    # friction moment, the difference from the frictionless sweep, is its Coulomb bound mu_kT sum(r N) within
    # 10 % (measured -1 % and +3 %: the frictionless sweep's line shape, hence its drag, differs a little)
    c = r["friction_cases"]
    for fr in ("directional", "stickslip"):
        assert c[f"axial_{fr}"]["ratio"] == pytest.approx(1.0, abs=0.05)
        assert c[f"transverse_{fr}"]["ratio"] == pytest.approx(1.0, abs=0.10)
    # with friction the transverse sweep needs more moment than without (friction resists it)
    assert c["transverse_directional"]["friction_moment_nm"] > 0.5 * c["transverse_directional"]["closed_form_nm"]
    # the loaded line's grounded chain (line 1, 0.4 x the thrust, flat seabed, steady wind): the paper's trends.
    # MoorDyn-F's saturated model makes the segment tensions equal (within 1 %; measured 0.01 %); stick-slip
    # makes them fall towards the anchor at the fully mobilised axial friction mu_kA W per metre (within 10 %;
    # measured -2.3 %, 741 kN at the touchdown to 410 kN at the anchor)
    ld = r["grounded_chain_tension_loaded_n"]
    sat = np.array(ld["with"]["segment_tension_n"])
    ss = np.array(ld["stickslip"]["segment_tension_n"])
    assert sat.size >= 5 and ss.size >= 5
    assert np.ptp(sat) < 0.01 * sat.mean()
    assert ss[0] < 0.8 * ss[-1]
    assert ld["stickslip"]["gradient_n_per_m"] == pytest.approx(ld["friction_gradient_n_per_m"], rel=0.10)
    # statics on the upslope (the quick run's slope): our quasi-static solver finds the equilibrium (it used to
    # hang line 1's chain through the slope) and equals MoorPy's lines at the same pose within 0.1 % (measured
    # 1e-5); line 1 lies along the fall line, so the dynamic model agrees with both within 2 % (measured 0.4 %)
    st = r["statics"]["upslope"]
    assert "fairlead" in st["ours_quasistatic"], st["ours_quasistatic"]
    qs, dyn = st["ours_quasistatic"], st["ours_dynamic_statics"]
    if st["moorpy"] is not None:
        assert np.allclose(qs["fairlead"], st["moorpy"]["fairlead"], rtol=1e-3)
        assert np.allclose(qs["anchor"], st["moorpy"]["anchor"], rtol=1e-3)
    assert dyn["fairlead"][0] == pytest.approx(qs["fairlead"][0], rel=0.02)
    assert dyn["anchor"][0] == pytest.approx(qs["anchor"][0], rel=0.02)


def test_oc3_bridle_spacing_sweep():
    """Fast (quasi-static statics only): the bridle's yaw stiffness against its fairlead spacing. The 30 deg row
    is the deck itself (the same stiffness within 1e-5, whatever the pose: the deck's coordinates carry four
    decimals, 4.5033 for 5.2 cos 30 deg; measured 2e-6); the stiffness grows with the spacing
    over 5-90 deg; the paper's 105e6 N m/rad over single lines falls between 45 and 70 deg (measured 58.8 deg at
    the equilibrium poses, 8.9 m spacing against the decks' 5.2 m)."""
    import importlib.util

    from moorline.io import read_deck
    from moorline.quasistatic import QuasiStaticModel

    spec = importlib.util.spec_from_file_location("oc3_run", ROOT / "validation" / "oc3_hywind" / "run.py")
    run = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(run)
    pose = np.array([0.0, 0.0, 1.0, 0.0, 0.0, 0.0])
    sw = run.bridle_spacing_sweep(pose, pose)
    rows = {r["half_angle_deg"]: r for r in sw["rows"]}
    deck = QuasiStaticModel(read_deck(ROOT / "validation" / "oc3_hywind" / "oc3_bridle.dat"), bodies_free=False)
    assert rows[30.0]["yaw_stiffness_nm_per_rad"] == pytest.approx(deck.solve(pose).stiffness[5, 5], rel=1e-5)
    k = np.array([r["yaw_stiffness_nm_per_rad"] for r in sw["rows"]])
    assert np.all(np.diff(k) > 0.0)
    assert 45.0 < sw["implied_half_angle_deg"] < 70.0
