"""VolturnUS-S on semi-taut chain-polyester moorings over sloped seabeds, with and without seabed friction.

Validation gallery II, study 2 (Housner et al., J. Phys. Conf. Ser. 2022, seabed bathymetry and friction in
MoorDyn): the IEA 15 MW VolturnUS-S semisubmersible (public WAMIT set, ElastoDyn mass properties, HydroDyn's
quadratic damping, from ../shared/data/volturnus_s) on three 500 m chain + 1000 m polyester lines in 850 m,
over a flat seabed and 12.5 % up-, down- and side-slopes; a constant wind thrust and a regular wave; MoorDyn-F's
directional saturated-damping friction and moorline's stick-slip friction; and the two single-line friction
cases (axial drag of a released line, transverse sweep around its anchor).

    PYTHONPATH=src python validation/volturnus_seabed/run.py [--quick]

Writes results.json (``--quick``: results_quick.json, shorter runs, no figures) and the figures beside this
file. Every assumption is in README.md.
"""

from __future__ import annotations

import argparse
import json
import logging
import re
import sys
import time
from pathlib import Path

import numpy as np

import moorline
from moorline import hydro
from moorline.io import read_deck
from moorline.model.types import Bathymetry
from moorline.model.water import Waves

HERE = Path(__file__).resolve().parent
DATA = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "volturnus_s"
STEM = DATA / "IEA-15-240-RWT-UMaineSemi"
RHO, G, DEPTH = 1025.0, 9.80665, 850.0

# ------------------------------------------------------------------ load cases (issue 17, the paper)
AIR_RHO, ROTOR_RADIUS, WIND_SPEED = 1.225, 120.0, 9.0
#: thrust coefficient of the IEA-15-240-RWT below rated (its design value, Gaertner et al. 2020)
CT = 0.80
THRUST = 0.5 * AIR_RHO * np.pi * ROTOR_RADIUS**2 * WIND_SPEED**2 * CT  # [N], about 1.79 MN
HUB_HEIGHT = 150.0  # [m]
WAVE_H, WAVE_T, WAVE_HEADING = 9.3, 14.9, 90.0
SLOPE = 0.125
#: MoorDyn-F friction of the paper: transverse/axial kinetic, static/kinetic ratio (1.33/1.0 = 0.92/0.69),
#: saturated-damping creep constant [N s/m]
MU_KT, MU_KA, MC, CV = 1.0, 0.69, 1.33, 1.0e6
BATHYMETRIES = ("flat", "upslope", "downslope", "sideslope")
#: the loaded-line case of the grounded-chain comparison: under the full thrust line 1 (upwind) lifts off its
#: whole chain, so the paper's loaded grounded chain is shown at 0.4 x the thrust (flat seabed, steady wind)
LOADED_THRUST_SCALE = 0.4


# ------------------------------------------------------------------ the platform from the public files
def _value(text: str, key: str) -> float:
    m = re.search(rf"^\s*(\S+)\s+{key}\s", text, re.MULTILINE)
    if m is None:
        raise KeyError(f"{key} not found")
    return float(m.group(1))


def _table(path: Path, ncol: int) -> np.ndarray:
    rows = []
    for line in path.read_text().splitlines():
        parts = line.split()
        if len(parts) == ncol:
            try:
                rows.append([float(p) for p in parts])
            except ValueError:
                continue
    return np.array(rows)


def mass_properties():
    """Platform, tower, yaw bearing, nacelle, hub and blades from the ElastoDyn files as one rigid body:
    mass [kg], centre of mass [m], principal inertia about it [kg m^2] (products of inertia neglected), and the
    parts. x downwind (the rotor is upwind, at -x), z up from the still-water line."""
    ed = (DATA / "IEA-15-240-RWT-UMaineSemi_ElastoDyn.dat").read_text()
    v = {k: _value(ed, k) for k in ("PtfmMass", "PtfmCMzt", "PtfmRIner", "PtfmPIner", "PtfmYIner", "TowerHt",
                                     "TowerBsHt", "YawBrMass", "NacMass", "NacCMxn", "NacCMzn", "NacYIner",
                                     "HubMass", "HubIner", "OverHang", "Twr2Shft", "ShftTilt", "TipRad", "HubRad")}
    precone = np.radians(_value(ed, r"PreCone\(1\)"))
    tilt = np.radians(v["ShftTilt"])
    tw = _table(DATA / "IEA-15-240-RWT-UMaineSemi_ElastoDyn_tower.dat", 4)
    tw = tw[(tw[:, 0] >= 0) & (tw[:, 0] <= 1) & (tw[:, 1] > 100)]  # HtFract, TMassDen rows
    z_t = v["TowerBsHt"] + tw[:, 0] * (v["TowerHt"] - v["TowerBsHt"])
    m_tower = np.trapezoid(tw[:, 1], z_t)
    zg_tower = np.trapezoid(tw[:, 1] * z_t, z_t) / m_tower
    i_tower = np.trapezoid(tw[:, 1] * (z_t - zg_tower) ** 2, z_t)  # about its CM, horizontal axes
    bl = _table(DATA / "IEA-15-240-RWT_ElastoDyn_blade.dat", 6)
    bl = bl[(bl[:, 0] >= 0) & (bl[:, 0] <= 1)]
    r_b = v["HubRad"] + bl[:, 0] * (v["TipRad"] - v["HubRad"])  # from the rotor apex along the blade
    m_blade = np.trapezoid(bl[:, 3], r_b)
    r_cm = np.trapezoid(bl[:, 3] * r_b, r_b) / m_blade
    i_polar = 3 * np.trapezoid(bl[:, 3] * (r_b * np.cos(precone)) ** 2, r_b)  # rotor about its shaft
    top = v["TowerHt"]
    apex = np.array([v["OverHang"] * np.cos(tilt), 0.0, top + v["Twr2Shft"] + v["OverHang"] * np.sin(tilt)])
    # (OverHang < 0 and ShftTilt < 0: the apex is upwind and above the shaft's tower-top height: 150 m)
    blades_cm = apex + np.array([r_cm * np.sin(precone), 0.0, 0.0])
    parts = {  # name: (mass, centre of mass, own inertia about its CM (xx, yy, zz))
        "platform": (v["PtfmMass"], np.array([0.0, 0.0, v["PtfmCMzt"]]),
                     np.array([v["PtfmRIner"], v["PtfmPIner"], v["PtfmYIner"]])),
        "tower": (m_tower, np.array([0.0, 0.0, zg_tower]), np.array([i_tower, i_tower, 0.0])),
        "yaw_bearing": (v["YawBrMass"], np.array([0.0, 0.0, top]), np.zeros(3)),
        "nacelle": (v["NacMass"], np.array([v["NacCMxn"], 0.0, top + v["NacCMzn"]]),
                    np.array([0.0, 0.0, v["NacYIner"]])),
        "hub": (v["HubMass"], apex, np.array([v["HubIner"], 0.0, 0.0])),
        "blades": (3 * m_blade, blades_cm, np.array([i_polar, 0.5 * i_polar, 0.5 * i_polar])),
    }
    m = sum(p[0] for p in parts.values())
    cg = sum(p[0] * p[1] for p in parts.values()) / m
    inertia = np.zeros(3)
    for mi, ri, ii in parts.values():
        d = ri - cg
        inertia += ii + mi * np.array([d[1] ** 2 + d[2] ** 2, d[0] ** 2 + d[2] ** 2, d[0] ** 2 + d[1] ** 2])
    return m, cg, inertia, {k: {"mass_kg": p[0], "cm_m": p[1].tolist()} for k, p in parts.items()}


