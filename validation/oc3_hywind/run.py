"""OC3-Hywind spar with single and bridle (delta) moorings: dynamic against quasi-static lines.

Validation gallery II, study 1 (Andersen, Wendt, Robertson, Jonkman, Hall, ISOPE 2016, "Verification and
validation of multisegmented mooring capabilities in FAST v8"): the DeepCwind 1:50 OC3-Hywind test at full
scale, five mooring configurations (quasi-static and dynamic, single lines and bridles, and the dynamic
bridles with the implicit scheme at a large step), free decays in surge, heave, pitch and yaw, the yaw
tuning of the paper's Table 3, the anchor tension in a 15 deg yaw decay, the quasi-static yaw stiffness
(ours and MoorPy's) and a regular wave.

    PYTHONPATH=src python validation/oc3_hywind/run.py [--quick]

Writes results.json and the figures beside this file (``--quick``: shorter runs, a reduced set, results in
results_quick.json, no figures). Every assumption is in README.md.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import logging
import sys
import time
from pathlib import Path

import numpy as np

import moorline
from moorline import hydro
from moorline.io import read_deck
from moorline.model import MorisonStrip
from moorline.model.water import Waves
from moorline.quasistatic import QuasiStaticModel

HERE = Path(__file__).resolve().parent
RHO, G, DEPTH = 1025.0, 9.80665, 200.0

# ------------------------------------------------------------------ the platform (issue 17, the paper)
#: the tested model's calibrated displacement [m^3] (the hull as described displaces about 8029 m^3)
DISPLACEMENT = 7947.8
PLATFORM_MASS = 7279.6e3  # [kg]
PLATFORM_ZG = -89.9155  # [m] platform centre of mass (OC3 definition; the paper does not give it)
PLATFORM_I_RP = 3966.2e6  # roll/pitch inertia about the platform CM [kg m^2]
PLATFORM_I_YAW = 98.6e6  # yaw inertia about the platform CM [kg m^2]
TOWER_MASS = 303.1e3  # [kg]
TOWER_BASE, TOWER_TOP = 10.0, 87.6  # [m] (tower base from the paper; top from OC3: 87.6 m)
TOWER_ZG = 43.4  # [m] tower centre of mass (OC3 definition's tower, 249.7 t, 43.4 m; assumed the same)
RNA_MASS = 394.5e3  # rotor-nacelle assembly [kg], a point mass at the hub height
HUB_HEIGHT = 89.6  # [m]
HEAVE_DAMPING = 71.0e3  # extra linear heave damping [N s/m]
MORISON_CD = 0.6

#: Table 3 of the paper: extra yaw stiffness [N m/rad] and yaw damping (linear [N m s/rad], quadratic
#: [N m s^2/rad^2]); the damping only on the quasi-static and the single-line dynamic models
TUNE_K = {"single": 140.0e6, "bridle": 35.0e6}
FAIRLEAD_RADIUS = 5.2  # [m] (issue 17); the decks' bridle fairleads at +-30 deg about each line's azimuth
TUNE_B_LIN, TUNE_B_QUAD = 10.0e6, 100.0e6

#: the five configurations: (layout, mooring mode, scheme, dtM [s], takes the Table 3 damping)
CONFIGS = {
    "qs_single": ("single", "quasistatic", "GenAlpha", 0.05, True),
    "qs_bridle": ("bridle", "quasistatic", "GenAlpha", 0.05, True),
    "dyn_single": ("single", "dynamic", "RK2", 0.004, True),
    "dyn_bridle": ("bridle", "dynamic", "RK2", 0.002, False),
    "dyn_bridle_implicit": ("bridle", "dynamic", "GenAlpha", 0.1, False),
}
#: free-decay initial displacements (from the equilibrium) [m or deg], durations and output steps [s]
DECAYS = {"surge": (0, 5.0, 600.0, 0.5), "heave": (2, 3.0, 200.0, 0.25), "pitch": (4, 3.0, 300.0, 0.25),
          "yaw": (5, 15.0, 120.0, 0.1)}
#: --quick: durations [s] of the untuned decays, the tuned and the anchor-tension yaw decays, the wave run
QUICK = {"surge": 100.0, "heave": 70.0, "pitch": 80.0, "yaw": 30.0, "yaw_tuned": 20.0, "anchor": 20.0, "wave": 90.0}
WAVE_H, WAVE_T = 10.74, 14.3
QS_INTERVAL = 0.05  # [s] quasi-static lines re-solved and re-linearised every QS_INTERVAL


def profile() -> np.ndarray:
    """Meridian (r, z) of the OC3 hull, keel to waterline: 9.4 m diameter to the 120 m draft, tapering
    between 12 m and 4 m below the surface to 6.5 m; panels of about 4 m."""
    pts = [(0.0, -120.0)]
    for a, b, n in (((0.0, -120.0), (4.7, -120.0), 3), ((4.7, -120.0), (4.7, -12.0), 27),
                    ((4.7, -12.0), (3.25, -4.0), 4), ((3.25, -4.0), (3.25, 0.0), 2)):
        for s in np.linspace(0.0, 1.0, n + 1)[1:]:
            pts.append((a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])))
    return np.array(pts)


def coefficients():
    """Capytaine on the axisymmetric hull, the displaced volume set to the tested model's: the buoyancy at
    rest and the V z_B part of the roll and pitch hydrostatic stiffness follow the volume (centre of
    buoyancy and waterplane kept)."""
    ds = hydro.compute_coefficients(hydro.mesh_axisymmetric(profile(), n_theta=24), omega=np.linspace(0.05, 3.0, 40),
                                    rho=RHO, g=G, water_depth=DEPTH, rotation_center=[0.0, 0.0, 0.0])
    ds = ds.copy(deep=True)
    v_mesh = float(ds["displaced_volume"].values[0])
    zb = float(ds["center_of_buoyancy"].values[0, 2])
    C = ds["hydrostatic_stiffness"]
    for dof in ("Roll", "Pitch"):
        C.loc[{"influenced_dof": dof, "radiating_dof": dof}] += RHO * G * (DISPLACEMENT - v_mesh) * zb
    ds["displaced_volume"][:] = DISPLACEMENT
    return ds, v_mesh


def mass_properties():
    """Platform, tower (a uniform rod between its base and top, centre of mass at TOWER_ZG) and the RNA
    (a point mass at the hub) as one rigid body: mass, centre of mass, principal inertia about it. The
    turbine adds no yaw inertia (its masses are on the axis; the rotor's own yaw inertia is not given)."""
    m = PLATFORM_MASS + TOWER_MASS + RNA_MASS
    zg = (PLATFORM_MASS * PLATFORM_ZG + TOWER_MASS * TOWER_ZG + RNA_MASS * HUB_HEIGHT) / m
    l_t = TOWER_TOP - TOWER_BASE
    i_rp = (PLATFORM_I_RP + PLATFORM_MASS * (PLATFORM_ZG - zg) ** 2 + TOWER_MASS * (l_t**2 / 12 + (TOWER_ZG - zg) ** 2)
            + RNA_MASS * (HUB_HEIGHT - zg) ** 2)
    return m, zg, np.array([i_rp, i_rp, PLATFORM_I_YAW])


def morison_strips():
    """Drag-only strips on the hull (body axes, reference point at the still-water line)."""
    return [MorisonStrip((0, 0, -120.0), (0, 0, -12.0), d=9.4, Cd=MORISON_CD, n=27),
            MorisonStrip((0, 0, -12.0), (0, 0, -4.0), d=0.5 * (9.4 + 6.5), Cd=MORISON_CD, n=4),
            MorisonStrip((0, 0, -4.0), (0, 0, 10.0), d=6.5, Cd=MORISON_CD, n=7)]


def build(ds, config: str, *, yaw_k=0.0, yaw_damping=None, waves=None, force=None):
    """The model of one configuration; ``yaw_k`` extra yaw stiffness, ``yaw_damping`` (linear, quadratic),
    ``force`` a constant load (6) about the reference point."""
    layout, mode, scheme, dtM, _ = CONFIGS[config]
    m = read_deck(HERE / f"oc3_{layout}.dat")
    mass, zg, inertia = mass_properties()
    b = m.bodies[0]
    b.m, b.rCG, b.I = mass, np.array([0.0, 0.0, zg]), inertia
    m.options.tScheme, m.options.dtM = scheme, dtM
    m.add_hydro([0], ds)
    lin = np.zeros(6)
    quad = np.zeros(6)
    lin[2] = HEAVE_DAMPING
    if yaw_damping is not None:
        lin[5], quad[5] = yaw_damping
    stiff = np.zeros(6)
    stiff[5] = yaw_k
    m.add_floating(0, linear_damping=lin, quadratic_damping=quad, stiffness=stiff, morison=morison_strips(),
                   force=np.zeros(6) if force is None else force)
    m.env.waves = waves
    m.env.waves_on_lines = False
    return m


_SYSTEMS = {}


def system(ds, config: str, **kw):
    """The System of a configuration (built once per configuration and settings, re-initialised on reuse),
    initialised at its equilibrium with no constant load."""
    key = (config, tuple(sorted((k, repr(v)) for k, v in kw.items())))
    if key not in _SYSTEMS:
        layout, mode, scheme, dtM, _ = CONFIGS[config]
        _SYSTEMS.clear()  # one at a time: each holds its own work arrays
        _SYSTEMS[key] = moorline.System(build(ds, config, **kw), mooring=mode,
                                        qs_interval=QS_INTERVAL if mode == "quasistatic" else None)
    s = _SYSTEMS[key]
    s.layout.fl.Fc[0][:] = 0.0
    s.init()
    return s


# ------------------------------------------------------------------ decays
#: first guesses of the system stiffness per DOF for the pull [N/m, N m/rad]
K_GUESS = {0: 3.0e5, 2: 4.0e5, 4: 2.7e9, 5: 3.0e7}
#: the surge pull acts at the fairlead level (where the lines' restoring force acts: the pull barely pitches
#: the spar, as a model test's line at the fairleads); heave and yaw at the reference point, pitch a moment
PULL_Z = -70.0


def pull_load(dof: int, load: float) -> np.ndarray:
    f = np.zeros(6)
    f[dof] = load
    if dof == 0:
        f[4] = PULL_Z * load
    return f


def pulled(ds, config: str, dof: int, amplitude: float, tol=2e-3, **kw):
    """The system in static equilibrium under a constant load in one DOF that displaces that DOF by
    ``amplitude`` [m, rad] from the unloaded equilibrium, as a model test holds the model before the release
    (the lines are in equilibrium at the start of the decay). The load is found by secant steps inside a
    bracket (the bridles stiffen or soften with yaw: a leg slackens)."""
    s = system(ds, config, **kw)
    pose0 = s.bodies[0].pose().copy()
    lo, hi = (0.0, 0.0), None
    load = K_GUESS[dof] * amplitude
    for _ in range(30):
        s.layout.fl.Fc[0][:] = pull_load(dof, load)
        try:
            s.init()
            d = s.bodies[0].pose()[dof] - pose0[dof]
        except moorline.SimulationError:
            d = np.inf  # no equilibrium: more than the system holds
        if "newton" not in s.ic_report.get("method", "") or not s.ic_report.get("converged", False):
            # Newton missed (an explicit scheme then falls back to MoorDyn's stationary solver, which stops on
            # the line tensions with the body still far from equilibrium): not an answer, try a nearby load
            load *= 1.013
            continue
        if abs(d / amplitude - 1.0) < tol:
            return s, pose0
        if d < amplitude:
            lo = (load, d)
        else:
            hi = (load, d)
        if hi is None:
            load *= min(amplitude / d, 4.0) if d > 0 else 4.0
        elif np.isfinite(hi[1]):
            load = lo[0] + (amplitude - lo[1]) * (hi[0] - lo[0]) / (hi[1] - lo[1])
        else:
            load = 0.5 * (lo[0] + hi[0])
    raise RuntimeError(f"{config}: no pull found for {amplitude} in DOF {dof}")


def decay(ds, config: str, dof: str, *, amplitude=None, duration=None, tensions=False, **kw):
    """Release the body from rest, held by a constant load in one DOF (see :func:`pulled`); the DOF's history
    from the unloaded equilibrium [m or deg], and the anchor tension of line 1 when asked."""
    i, a0, dur, dt = DECAYS[dof]
    a0 = a0 if amplitude is None else amplitude
    dur = dur if duration is None else duration
    s, pose0 = pulled(ds, config, i, a0 if i < 3 else np.radians(a0), **kw)
    s.layout.fl.Fc[0][:] = 0.0  # release
    t = np.arange(0.0, dur + 1e-9, dt)
    x = np.zeros(t.size)
    ta = np.zeros(t.size)
    x[0] = s.bodies[0].pose()[i] - pose0[i]
    ta[0] = s.line_end_tensions()[0, 0]
    for k in range(1, t.size):
        s.step(None, None, t[k - 1], dt)
        x[k] = s.bodies[0].pose()[i] - pose0[i]
        if tensions:
            ta[k] = s.line_end_tensions()[0, 0]
    if i >= 3:
        x = np.degrees(x)
    return t, x, (ta if tensions else None), s


def period_and_damping(t, x, n_cycles=3):
    """Damped period (mean spacing of the zero crossings, x2) and damping ratio from the logarithmic
    decrement of successive extrema (half cycles) over the first ``n_cycles`` cycles."""
    sgn = np.sign(x)
    i = np.where(sgn[:-1] * sgn[1:] < 0)[0]
    zc = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
    zc = zc[:2 * n_cycles + 1]
    if zc.size < 3:
        return float("nan"), float("nan")
    period = 2.0 * float(np.mean(np.diff(zc)))
    # extrema: the largest |x| in each half cycle (the first from t = 0 to the first crossing), refined by
    # a parabola through the three samples around it
    bounds = np.concatenate([[t[0]], zc])
    peaks = []
    for a, b in zip(bounds[:-1], bounds[1:], strict=False):
        sel = np.where((t >= a) & (t <= b))[0]
        k = sel[np.argmax(np.abs(x[sel]))]
        if 0 < k < t.size - 1:
            y0, y1, y2 = np.abs(x[k - 1:k + 2])
            den = y0 - 2 * y1 + y2
            peaks.append(y1 - 0.125 * (y2 - y0) ** 2 / den if den != 0 else y1)
        else:
            peaks.append(abs(x[k]))
    peaks = np.array(peaks)
    delta = 2.0 * float(np.mean(np.log(peaks[:-1] / peaks[1:])))  # per full cycle
    return period, delta / np.sqrt(4 * np.pi**2 + delta**2)


# ------------------------------------------------------------------ statics
def quasistatic_stiffness(ds, layout: str):
    """Equilibrium (free body with its hydrostatics, weight and the lines) and the coupled stiffness of the
    lines there, ours and MoorPy's."""
    config = "qs_" + layout
    s = system(ds, config)
    pose = s.bodies[0].pose().copy()
    qs = QuasiStaticModel(build(ds, config), bodies_free=False)
    sol = qs.solve(pose, stiffness=True)
    out = {"pose": pose.tolist(), "yaw_stiffness": float(sol.stiffness[5, 5]),
           "surge_stiffness": float(sol.stiffness[0, 0]), "heave_stiffness": float(sol.stiffness[2, 2]),
           "pitch_stiffness": float(sol.stiffness[4, 4]),
           "fairlead_tension": sol.tensions[:, 1].tolist(), "anchor_tension": sol.tensions[:, 0].tolist()}
    out["moorpy"] = moorpy_statics(layout, pose)
    return out


#: half-angles [deg] of a bridle's two fairleads about the line's azimuth for the spacing sweep (the decks: 30)
BRIDLE_HALF_ANGLES = (5.0, 10.0, 20.0, 30.0, 40.0, 50.0, 55.0, 60.0, 65.0, 75.0, 90.0)


def bridle_spacing_sweep(pose_single, pose_bridle) -> dict:
    """Quasi-static yaw stiffness of the bridles against the spacing of each bridle's two fairleads (neither the
    paper nor the issue gives it), the body held at the bridle deck's equilibrium pose (the pretension, hence
    the heave, changes with the spacing; the sweep shows the sensitivity, not new equilibria); beside it the
    single lines' at theirs, and the difference the paper's Table 3 implies (140e6 - 35e6)."""
    k_single = float(QuasiStaticModel(read_deck(HERE / "oc3_single.dat"), bodies_free=False)
                     .solve(np.asarray(pose_single)).stiffness[5, 5])
    rows = []
    for phi in BRIDLE_HALF_ANGLES:
        m = read_deck(HERE / "oc3_bridle.dat")
        fair = [p for p in m.points if p.kind.name == "BODY"]
        if len(fair) != 6:
            raise RuntimeError(f"expected 6 fairleads on the body, found {len(fair)}")
        for i, p in enumerate(fair):  # points 7-12 of the deck: bridles at 0, 120, 240 deg, legs at -phi, +phi
            az = np.radians(120.0 * (i // 2) + (phi if i % 2 else -phi))
            p.r[0], p.r[1] = FAIRLEAD_RADIUS * np.cos(az), FAIRLEAD_RADIUS * np.sin(az)
        sol = QuasiStaticModel(m, bodies_free=False).solve(np.asarray(pose_bridle))
        rows.append({"half_angle_deg": phi, "spacing_m": float(2.0 * FAIRLEAD_RADIUS * np.sin(np.radians(phi))),
                     "yaw_stiffness_nm_per_rad": float(sol.stiffness[5, 5]),
                     "extra_over_single_nm_per_rad": float(sol.stiffness[5, 5]) - k_single,
                     "anchor_tension_n": float(sol.tensions[0, 0])})
    target = TUNE_K["single"] - TUNE_K["bridle"]
    extra = np.array([r["extra_over_single_nm_per_rad"] for r in rows])
    phis = np.array(BRIDLE_HALF_ANGLES)
    implied = float(np.interp(target, extra, phis)) if extra[0] < target < extra[-1] else None
    return {"single_yaw_stiffness_nm_per_rad": k_single, "rows": rows, "paper_difference_nm_per_rad": target,
            "implied_half_angle_deg": implied,
            "implied_spacing_m": None if implied is None else
            float(2.0 * FAIRLEAD_RADIUS * np.sin(np.radians(implied)))}


def moorpy_statics(layout: str, pose):
    """MoorPy 1.3.0 on the same deck with the body held at ``pose`` (its junctions free)."""
    try:
        import moorpy as mp
    except ImportError:
        return None
    with contextlib.redirect_stdout(io.StringIO()):
        ms = mp.System(file=str(HERE / f"oc3_{layout}.dat"), depth=DEPTH, rho=RHO, g=G)
        body = ms.bodyList[0]
        body.type = -1  # coupled: held where it is put
        body.r6 = np.array(pose, dtype=float)
        ms.initialize()
        ms.solveEquilibrium(tol=1e-8, maxIter=5000)
        K = ms.getCoupledStiffnessA()
    return {"yaw_stiffness": float(K[5, 5]), "surge_stiffness": float(K[0, 0]), "heave_stiffness": float(K[2, 2]),
            "pitch_stiffness": float(K[4, 4]),
            "fairlead_tension": [float(ln.TB) for ln in ms.lineList],
            "anchor_tension": [float(ln.TA) for ln in ms.lineList]}


# ------------------------------------------------------------------ regular wave
def regular_wave(ds, config: str, duration: float, dt: float = 0.25, ramp=3 * WAVE_T, fit_periods=10, **kw):
    """Surge in a regular wave (on the body only: FAST v8's MoorDyn had no wave kinematics on the lines):
    first-harmonic amplitude and mean over the last ``fit_periods`` periods."""
    waves = Waves.regular(WAVE_H, WAVE_T, heading=0.0, ramp_time=ramp)
    s = system(ds, config, waves=waves, **kw)
    x0 = s.bodies[0].pose()[0]
    t = np.arange(0.0, duration + 1e-9, dt)
    x = np.zeros(t.size)
    for k in range(1, t.size):
        s.step(None, None, t[k - 1], dt)
        x[k] = s.bodies[0].pose()[0] - x0
    sel = t >= t[-1] - fit_periods * WAVE_T
    w = 2 * np.pi / WAVE_T
    A = np.column_stack([np.ones(sel.sum()), np.cos(w * t[sel]), np.sin(w * t[sel])])
    c, *_ = np.linalg.lstsq(A, x[sel], rcond=None)
    return t, x, {"amplitude_m": float(np.hypot(c[1], c[2])), "mean_m": float(c[0]),
                  "range_m": float(x[sel].max() - x[sel].min())}


# ------------------------------------------------------------------ main
def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="short runs for CI (results_quick.json, no figures)")
    ap.add_argument("--sweep", action="store_true",
                    help="only the bridle-spacing sweep (seconds), merged into results.json at its poses")
    args = ap.parse_args(argv)
    logging.getLogger("moorline").setLevel(logging.ERROR)
    if args.sweep:
        out = HERE / "results.json"
        res = json.loads(out.read_text())
        res["bridle_spacing_sweep"] = bridle_spacing_sweep(res["statics"]["single"]["pose"],
                                                           res["statics"]["bridle"]["pose"])
        out.write_text(json.dumps(res, indent=1, default=float) + "\n")
        (HERE / "tables.md").write_text(tables(res))
        return res
    quick = args.quick
    t_start = time.time()
    timing = {}
    ds, v_mesh = coefficients()
    res = {"study": "oc3_hywind", "quick": quick, "units": "SI (m, s, N, N m, rad; decay amplitudes m or deg)",
           "hull_mesh_volume_m3": v_mesh, "displacement_m3": DISPLACEMENT}
    mass, zg, inertia = mass_properties()
    res["mass_properties"] = {"mass_kg": mass, "zg_m": zg, "inertia_kgm2": inertia.tolist(),
                              "net_buoyancy_n": RHO * G * DISPLACEMENT - mass * G}

    # quasi-static stiffness (ours and MoorPy's) at each layout's equilibrium
    statics = {lay: quasistatic_stiffness(ds, lay) for lay in ("single", "bridle")}
    res["statics"] = statics
    res["yaw_stiffness_nm_per_rad"] = {lay: statics[lay]["yaw_stiffness"] for lay in statics}
    res["bridle_spacing_sweep"] = bridle_spacing_sweep(statics["single"]["pose"], statics["bridle"]["pose"])
    timing["statics_s"] = time.time() - t_start

    configs = list(CONFIGS)
    dofs = list(DECAYS)
    periods = {d: {} for d in dofs}
    zetas = {d: {} for d in dofs}
    histories = {}
    for dof in dofs:
        for c in configs:
            t0 = time.time()
            dur = QUICK[dof] if quick else DECAYS[dof][2]
            t, x, _, s = decay(ds, c, dof, duration=dur)
            periods[dof][c], zetas[dof][c] = period_and_damping(t, x, n_cycles=1 if quick else 3)
            histories[(dof, c)] = (t, x)
            timing[f"decay_{dof}_{c}_s"] = time.time() - t0
            print(f"{dof:6s} {c:20s} T = {periods[dof][c]:8.3f} s  zeta = {zetas[dof][c]:.4f}  "
                  f"({time.time() - t0:.1f} s)", flush=True)
    res["natural_period_s"] = periods
    res["damping_ratio"] = zetas

    # yaw: the stiffness each model lacks, from the decays: K = (I_zz + A_66) w_n^2 (A_66 = 0, axisymmetric)
    izz = inertia[2]

    def k_decay(T, z):
        return izz * (2 * np.pi / T) ** 2 / (1.0 - z**2)

    res["yaw_stiffness_from_decay_nm_per_rad"] = {c: k_decay(periods["yaw"][c], zetas["yaw"][c]) for c in configs}
    ref = res["yaw_stiffness_from_decay_nm_per_rad"]["dyn_bridle"]
    res["yaw_stiffness_lacking_vs_dyn_bridle_nm_per_rad"] = {
        c: ref - res["yaw_stiffness_from_decay_nm_per_rad"][c] for c in configs}

    # tuned yaw decays (Table 3)
    tuned_T, tuned_z, tuned_hist = {}, {}, {}
    for c in configs:
        layout, _, _, _, damp = CONFIGS[c]
        kw = {"yaw_k": TUNE_K[layout], "yaw_damping": (TUNE_B_LIN, TUNE_B_QUAD) if damp else None}
        t, x, _, _ = decay(ds, c, "yaw", duration=QUICK["yaw_tuned"] if quick else DECAYS["yaw"][2], **kw)
        tuned_T[c], tuned_z[c] = period_and_damping(t, x, n_cycles=1 if quick else 3)
        tuned_hist[c] = (t, x)
        print(f"tuned yaw {c:20s} T = {tuned_T[c]:8.3f} s  zeta = {tuned_z[c]:.4f}", flush=True)
    res["natural_period_s_tuned"] = {"yaw": tuned_T}
    res["damping_ratio_tuned"] = {"yaw": tuned_z}

    # anchor tension of line 1 in a 15 deg yaw decay: every model with the same total yaw stiffness (bridles
    # without extra stiffness, single lines with 140e6 - 35e6), the Table 3 damping as above
    amax, amin, a0, ten_hist = {}, {}, {}, {}
    for c in configs:
        layout, _, _, _, damp = CONFIGS[c]
        kw = {"yaw_k": 0.0 if layout == "bridle" else TUNE_K["single"] - TUNE_K["bridle"],
              "yaw_damping": (TUNE_B_LIN, TUNE_B_QUAD) if damp else None}
        dur = QUICK["anchor"] if quick else 60.0
        t, x, ta, _ = decay(ds, c, "yaw", amplitude=15.0, duration=dur, tensions=True, **kw)
        amax[c], amin[c], a0[c] = float(ta.max()), float(ta.min()), float(ta[0])
        ten_hist[c] = (t, x, ta)
        print(f"anchor tension {c:20s} max {amax[c] / 1e3:8.1f} kN  min {amin[c] / 1e3:8.1f} kN", flush=True)
    res["anchor_tension_max_n"] = amax
    res["anchor_tension_min_n"] = amin
    res["anchor_tension_release_n"] = a0

    # regular wave
    wave = {}
    wave_hist = {}
    for c in configs:
        t0 = time.time()
        t, x, w = regular_wave(ds, c, QUICK["wave"] if quick else 25 * WAVE_T, ramp=WAVE_T if quick else 3 * WAVE_T,
                               fit_periods=3 if quick else 10)
        wave[c] = w
        wave_hist[c] = (t, x)
        timing[f"wave_{c}_s"] = time.time() - t0
        print(f"wave {c:20s} surge amplitude {w['amplitude_m']:.3f} m  mean {w['mean_m']:.3f} m", flush=True)
    res["regular_wave_surge"] = {"H_m": WAVE_H, "T_s": WAVE_T, **wave}
    timing["total_s"] = time.time() - t_start
    res["run_time_s"] = timing
    out = HERE / ("results_quick.json" if quick else "results.json")
    out.write_text(json.dumps(res, indent=1, default=float) + "\n")
    print(f"wrote {out} in {timing['total_s']:.0f} s")
    (HERE / ("tables_quick.md" if quick else "tables.md")).write_text(tables(res))
    if not quick:
        figures(res, histories, tuned_hist, ten_hist, wave_hist)
    return res


def tables(res) -> str:
    """The README's tables, from the results."""
    cfg = list(CONFIGS)
    out = ["| DOF | " + " | ".join(cfg) + " |", "|---|" + "---|" * len(cfg)]
    for dof in DECAYS:
        out.append(f"| {dof}: T [s] / zeta | " + " | ".join(
            f"{res['natural_period_s'][dof][c]:.2f} / {res['damping_ratio'][dof][c]:.3f}" for c in cfg) + " |")
    out.append("| yaw tuned (Table 3): T [s] / zeta | " + " | ".join(
        f"{res['natural_period_s_tuned']['yaw'][c]:.2f} / {res['damping_ratio_tuned']['yaw'][c]:.3f}"
        for c in cfg) + " |")
    out.append("| yaw stiffness from the untuned decay [MN m/rad] | " + " | ".join(
        f"{res['yaw_stiffness_from_decay_nm_per_rad'][c] / 1e6:.1f}" for c in cfg) + " |")
    out.append("| lacking against dyn_bridle [MN m/rad] | " + " | ".join(
        f"{res['yaw_stiffness_lacking_vs_dyn_bridle_nm_per_rad'][c] / 1e6:.1f}" for c in cfg) + " |")
    out.append("| line 1 anchor tension, 15 deg yaw decay: release / max / min [kN] | " + " | ".join(
        f"{res['anchor_tension_release_n'][c] / 1e3:.0f} / {res['anchor_tension_max_n'][c] / 1e3:.0f} / "
        f"{res['anchor_tension_min_n'][c] / 1e3:.0f}" for c in cfg) + " |")
    w = res["regular_wave_surge"]
    out.append(f"| regular wave H {w['H_m']} m T {w['T_s']} s: surge amplitude / mean [m] | " + " | ".join(
        f"{w[c]['amplitude_m']:.2f} / {w[c]['mean_m']:.2f}" for c in cfg) + " |")
    out += ["", "| statics (body at its quasi-static equilibrium) | ours single | MoorPy single | ours bridle | "
            "MoorPy bridle |", "|---|---|---|---|---|"]
    st = res["statics"]
    for key, lab, sc in (("yaw_stiffness", "yaw stiffness [MN m/rad]", 1e-6),
                         ("surge_stiffness", "surge stiffness [kN/m]", 1e-3),
                         ("heave_stiffness", "heave stiffness [kN/m]", 1e-3),
                         ("pitch_stiffness", "pitch stiffness [MN m/rad]", 1e-6)):
        row = [f"{st[lay][key] * sc:.4f} | " + (f"{st[lay]['moorpy'][key] * sc:.4f}" if st[lay]["moorpy"] else "-")
               for lay in ("single", "bridle")]
        out.append(f"| {lab} | " + " | ".join(row) + " |")
    for key, lab in (("fairlead_tension", "line 1 fairlead tension [kN]"),
                     ("anchor_tension", "line 1 anchor tension [kN]")):
        row = [f"{st[lay][key][0] / 1e3:.3f} | " + (f"{st[lay]['moorpy'][key][0] / 1e3:.3f}" if st[lay]["moorpy"]
                                                    else "-") for lay in ("single", "bridle")]
        out.append(f"| {lab} | " + " | ".join(row) + " |")
    sw = res.get("bridle_spacing_sweep")
    if sw:
        out += ["", "| bridle fairleads: half-angle [deg] / spacing [m] | quasi-static yaw stiffness [MN m/rad] | "
                "over single lines [MN m/rad] | line 1 anchor tension [kN] |", "|---|---|---|---|"]
        for r in sw["rows"]:
            out.append(f"| {r['half_angle_deg']:.0f} / {r['spacing_m']:.2f} | "
                       f"{r['yaw_stiffness_nm_per_rad'] / 1e6:.1f} | {r['extra_over_single_nm_per_rad'] / 1e6:.1f} | "
                       f"{r['anchor_tension_n'] / 1e3:.0f} |")
        if sw["implied_half_angle_deg"] is not None:
            out.append(f"| the paper's {sw['paper_difference_nm_per_rad'] / 1e6:.0f} MN m/rad (Table 3) | - | - | "
                       f"at {sw['implied_half_angle_deg']:.1f} deg / {sw['implied_spacing_m']:.2f} m |")
    return "\n".join(out) + "\n"


def figures(res, histories, tuned_hist, ten_hist, wave_hist):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    configs = list(CONFIGS)
    styles = {"qs_single": ("C0", "--"), "qs_bridle": ("C1", "--"), "dyn_single": ("C0", "-"),
              "dyn_bridle": ("C1", "-"), "dyn_bridle_implicit": ("C3", ":")}
    units = {"surge": "m", "heave": "m", "pitch": "deg", "yaw": "deg"}
    for dof in DECAYS:
        fig, ax = plt.subplots(figsize=(7.5, 3.4))
        for c in configs:
            t, x = histories[(dof, c)]
            col, ls = styles[c]
            ax.plot(t, x, color=col, ls=ls, lw=1.2,
                    label=f"{c}: T {res['natural_period_s'][dof][c]:.1f} s, zeta {res['damping_ratio'][dof][c]:.3f}")
        ax.set_xlabel("time [s]")
        ax.set_ylabel(f"{dof} [{units[dof]}]")
        ax.set_title(f"OC3-Hywind {dof} free decay (untuned)")
        ax.legend(fontsize=7, loc="upper right")
        ax.grid(alpha=0.3)
        fig.tight_layout()
        fig.savefig(HERE / f"decay_{dof}.png", dpi=90)
        plt.close(fig)
    fig, ax = plt.subplots(figsize=(7.5, 3.4))
    for c in configs:
        t, x = tuned_hist[c]
        col, ls = styles[c]
        ax.plot(t, x, color=col, ls=ls, lw=1.2, label=f"{c}: T {res['natural_period_s_tuned']['yaw'][c]:.2f} s, "
                f"zeta {res['damping_ratio_tuned']['yaw'][c]:.3f}")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("yaw [deg]")
    ax.set_title("yaw decay tuned as the paper's Table 3")
    ax.legend(fontsize=7, loc="upper right")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(HERE / "decay_yaw_tuned.png", dpi=90)
    plt.close(fig)
    fig, axs = plt.subplots(2, 1, figsize=(7.5, 5.0), sharex=True)
    for c in configs:
        t, x, ta = ten_hist[c]
        col, ls = styles[c]
        axs[0].plot(t, x, color=col, ls=ls, lw=1.2, label=c)
        axs[1].plot(t, ta / 1e3, color=col, ls=ls, lw=1.2, label=c)
    axs[0].set_ylabel("yaw [deg]")
    axs[1].set_ylabel("line 1 anchor tension [kN]")
    axs[1].set_xlabel("time [s]")
    axs[0].set_title("15 deg yaw decay, equal total yaw stiffness\n(bridles +0, single lines +105e6 N m/rad)",
                     fontsize=10)
    axs[0].legend(fontsize=7, ncol=2)
    for a in axs:
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(HERE / "yaw_anchor_tension.png", dpi=90)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(7.5, 3.4))
    for c in configs:
        t, x = wave_hist[c]
        col, ls = styles[c]
        amp = res["regular_wave_surge"][c]["amplitude_m"]
        ax.plot(t, x, color=col, ls=ls, lw=1.2, label=f"{c}: amplitude {amp:.2f} m")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("surge [m]")
    ax.set_title(f"regular wave H {WAVE_H} m, T {WAVE_T} s")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(HERE / "regular_wave_surge.png", dpi=90)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(0 if main() else 1)