def add_bquad() -> np.ndarray:
    """HydroDyn's AddBQuad (6x6) from the HydroDyn file."""
    lines = (DATA / "IEA-15-240-RWT-UMaineSemi_HydroDyn.dat").read_text().splitlines()
    i = next(k for k, ln in enumerate(lines) if "AddBQuad" in ln)
    return np.array([[float(x) for x in ln.split()[:6]] for ln in lines[i:i + 6]])


def coefficients():
    """The public WAMIT set: the .hst is buoyancy only (the WAMIT run had its centre of gravity at the origin,
    README_HydroData), displaced volume HydroDyn's PtfmVol0, centre of buoyancy on the axis."""
    hd = (DATA / "IEA-15-240-RWT-UMaineSemi_HydroDyn.dat").read_text()
    vol = _value(hd, "PtfmVol0")
    return hydro.read_wamit(STEM, rho=RHO, g=G, cog=[0.0, 0.0, 0.0], reference_point=[0.0, 0.0, 0.0],
                            displaced_volume=vol, center_of_buoyancy=[0.0, 0.0, 0.0])


# ------------------------------------------------------------------ seabed and model
def bathymetry(kind: str):
    """Planar 12.5 % slopes through 850 m under the platform, on a 2.8 km square grid (100 m ticks): upslope
    rises towards line 1's anchor (-x), downslope falls towards it, sideslope rises towards +y (across line
    1). Over the anchor footprint (1130 m radius) the depth spans about 700-1000 m."""
    if kind == "flat":
        return None
    x = np.arange(-1400.0, 1400.0 + 1e-9, 100.0)
    X, Y = np.meshgrid(x, x)
    depth = {"upslope": DEPTH + SLOPE * X, "downslope": DEPTH - SLOPE * X, "sideslope": DEPTH - SLOPE * Y}[kind]
    return Bathymetry(x, x, -depth, source=f"{kind} (run.py)")


def set_friction(m, friction: str, mc: float = MC) -> None:
    env = m.env
    if friction == "without":
        env.friction, env.mu, env.mu_kT, env.mu_kA = "isotropic", 0.0, 0.0, 0.0
    elif friction in ("directional", "stickslip"):
        env.friction, env.mu_kT, env.mu_kA, env.mc, env.cv = friction, MU_KT, MU_KA, mc, CV
    else:
        raise ValueError(friction)


#: linear damping [N s/m, N m s/rad] that settles the platform quickly (about critical in every DOF) when the
#: frictionless equilibrium is found by time stepping (see :func:`start_at_equilibrium`)
SETTLE_DAMPING = (2.0e6, 2.0e6, 2.5e7, 1.3e10, 1.3e10, 2.0e9)


def build(ds, bathy: str, friction: str, waves=None, linear_damping=None):
    m = read_deck(HERE / "volturnus_850m.dat")
    mass, cg, inertia, _ = mass_properties()
    b = m.bodies[0]
    b.m, b.rCG, b.I = mass, cg, inertia
    m.env.bathymetry = bathymetry(bathy)
    if m.env.bathymetry is not None:  # anchors on the local seabed, the junctions start 50 m above it
        for p in m.points:
            if p.kind.name in ("FIXED", "FREE"):
                p.r[2] = float(m.env.bathymetry.height(p.r[0], p.r[1])) + (50.0 if p.kind.name == "FREE" else 0.0)
    set_friction(m, friction)
    m.add_hydro([0], ds, ss_max_order=12)
    m.add_floating(0, quadratic_damping=add_bquad(), linear_damping=linear_damping)
    m.env.waves = waves
    m.env.waves_on_lines = True
    return m


def thrust_load(scale: float) -> np.ndarray:
    """The rotor thrust along +x at the hub: force and moment about the reference point."""
    return scale * np.array([THRUST, 0.0, 0.0, 0.0, HUB_HEIGHT * THRUST, 0.0])


def run_case(ds, bathy: str, friction: str, loading: str, duration: float, dt: float = 0.5, ramp: float = 600.0,
             thrust_scale: float = 1.0):
    """Line-1 fairlead tension history, and the line-1 segment tensions at the end; ``thrust_scale`` scales the
    wind thrust."""
    waves = Waves.regular(WAVE_H, WAVE_T, heading=WAVE_HEADING, ramp_time=3 * WAVE_T) if loading == "waves" else None
    s = moorline.System(build(ds, bathy, friction, waves=waves))
    start_at_equilibrium(s, ds, bathy)
    t = np.arange(0.0, duration + 1e-9, dt)
    ten = np.zeros(t.size)
    pose = np.zeros((t.size, 6))
    ten[0] = s.line_end_tensions()[3, 1]
    pose[0] = s.bodies[0].pose()
    for k in range(1, t.size):
        if loading == "wind":
            # a smooth ramp over about two surge periods (the soft semi-taut system's is about 330 s), so that
            # the platform reaches its mean offset without a large surge transient
            s.layout.fl.Fc[0][:] = thrust_load(thrust_scale * 0.5 * (1.0 - np.cos(np.pi * min(1.0, t[k - 1] / ramp))))
        s.step(None, None, t[k - 1], dt)
        ten[k] = s.line_end_tensions()[3, 1]  # line 4: line 1's polyester, its end B the fairlead
        pose[k] = s.bodies[0].pose()
    profile = {}
    for k in (1, 2):  # the chains of lines 1 and 2 (deck lines 1 and 2)
        chain = s.lines[k - 1]
        r = chain.node_positions()
        profile[f"line{k}"] = {"node_z": r[:, 2].tolist(), "node_xy": r[:, :2].tolist(),
                               "segment_tension": chain.segment_tensions().tolist(),
                               "seabed_z": seabed_height(s, r).tolist()}
    return t, ten, pose, profile


_EQUILIBRIA = {}


def loaded_grounded_chain(ds) -> dict:
    """Segment tensions along line 1's grounded chain (anchor first) at the end of 1200 s of steady wind at
    ``LOADED_THRUST_SCALE`` x the thrust on the flat seabed, for the three friction settings; beside them the
    closed-form gradient of fully mobilised axial kinetic friction, mu_kA W per metre."""
    out = {"thrust_n": LOADED_THRUST_SCALE * THRUST, "segment_length_m": None,
           "friction_gradient_n_per_m": MU_KA * chain_wet_weight()}
    for fr, model in (("with", "directional"), ("without", "without"), ("stickslip", "stickslip")):
        _, ten, pose, prof = run_case(ds, "flat", model, "wind", 1200.0, thrust_scale=LOADED_THRUST_SCALE)
        p = prof["line1"]
        on = np.array(p["node_z"]) < np.array(p["seabed_z"]) + 0.5
        seg = on[:-1] & on[1:]
        T = np.array(p["segment_tension"])[seg]
        xy = np.array(p["node_xy"])
        out["segment_length_m"] = float(np.linalg.norm(xy[1] - xy[0]))
        out[fr] = {"segment_tension_n": T.tolist(), "segments": int(seg.sum()),
                   "fairlead_tension_n": float(ten[-1]), "surge_m": float(pose[-1, 0])}
        if T.size > 1:
            out[fr]["gradient_n_per_m"] = float((T[-1] - T[0]) / ((T.size - 1) * out["segment_length_m"]))
    return out


def chain_wet_weight() -> float:
    """Wet weight of the chain [N/m] from the deck's type (mass and volume-equivalent diameter)."""
    lt = read_deck(HERE / "volturnus_850m.dat").line_types["chain"]
    return float((lt.w - RHO * np.pi / 4.0 * lt.d**2) * G)


def start_at_equilibrium(s, ds, bathy: str) -> None:
    """Initialise ``s`` at the frictionless static equilibrium on its bathymetry. The saturated friction models
    act during the implicit relaxation that Newton statics falls back on (they depend on the velocity), hold
    the lying chain and stop the platform short of its equilibrium on the slopes; every run therefore starts
    from the frictionless equilibrium (found once per bathymetry, with the stick-slip springs relaxed there),
    as the saturated models give no friction in statics."""
    if bathy not in _EQUILIBRIA:
        s0 = moorline.System(build(ds, bathy, "without"))
        try:
            s0.init()
            how = s0.ic_report["method"]
        except moorline.SimulationError:
            # on the slopes Newton statics stalls at about 5e-5 m/s^2 (a node at the sloped touchdown toggles its
            # contact) against its 1e-5 tolerance: settle the frictionless system in time instead, with heavy
            # linear damping on the platform, until it moves less than 0.1 mm/s
            s0 = moorline.System(build(ds, bathy, "without", linear_damping=SETTLE_DAMPING))
            s0.init(solve_ic=False)
            t = 0.0
            while t < 3000.0:
                s0.step(None, None, t, 10.0)
                t += 10.0
                if t > 100.0 and np.max(np.abs(s0.bodies[0].velocity())) < 1e-4:
                    break
            how = f"settled in time with heavy damping ({t:.0f} s; platform speed < 0.1 mm/s)"
        _EQUILIBRIA[bathy] = ([ln.node_positions() for ln in s0.lines], np.array([p.position() for p in s0.points]),
                              s0.bodies[0].pose(), {"method": how})
    lines, points, pose, _ = _EQUILIBRIA[bathy]
    s.init(solve_ic=False)
    s.set_body_state(0, position=pose[:3], angles=pose[3:])
    s.set_state(line_positions=lines, point_positions=points)


def seabed_height(s, nodes):
    bt = s.model.env.bathymetry
    return np.full(len(nodes), -DEPTH) if bt is None else bt.height(nodes[:, 0], nodes[:, 1])


# ------------------------------------------------------------------ the single-line friction cases
def single_line(friction: str, *, anchor_free: bool):
    """Line 1 alone (chain + polyester, anchor at -1130 m, fairlead a coupled point at -58 m, flat 850 m),
    static friction = kinetic (mc = 1)."""
    full = read_deck(HERE / "volturnus_850m.dat")
    m = moorline.model.Model()
    m.env.depth, m.env.rho, m.env.g = DEPTH, RHO, G
    m.options.tScheme, m.options.dtM, m.options.ICNewton = "GenAlpha", 0.05, 1
    for name, lt in full.line_types.items():
        m.line_types[name] = lt
    a = m.add_point("free" if anchor_free else "fixed", (-1130.0, 0.0, -DEPTH))
    j = m.add_point("free", (-635.0, 0.0, -800.0))
    f = m.add_point("coupled", (-58.0, 0.0, -14.0))
    m.add_line("chain", a, j, L=500.0, N=25)
    m.add_line("polyester", j, f, L=1000.0, N=20)
    set_friction(m, friction, mc=1.0)
    return m


def axial_case(friction: str, duration: float, speed: float = 0.2, ramp: float = 10.0, dt: float = 0.5):
    """The anchor released, the fairlead pulled away from it along the line at 0.2 m/s: once the slack is
    taken up (about 600 s) the whole grounded chain slides along its axis, and the fairlead's horizontal pull
    equals mu_kA times the seabed's normal force on the chain (plus the drag of the suspended line at
    0.2 m/s)."""
    m = single_line(friction, anchor_free=True)
    s = moorline.System(m)
    x0 = s.deck_coupled_positions()
    s.init(x0, solve_ic=False)  # no static equilibrium with a released anchor: start on the catenaries
    t = np.arange(0.0, duration + 1e-9, dt)
    h = np.zeros(t.size)
    expect = np.zeros(t.size)
    for k in range(1, t.size):
        tau = t[k]
        x = x0.copy()
        x[0] += speed * (tau - 0.5 * ramp if tau > ramp else tau**2 / (2 * ramp))
        v = np.zeros(3)
        v[0] = speed * min(1.0, tau / ramp)
        s.step(x, v, t[k - 1], dt)
        h[k] = abs(s.coupled_forces()[0])  # horizontal pull of the line on the fairlead
        expect[k] = MU_KA * normal_force(s)
    return t, h, expect


def normal_force(s, line=0, weights=None):
    """Seabed contact force of the chain's nodes, normal to the flat seabed (vertical; the friction is
    horizontal) [N], summed with ``weights`` per node (default 1)."""
    n = np.maximum(s.lines[line].node_seabed_forces()[:, 2], 0.0)
    return float(np.sum(n if weights is None else n * weights))


def transverse_case(friction: str, duration: float, speed: float = 0.9, ramp: float = 20.0, dt: float = 0.5):
    """The anchor held, the fairlead moved on a circle around it at 0.9 m/s: the grounded chain is swept
    sideways. Returns the moment of the fairlead's pull about the anchor (vertical axis) [N m] and the
    Coulomb bound of the transverse friction moment of the grounded chain, mu_kT sum(r_i N_i) over its nodes
    (N_i the seabed's normal force, r_i the distance from the anchor): reached if every grounded node slid
    transversely at more than the creep velocity; the chain next to the anchor moves slower, and part of
    the grounded chain slides partly along its axis."""
    m = single_line(friction, anchor_free=False)
    s = moorline.System(m)
    x0 = s.deck_coupled_positions()
    s.init(x0)
    anchor = np.array([-1130.0, 0.0])
    r0 = x0[:2] - anchor
    R = float(np.hypot(*r0))
    th0 = np.arctan2(r0[1], r0[0])
    t = np.arange(0.0, duration + 1e-9, dt)
    mom = np.zeros(t.size)
    expect = np.zeros(t.size)
    for k in range(1, t.size):
        tau = t[k]
        arc = speed * (tau - 0.5 * ramp if tau > ramp else tau**2 / (2 * ramp))
        th = th0 + arc / R
        om = speed * min(1.0, tau / ramp) / R
        x = x0.copy()
        x[:2] = anchor + R * np.array([np.cos(th), np.sin(th)])
        v = np.array([-R * om * np.sin(th), R * om * np.cos(th), 0.0])
        s.step(x, v, t[k - 1], dt)
        f = s.coupled_forces()  # load of the line on the fairlead
        rr = x[:2] - anchor
        mom[k] = -(rr[0] * f[1] - rr[1] * f[0])  # the pull's moment against the sweep
        nodes = s.lines[0].node_positions()
        r = np.hypot(nodes[:, 0] - anchor[0], nodes[:, 1] - anchor[1])
        expect[k] = MU_KT * normal_force(s, weights=r) if friction != "without" else 0.0
    return t, mom, expect


# ------------------------------------------------------------------ statics against MoorPy
def statics(ds, bathy: str) -> dict:
    """Line tensions at the frictionless equilibrium pose of the platform: the dynamic model's statics, our
    quasi-static solver and MoorPy 1.3.0 (its grid set directly, as tests/quasistatic do), the platform held
    at the same pose and the junctions free; MoorPy also at our junction positions (its lines' tensions there
    and the net force they leave on each junction).

    MoorPy 1.3.0's equilibrium solver keeps free points above its flat ``depth`` whatever the bathymetry
    (system.py, ``solveEquilibrium``: a z DOF at or below ``-self.depth`` is clamped there and dropped): with
    the deck's 850 m, the downslope's line-1 junction (880 m deep over a 937 m seabed) was held at 850 m with
    221 kN of vertical force unbalanced. Its ``depth`` is therefore set below the deepest grid point; its
    lines take their seabed from the grid (``seabedMod`` 2) either way. MoorPy's lines stay in their vertical
    planes, with the seabed slope between the depths under their two ends: a chain lying across a slope's fall
    line (lines 2 and 3 on the up- and downslope, all three on the sideslope) cannot bow down the slope as
    ours does (``grounded_plan_bow_m``), so only lines along the fall line compare like for like."""
    import contextlib
    import io

    from moorline.quasistatic import QuasiStaticError, QuasiStaticModel

    lines, points, pose, how = _EQUILIBRIA[bathy]
    m = build(ds, bathy, "without")
    for k, pt in enumerate(m.points):  # the junctions start where the dynamic statics put them
        if pt.kind.name == "FREE":
            pt.r[:] = points[k]
    out = {"pose": pose.tolist(), "equilibrium": how["method"]}
    try:
        sol = QuasiStaticModel(m, bodies_free=False).solve(pose)
        out["ours_quasistatic"] = {"fairlead": sol.tensions[3:, 1].tolist(), "anchor": sol.tensions[:3, 0].tolist()}
    except QuasiStaticError as e:
        out["ours_quasistatic"] = {"error": str(e)}
    s = moorline.System(build(ds, bathy, "without"))
    s.init(solve_ic=False)
    s.set_body_state(0, position=pose[:3], angles=pose[3:])
    s.set_state(line_positions=lines, point_positions=points)
    T = s.line_end_tensions()
    out["ours_dynamic_statics"] = {"fairlead": T[3:, 1].tolist(), "anchor": T[:3, 0].tolist()}
    free = [k for k, pt in enumerate(m.points) if pt.kind.name == "FREE"]
    out["junctions_ours_m"] = [points[k].tolist() for k in free]
    # the grounded chain's largest distance, in plan, from the straight chord between its ends (a frictionless
    # chain lying across a slope's fall line bows down the slope)
    bow = []
    for k in range(3):
        r = lines[k]
        on = r[:, 2] < seabed_height(s, r) + 0.5
        rg = r[on]
        if len(rg) < 3:
            bow.append(0.0)
            continue
        u = (rg[-1, :2] - rg[0, :2]) / np.linalg.norm(rg[-1, :2] - rg[0, :2])
        bow.append(float(np.max(np.abs((rg[:, :2] - rg[0, :2]) @ np.array([-u[1], u[0]])))))
    out["grounded_plan_bow_m"] = bow
    try:
        import moorpy as mp
    except ImportError:
        out["moorpy"] = None
        return out
    with contextlib.redirect_stdout(io.StringIO()):
        ms = mp.System(file=str(HERE / "volturnus_850m.dat"), depth=DEPTH, rho=RHO, g=G)
        for k, pt in enumerate(m.points):  # anchors on the slope, junctions from our equilibrium
            if pt.kind.name == "FIXED":
                ms.pointList[k].r = np.array(pt.r, dtype=float)
            elif pt.kind.name == "FREE":
                ms.pointList[k].r = np.array(points[k], dtype=float)
        bt = m.env.bathymetry
        if bt is not None:
            ms.bathGrid_Xs, ms.bathGrid_Ys, ms.bathGrid, ms.seabedMod = bt.x, bt.y, -bt.z, 2
            ms.depth = float(np.max(-bt.z)) + 100.0  # no clamp of the free points (see the docstring)
        body = ms.bodyList[0]
        body.type = -1
        body.r6 = np.array(pose, dtype=float)
        ms.initialize()
        out["moorpy_at_our_junctions"] = {
            "fairlead": [float(ms.lineList[k].TB) for k in (3, 4, 5)],
            "anchor": [float(ms.lineList[k].TA) for k in (0, 1, 2)],
            "junction_force_n": [np.asarray(ms.pointList[k].getForces(), dtype=float).tolist() for k in free]}
        converged = ms.solveEquilibrium(tol=1e-8, maxIter=5000)
    out["moorpy"] = {"fairlead": [float(ms.lineList[k].TB) for k in (3, 4, 5)],
                     "anchor": [float(ms.lineList[k].TA) for k in (0, 1, 2)],
                     "junctions_m": [np.asarray(ms.pointList[k].r, dtype=float).tolist() for k in free],
                     "junction_force_n": [np.asarray(ms.pointList[k].getForces(), dtype=float).tolist() for k in free],
                     "converged": bool(converged)}
    return out


# ------------------------------------------------------------------ main
def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="short runs for CI (results_quick.json, no figures)")
    ap.add_argument("--statics", action="store_true",
                    help="only the frictionless equilibria and the statics comparison, merged into results.json")
    ap.add_argument("--loaded", action="store_true",
                    help="only the loaded-line grounded-chain case (three runs), merged into results.json")
    args = ap.parse_args(argv)
    logging.getLogger("moorline").setLevel(logging.ERROR)
    if args.statics:
        return statics_only()
    if args.loaded:
        out = HERE / "results.json"
        res = json.loads(out.read_text())
        t0 = time.time()
        res["grounded_chain_tension_loaded_n"] = loaded_grounded_chain(coefficients())
        res["run_time_s"]["loaded_grounded_chain_s"] = time.time() - t0
        out.write_text(json.dumps(res, indent=1, default=float) + "\n")
        (HERE / "tables.md").write_text(tables(res))
        figure_loaded(res)
        return res
    quick = args.quick
    t_start = time.time()
    timing = {}
    ds = coefficients()
    mass, cg, inertia, parts = mass_properties()
    res = {"study": "volturnus_seabed", "quick": quick, "units": "SI (m, s, N, N m)",
           "mass_properties": {"mass_kg": mass, "cg_m": cg.tolist(), "inertia_kgm2": inertia.tolist(), "parts": parts},
           "thrust_n": THRUST, "hub_height_m": HUB_HEIGHT,
           "wave": {"H_m": WAVE_H, "T_s": WAVE_T, "heading_deg": WAVE_HEADING},
           "friction": {"mu_kT": MU_KT, "mu_kA": MU_KA, "mc": MC, "cv": CV}}
    dur = {"wind": 200.0 if quick else 1200.0, "waves": 120.0 if quick else 300.0}
    window = {"wind": 60.0 if quick else 400.0, "waves": 4 * WAVE_T if quick else 10 * WAVE_T}
    ramp = 100.0 if quick else 600.0
    bathys = ("flat", "upslope") if quick else BATHYMETRIES
    means, ranges, hist, profiles = {}, {}, {}, {}
    for b in bathys:
        means[b], ranges[b] = {}, {}
        for load in ("wind", "waves"):
            means[b][load], ranges[b][load] = {}, {}
            for fr, model in (("with", "directional"), ("without", "without")):
                t0 = time.time()
                t, ten, pose, prof = run_case(ds, b, model, load, dur[load], ramp=ramp)
                sel = t >= t[-1] - window[load]
                means[b][load][fr] = float(ten[sel].mean())
                ranges[b][load][fr] = [float(ten[sel].min()), float(ten[sel].max())]
                hist[(b, load, fr)] = (t, ten, pose)
                profiles[(b, load, fr)] = prof
                timing[f"{b}_{load}_{fr}_s"] = time.time() - t0
                print(f"{b:10s} {load:6s} friction {fr:8s} mean fairlead tension {means[b][load][fr] / 1e3:9.1f} kN "
                      f"surge {pose[sel, 0].mean():7.2f} m ({time.time() - t0:.0f} s)", flush=True)
    res["fairlead_tension_mean_n"] = means
    res["statics"] = {b: statics(ds, b) for b in bathys}
    res["fairlead_tension_range_n"] = ranges
    # moorline's stick-slip friction (the paper's OrcaFlex counterpart), same coefficients
    stick = {}
    for b in (("flat",) if quick else bathys):
        stick[b] = {}
        for load in ("wind", "waves"):
            t0 = time.time()
            t, ten, pose, prof = run_case(ds, b, "stickslip", load, dur[load], ramp=ramp)
            sel = t >= t[-1] - window[load]
            stick[b][load] = float(ten[sel].mean())
            profiles[(b, load, "stickslip")] = prof
            hist[(b, load, "stickslip")] = (t, ten, pose)
            timing[f"{b}_{load}_stickslip_s"] = time.time() - t0
            print(f"{b:10s} {load:6s} stick-slip mean fairlead tension {stick[b][load] / 1e3:9.1f} kN "
                  f"({time.time() - t0:.0f} s)", flush=True)
    res["fairlead_tension_mean_n_stickslip"] = stick
    t0 = time.time()
    res["grounded_chain_tension_loaded_n"] = loaded_grounded_chain(ds)
    timing["loaded_grounded_chain_s"] = time.time() - t0
    # the grounded chain's tensions at the end of each run: line 1 (upwind under the thrust) and line 2
    res["grounded_chain_tension_n"] = {}
    for (b, load, fr), prof in profiles.items():
        for ln, p in prof.items():
            on = np.array(p["node_z"]) < np.array(p["seabed_z"]) + 0.5
            seg_on = on[:-1] & on[1:]
            T = np.array(p["segment_tension"])[seg_on]
            res["grounded_chain_tension_n"].setdefault(b, {}).setdefault(load, {}).setdefault(ln, {})[fr] = {
                "segments": int(seg_on.sum()), "max": float(T.max()) if T.size else None,
                "min": float(T.min()) if T.size else None, "anchor_tension": float(p["segment_tension"][0])}
    # single-line friction cases
    cases = {}
    d_ax = d_tr = 1500.0  # single-line cases (seconds of wall time): as the full run, steady sliding needs them
    for fr in ("directional", "stickslip"):
        t0 = time.time()
        t, h, e = axial_case(fr, d_ax)
        sel = t >= t[-1] - 200.0
        cases[f"axial_{fr}"] = {"fairlead_pull_n": float(h[sel].mean()), "closed_form_n": float(e[sel].mean()),
                                "ratio": float(h[sel].mean() / e[sel].mean())}
        hist[("axial", fr)] = (t, h, e)
        print(f"axial {fr}: pull {h[sel].mean() / 1e3:.1f} kN, mu_kA sum N {e[sel].mean() / 1e3:.1f} kN "
              f"({time.time() - t0:.0f} s)", flush=True)
    for fr in ("without", "directional", "stickslip"):
        t0 = time.time()
        t, mom, e = transverse_case(fr, d_tr)
        sel = t >= t[-1] - 100.0
        cases[f"transverse_{fr}"] = {"moment_nm": float(mom[sel].mean()), "closed_form_nm": float(e[sel].mean())}
        hist[("transverse", fr)] = (t, mom, e)
        print(f"transverse {fr}: moment {mom[sel].mean() / 1e6:.2f} MN m, Coulomb bound "
              f"{e[sel].mean() / 1e6:.2f} MN m ({time.time() - t0:.0f} s)", flush=True)
    for fr in ("directional", "stickslip"):
        c = cases[f"transverse_{fr}"]
        c["friction_moment_nm"] = c["moment_nm"] - cases["transverse_without"]["moment_nm"]
        c["ratio"] = c["friction_moment_nm"] / c["closed_form_nm"]
    res["friction_cases"] = cases
    timing["total_s"] = time.time() - t_start
    res["run_time_s"] = timing
    out = HERE / ("results_quick.json" if quick else "results.json")
    out.write_text(json.dumps(res, indent=1, default=float) + "\n")
    print(f"wrote {out} in {timing['total_s']:.0f} s")
    (HERE / ("tables_quick.md" if quick else "tables.md")).write_text(tables(res))
    if not quick:
        figures(res, hist, profiles)
    return res


def statics_only():
    """Recompute the ``statics`` entry of results.json (all four bathymetries) and its tables, keeping the
    time-domain results: the equilibria take about a minute per slope, the full run about ten."""
    out = HERE / "results.json"
    res = json.loads(out.read_text())
    ds = coefficients()
    t0 = time.time()
    for b in BATHYMETRIES:
        start_at_equilibrium(moorline.System(build(ds, b, "without")), ds, b)
        res["statics"][b] = statics(ds, b)
        st = res["statics"][b]
        print(f"{b:10s} line-1 fairlead tension: ours {st['ours_dynamic_statics']['fairlead'][0] / 1e3:.2f} kN, "
              f"MoorPy {st['moorpy']['fairlead'][0] / 1e3:.2f} kN ({time.time() - t0:.0f} s)", flush=True)
    res["run_time_s"]["statics_only_s"] = time.time() - t0
    out.write_text(json.dumps(res, indent=1, default=float) + "\n")
    (HERE / "tables.md").write_text(tables(res))
    return res


def tables(res) -> str:
    f = res["fairlead_tension_mean_n"]
    rng = res["fairlead_tension_range_n"]
    out = ["| bathymetry | wind, friction | wind, no friction | wind, stick-slip | waves, friction (range) | "
           "waves, no friction (range) |", "|---|---|---|---|---|---|"]
    for b in f:
        ss = res["fairlead_tension_mean_n_stickslip"].get(b, {}).get("wind")
        out.append(f"| {b} | {f[b]['wind']['with'] / 1e3:.1f} | {f[b]['wind']['without'] / 1e3:.1f} | "
                   + (f"{ss / 1e3:.1f}" if ss is not None else "-") + " | "
                   + " | ".join(f"{f[b]['waves'][fr] / 1e3:.1f} ({rng[b]['waves'][fr][0] / 1e3:.0f}-"
                                f"{rng[b]['waves'][fr][1] / 1e3:.0f})" for fr in ("with", "without")) + " |")
    out += ["", "| grounded chain at the end of the run | segments on the seabed | tension min-max [kN] | "
            "anchor tension [kN] |", "|---|---|---|---|"]
    for b, d in res["grounded_chain_tension_n"].items():
        for load, dl in d.items():
            for ln, dd in dl.items():
                for fr, v in dd.items():
                    mm = f"{v['min'] / 1e3:.1f}-{v['max'] / 1e3:.1f}" if v["min"] is not None else "-"
                    out.append(f"| {b}, {load}, {ln}, {fr} | {v['segments']} | {mm} | "
                               f"{v['anchor_tension'] / 1e3:.1f} |")
    out += ["", "| statics (no load, frictionless): bathymetry | platform surge / sway / heave [m] | fairlead tension "
            "[kN], lines 1 / 2 / 3: ours dynamic; ours quasi-static; MoorPy | line 1 anchor tension [kN]: ours "
            "dynamic / ours quasi-static / MoorPy | MoorPy's net force on the line-1 junction at ours [kN] | "
            "grounded chains' plan bow, lines 1 / 2 / 3 [m] |", "|---|---|---|---|---|---|"]

    def fmt(vals, sep=" / "):
        return sep.join("failed" if v is None else f"{v / 1e3:.1f}" for v in vals)

    for b, st in res["statics"].items():
        p = st["pose"]
        mp = st["moorpy"]
        qs = st["ours_quasistatic"]
        fl = "; ".join(fmt(v) for v in (st["ours_dynamic_statics"]["fairlead"], qs.get("fairlead", [None] * 3),
                                         mp["fairlead"] if mp else [None] * 3))
        an = [st["ours_dynamic_statics"]["anchor"][0], qs["anchor"][0] if "anchor" in qs else None,
              mp["anchor"][0] if mp else None]
        jf = "-"
        if mp and "moorpy_at_our_junctions" in st:
            jf = f"{np.linalg.norm(st['moorpy_at_our_junctions']['junction_force_n'][0]) / 1e3:.1f}"
        bow = " / ".join(f"{v:.1f}" for v in st.get("grounded_plan_bow_m", []))
        out.append(f"| {b} | {p[0]:.2f} / {p[1]:.2f} / {p[2]:.2f} | {fl} | {fmt(an)} | {jf} | {bow or '-'} |")
    ld = res.get("grounded_chain_tension_loaded_n")
    if ld:
        out += ["", f"| loaded line 1, flat, steady wind at {ld['thrust_n'] / 1e3:.0f} kN | grounded segments | "
                "tension at the anchor / at the touchdown [kN] | gradient [N/m] (mu_kA W = "
                f"{ld['friction_gradient_n_per_m']:.0f}) |", "|---|---|---|---|"]
        for fr in ("with", "without", "stickslip"):
            v = ld[fr]
            T = v["segment_tension_n"]
            g = v.get("gradient_n_per_m")
            out.append(f"| {fr} | {v['segments']} | " + (f"{T[0] / 1e3:.1f} / {T[-1] / 1e3:.1f}" if T else "-")
                       + " | " + ("-" if g is None else f"{g:.0f}") + " |")
    c = res["friction_cases"]
    out += ["", "| single-line case | ours | closed form | ratio |", "|---|---|---|---|"]
    for fr in ("directional", "stickslip"):
        a = c[f"axial_{fr}"]
        out.append(f"| axial, {fr}: fairlead pull [kN] vs mu_kA sum N | {a['fairlead_pull_n'] / 1e3:.1f} | "
                   f"{a['closed_form_n'] / 1e3:.1f} | {a['ratio']:.3f} |")
    for fr in ("directional", "stickslip"):
        a = c[f"transverse_{fr}"]
        out.append(f"| transverse, {fr}: friction moment about the anchor [MN m] vs its bound mu_kT sum(r N) | "
                   f"{a['friction_moment_nm'] / 1e6:.2f} | {a['closed_form_nm'] / 1e6:.2f} | {a['ratio']:.3f} |")
    return "\n".join(out) + "\n"


def figure_loaded(res):
    """Segment tension along line 1's grounded chain under the reduced thrust, the three friction settings."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ld = res["grounded_chain_tension_loaded_n"]
    fig, ax = plt.subplots(figsize=(7, 4))
    for fr, lab, ls in (("without", "no friction", "--"), ("with", "MoorDyn-F directional saturated damping", "-"),
                        ("stickslip", "moorline stick-slip", ":")):
        T = np.array(ld[fr]["segment_tension_n"])
        ax.plot((np.arange(T.size) + 0.5) * ld["segment_length_m"], T / 1e3, ls, marker="o", ms=3, label=lab)
    ax.set_xlabel("distance along the grounded chain from the anchor [m]")
    ax.set_ylabel("segment tension [kN]")
    ax.set_title(f"line 1 (loaded), flat seabed, steady thrust {ld['thrust_n'] / 1e3:.0f} kN")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(HERE / "grounded_tension_loaded.png", dpi=90)
    plt.close(fig)


def figures(res, hist, profiles):
    figure_loaded(res)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cols = dict(zip(BATHYMETRIES, ("k", "C0", "C3", "C2"), strict=True))
    fig, axs = plt.subplots(2, 1, figsize=(8, 6))
    for ax, load in zip(axs, ("wind", "waves"), strict=True):
        for b in BATHYMETRIES:
            for fr, ls in (("with", "-"), ("without", "--"), ("stickslip", ":")):
                if (b, load, fr) not in hist:
                    continue
                t, ten, _ = hist[(b, load, fr)]
                lab = {"with": "directional friction", "without": "no friction", "stickslip": "stick-slip"}[fr]
                ax.plot(t, ten / 1e3, color=cols[b], ls=ls, lw=1.0, label=f"{b}, {lab}")
        ax.set_ylabel("line 1 fairlead tension [kN]")
        ax.set_title(f"{load}: " + (f"thrust {THRUST / 1e6:.2f} MN at {HUB_HEIGHT:.0f} m along +x (towards line 2/3)"
                                     if load == "wind" else f"regular wave H {WAVE_H} m, T {WAVE_T} s, 90 deg"))
        ax.grid(alpha=0.3)
    axs[0].legend(fontsize=7, ncol=2)
    axs[1].set_xlabel("time [s]")
    fig.tight_layout()
    fig.savefig(HERE / "fairlead_tension.png", dpi=90)
    plt.close(fig)

    fig, axs = plt.subplots(2, 4, figsize=(12, 6.4), sharey="row")
    for row, (load, ln) in enumerate((("waves", "line1"), ("wind", "line2"))):
        for ax, b in zip(axs[row], BATHYMETRIES, strict=True):
            for fr, col, lab in (("without", "0.6", "no friction"), ("with", "C0", "MoorDyn-F directional saturated"),
                                 ("stickslip", "C3", "moorline stick-slip")):
                prof = profiles.get((b, load, fr), {}).get(ln)
                if prof is None:
                    continue
                xy = np.array(prof["node_xy"])
                s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(xy, axis=0).T))])
                sm = 0.5 * (s[1:] + s[:-1])
                on = np.array(prof["node_z"]) < np.array(prof["seabed_z"]) + 0.5
                seg_on = on[:-1] & on[1:]
                T = np.array(prof["segment_tension"]) / 1e3
                ax.plot(sm, T, color=col, lw=0.8, alpha=0.5)
                ax.plot(sm[seg_on], T[seg_on], "o-", color=col, ms=3, lw=1.2, label=lab)
            ax.set_title(f"{b}: {ln.replace('line', 'line ')}, {load}", fontsize=9)
            ax.set_xlabel("distance from anchor (plan) [m]")
            ax.grid(alpha=0.3)
        axs[row][0].set_ylabel("chain segment tension [kN]")
    axs[0][0].legend(fontsize=7)
    fig.suptitle("chain tension at the end of the run (markers: segments lying on the seabed)", fontsize=9)
    fig.tight_layout()
    fig.savefig(HERE / "grounded_tension.png", dpi=90)
    plt.close(fig)

    fig, axs = plt.subplots(1, 2, figsize=(10, 3.4))
    for fr, col in (("directional", "C0"), ("stickslip", "C3")):
        t, h, e = hist[("axial", fr)]
        axs[0].plot(t, h / 1e3, color=col, label=f"{fr}: fairlead pull")
        axs[0].plot(t, e / 1e3, color=col, ls=":", label=f"{fr}: mu_kA sum N")
    axs[0].set_title("axial: anchor released, fairlead pulled at 0.2 m/s")
    axs[0].set_xlabel("time [s]")
    axs[0].set_ylabel("[kN]")
    for fr, col in (("without", "0.5"), ("directional", "C0"), ("stickslip", "C3")):
        t, mom, e = hist[("transverse", fr)]
        axs[1].plot(t, mom / 1e6, color=col, label=f"{fr}: moment of the pull about the anchor")
        if fr != "without":
            t0, m0, _ = hist[("transverse", "without")]
            axs[1].plot(t, (m0 + e) / 1e6, color=col, ls=":", label=f"{fr}: no-friction + mu_kT sum(r N)")
    axs[1].set_title("transverse: fairlead swept around the anchor at 0.9 m/s")
    axs[1].set_xlabel("time [s]")
    axs[1].set_ylabel("[MN m]")
    for a in axs:
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(HERE / "friction_cases.png", dpi=90)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(0 if main() else 1)
