"""The Waves4Power buoy, its four chains and its free-hanging power cable (Yang, Ringsberg & Johnson
2018, J. Mar. Sci. Technol. 23:10-29), as a moorline model, and one case of the fatigue study:
one cable design in one regular sea state, post-processed to damage rates along the cable.

Kept apart from ``run.py`` so that the case function can be pickled by reference and run in the
worker processes of :func:`moorline.studies.executors.run_local`.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field

import numpy as np

import moorline
from moorline import hydro
from moorline.model import Model, MorisonStrip
from moorline.model.water import Current, Waves
from moorline.post import SNCurve, TubeSection, cross_section_stress, fatigue_damage, section_loads

log = logging.getLogger("w4p")

RHO, G, DEPTH = 1025.0, 9.81, 50.0
# ---------------------------------------------------------------- the buoy (Table 1 of the paper)
DRAFT, MASS = 27.8, 353.8e3  # [m], [kg]
ZB, ZG = -10.9, -11.8  # centres of buoyancy and gravity [m]
PTO_HEAVE = 197.1e3  # [N s/m] linear PTO damping in heave (to the ground)
#: assumed (not in the paper): float radius; the float draft and the tube radius follow from the
#: displaced volume (MASS / RHO) and the centre of buoyancy (:func:`hull_dimensions`)
FLOAT_RADIUS = 4.0
#: assumed: radius of gyration about the CG in roll/pitch and yaw [m]
GYRATION = (8.0, 8.0, 2.5)
TUBE_CD = 1.0  # assumed Morison drag coefficient of the tube
#: assumed (the paper is silent): linear yaw damping of the buoy [N m s/rad], for the viscous yaw
#: damping that the axisymmetric potential-flow hull and the tube's Morison strips do not give.
#: Without it the yaw is parametrically unstable in waves (single condition: growth 0.0255 1/s,
#: threshold 1.13e5 N m s/rad; the hull's skin friction gives 7.6e3): 2e5 is 17 % of critical,
#: 1.8 x the threshold (README, "Yaw damping, and the run length"); 0 reproduces the instability
YAW_DAMPING = 2.0e5
# ---------------------------------------------------------------- moorings
CHAIN = {"L": 100.0, "d": 0.086, "w": 45.0, "EA": 193.0e6, "Cd": 2.5, "Ca": 3.8, "CdAx": 0.5, "N": 20}
FAIRLEADS = [(sx * 1.24, sy * 1.24, -5.0) for sx, sy in ((1, 1), (-1, 1), (-1, -1), (1, -1))]
ANCHOR_RADIUS = 77.58  # [m] in plan, along the fairleads' bearings
# ---------------------------------------------------------------- the cable
HUB = (54.0, 0.0, -1.0)  # [m] a fixed point near the surface
CABLE_ATTACH_Z = -1.0  # assumed: the buoy-side connector depth on the float's side [m]
SEGMENT = 0.7  # [m] element length
DESIGNS = {"initial": {"w": 2.75, "EI": 350.0, "L": 70.0}, "improved": {"w": 2.00, "EI": 50.0, "L": 70.0}}
CABLE = {"d": 0.040, "di": 0.020, "EA": 94.3e3, "Cd": 1.2, "Ca": 1.0, "CdAx": 0.0, "CaAx": 0.0, "BA": -0.5}
CURRENT = 1.0  # [m/s]
HEADING = 180.0  # [deg] waves and current travel toward -x: from the hub toward the buoy
#: S-N curve of the copper conductor (examples/w4p_study): N = 6.098e19 S^-6.238, S in MPa
SN = SNCurve.one_slope(6.098e19, 6.238, unit=1e6)
EXCLUDE_ELEMENTS = 2  # the first two elements at each end are left out of the fatigue result


def hull_dimensions(float_radius: float = FLOAT_RADIUS) -> dict:
    """Float draft and tube radius such that the float (a cylinder of the given radius) on a
    central tube to the draft displaces MASS / RHO with its centre of buoyancy at ZB.

    Solved by bisection on the float draft h: the tube area follows from the volume, and the
    centre of buoyancy rises monotonically with h.
    """
    V = MASS / RHO
    af = math.pi * float_radius**2

    def zb(h):
        at = (V - af * h) / (DRAFT - h)
        return (af * h * (-h / 2) + at * (DRAFT - h) * (-(DRAFT + h) / 2)) / V, at

    lo, hi = 1e-3, min(DRAFT - 1e-3, V / af - 1e-6)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        z, _ = zb(mid)
        if z < ZB:
            lo = mid
        else:
            hi = mid
    h = 0.5 * (lo + hi)
    z, at = zb(h)
    return {"float_radius": float_radius, "float_draft": h, "tube_radius": math.sqrt(at / math.pi), "volume": V,
            "zb": z}


def profile(dims: dict) -> np.ndarray:
    """Meridian of the hull (keel to waterline) with panels of about 0.5-1 m."""
    rt, rf, hf = dims["tube_radius"], dims["float_radius"], dims["float_draft"]
    pts = [(0.0, -DRAFT)]
    for a, b, n in (((0.0, -DRAFT), (rt, -DRAFT), 3), ((rt, -DRAFT), (rt, -hf), 26), ((rt, -hf), (rf, -hf), 4),
                    ((rf, -hf), (rf, 0.0), 3)):
        for s in np.linspace(0.0, 1.0, n + 1)[1:]:
            pts.append((a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])))
    return np.array(pts)


def coefficients(dims: dict, cache_dir=None):
    """Capytaine coefficients of the buoy about the waterline centre, with a lid (cached)."""
    mesh = hydro.mesh_axisymmetric(profile(dims), n_theta=24)
    return hydro.compute_coefficients(mesh, omega=np.linspace(0.2, 3.2, 31), wave_direction=[math.radians(HEADING)],
                                      rho=RHO, g=G, water_depth=DEPTH,
                                      rotation_center=[0.0, 0.0, 0.0], lid=True, cache_dir=cache_dir)


@dataclass
class CaseSpec:
    """One case: a cable design in one regular sea state (H, T), or in still water (H = 0)."""

    design: dict
    H: float
    T: float
    label: str = ""
    duration: float = 1500.0
    window: float = 600.0
    dtM: float = 0.02
    samples_per_period: int = 40
    coefficients: object = None
    dims: dict = field(default_factory=hull_dimensions)
    yaw_damping: float = YAW_DAMPING
    keep_series: bool = False


def build(spec: CaseSpec, *, sea: bool = True) -> Model:
    """The coupled model: buoy (body 0) on four chains (lines 1-4) and the cable (line 5, end A at
    the buoy, clamped to a connector rod on the float's side, end B clamped to a fixed rod at the
    hub)."""
    dims = spec.dims
    m = Model()
    m.env.rho, m.env.g, m.env.depth = RHO, G, DEPTH
    m.env.kBot, m.env.cBot = 1.0e5, 1.0e3
    m.options.tScheme = "GenAlpha"
    m.options.dtM = spec.dtM
    I = tuple(MASS * r**2 for r in GYRATION)  # noqa: E741
    b = m.add_body("free", (0.0, 0.0, 0.0), m=MASS, rCG=(0.0, 0.0, ZG), I=I)
    m.add_line_type("chain", d=CHAIN["d"], w=CHAIN["w"], EA=CHAIN["EA"], BA=-0.8, Cd=CHAIN["Cd"], Ca=CHAIN["Ca"],
                    CdAx=CHAIN["CdAx"], CaAx=0.0)
    for f in FAIRLEADS:
        bearing = math.atan2(f[1], f[0])
        fl = m.add_point("body", f, body=b)
        an = m.add_point("fixed", (ANCHOR_RADIUS * math.cos(bearing), ANCHOR_RADIUS * math.sin(bearing), -DEPTH))
        m.add_line("chain", an, fl, L=CHAIN["L"], N=CHAIN["N"])
    d = spec.design
    m.add_line_type("cable", d=CABLE["d"], w=d["w"], EA=CABLE["EA"], BA=CABLE["BA"], EI=d["EI"], Cd=CABLE["Cd"],
                    Ca=CABLE["Ca"], CdAx=CABLE["CdAx"], CaAx=CABLE["CaAx"])
    m.add_rod_type("connector", d=0.2, w=10.0)
    rf = dims["float_radius"]
    _, buoy_end = m.add_rod("connector", "body", (rf - 0.5, 0.0, CABLE_ATTACH_Z), (rf, 0.0, CABLE_ATTACH_Z), N=1,
                            body=b)
    hub_end, _ = m.add_rod("connector", "fixed", HUB, (HUB[0] + 0.5, HUB[1], HUB[2]), N=1)
    n = int(round(d["L"] / SEGMENT))
    m.add_line("cable", buoy_end, hub_end, L=d["L"], N=n)
    ds = spec.coefficients if spec.coefficients is not None else coefficients(dims)
    m.add_hydro([b], ds)
    damp = np.zeros(6)
    damp[2] = PTO_HEAVE
    damp[5] = spec.yaw_damping
    tube = MorisonStrip((0.0, 0.0, -DRAFT), (0.0, 0.0, -dims["float_draft"]), 2 * dims["tube_radius"],
                                       TUBE_CD, 14)
    m.add_floating(b, linear_damping=damp, morison=[tube])
    if not sea:
        return m
    m.env.current = current_ramp(CURRENT, HEADING)
    if spec.H > 0:
        m.env.waves = Waves.regular(spec.H, spec.T, heading=HEADING, ramp_time=min(5 * spec.T, 60.0))
    m.env.waves_on_lines = True
    return m


CURRENT_RAMP = 60.0  # [s] the current is ramped in from still water (see current_ramp)


def current_ramp(speed: float, heading: float) -> Current:
    """A uniform current switched on linearly over CURRENT_RAMP seconds from rest.

    Newton statics does not converge for this light cable in the 1 m/s current (the drag, 25 N/m,
    is nearly twice its wet weight: residual 1.4 m/s^2 after 430 iterations); the still-water
    equilibrium converges (:func:`equilibrium`), and the dynamic run brings the current in. It is
    part of the transient that the analysis window leaves out.
    """
    c, s = math.cos(math.radians(heading)), math.sin(math.radians(heading))
    t = np.array([0.0, CURRENT_RAMP, 1.0e7])
    z = np.array([-DEPTH - 1.0, 1.0])
    f = np.array([[0.0, 0.0], [1.0, 1.0], [1.0, 1.0]]) * speed
    return Current.dynamic_profile(t, z, f * c, f * s)


def hull_clearance(pos_body: np.ndarray, dims: dict) -> np.ndarray:
    """Distance [m] from points in body axes (..., 3) to the hull (float cylinder from its draft to
    1 m above the waterline, tube to the keel); negative inside."""
    r = np.hypot(pos_body[..., 0], pos_body[..., 1])
    z = pos_body[..., 2]

    def cyl(radius, z0, z1):
        dr = r - radius
        dz = np.maximum(z0 - z, z - z1)
        out = np.hypot(np.maximum(dr, 0.0), np.maximum(dz, 0.0))
        inside = np.minimum(np.maximum(dr, dz), 0.0)
        return out + inside

    return np.minimum(cyl(dims["float_radius"], -dims["float_draft"], 1.0), cyl(dims["tube_radius"], -DRAFT,
                                                                                -dims["float_draft"]))


def _rotation(angles):
    from moorline.model.types import rotation_xyz

    return rotation_xyz(angles)


def equilibrium(spec: CaseSpec, m: Model):
    """A System of model ``m`` started from the still-water equilibrium (Newton statics of the same
    model without current and waves, whose state vector is the same)."""
    still = moorline.System(build(spec, sea=False))
    still.init()
    s = moorline.System(m)
    s.init(solve_ic=False)
    s.y[:] = still.y
    s.set_state()
    s.ic_report = dict(still.ic_report)
    return s


def run_case(spec: CaseSpec) -> dict:
    """Run one case and post-process the analysis window (the last ``spec.window`` seconds).

    Returns
    -------
    dict
        ``s`` (arc length from the WEC, per node), ``damage_rate`` (node, theta) [1/s] of the
        12-point tensile stress, ``curvature_max``/``tension_max``/``tension_min`` envelopes,
        ``min_clearance`` [m] of the cable nodes (beyond the first two elements) to the hull,
        buoy motion amplitudes, timings.
    """
    wall0 = time.perf_counter()
    m = build(spec)
    s = equilibrium(spec, m)
    line = len(m.lines)  # the cable, 1-based
    transient = spec.duration - spec.window
    if spec.H > 0:
        dt_out = spec.T / spec.samples_per_period
        n_per = max(1, int(math.floor(spec.window / spec.T + 1e-9)))
        window = n_per * spec.T
        transient = spec.duration - window
    else:
        dt_out, window = 0.5, spec.window
    if transient > 0:
        moorline.simulate(s, transient, dt_out=transient, progress=False, record_nodes=False)
    r = moorline.simulate(s, window, dt_out=dt_out, progress=False)
    periodic = spec.H > 0
    an = r.isel(time=slice(0, -1)) if periodic else r
    sec = section_loads(an, line, model=m)
    st = cross_section_stress(sec, TubeSection(CABLE["d"], CABLE["di"]), n_theta=12, tensile_only=True)
    dmg = fatigue_damage(st, SN, periodic=periodic) / window
    nodes = np.flatnonzero(an.node_line.values == line)
    s_arc = an.node_s.values[nodes] if "node_s" in an.coords else np.arange(nodes.size) * SEGMENT
    curv = an.node_curvature.isel(node=nodes).values
    ten = an.node_tension.isel(node=nodes).values
    pos = an.node_position.isel(node=nodes).values  # (time, node, 3)
    pose = an.body_pose.values[:, 0, :]
    rel = pos - pose[:, None, :3]
    body_pos = np.empty_like(rel)
    for k in range(pose.shape[0]):
        body_pos[k] = rel[k] @ _rotation(pose[k, 3:])  # R^T applied to each row
    clear = hull_clearance(body_pos, spec.dims)
    # periodicity of the analysed record: the largest change of a node position over one period,
    # relative to the largest range of a node position over the window
    if periodic:
        spp = int(round(spec.T / dt_out))
        drift = float(np.abs(pos[spp:] - pos[:-spp]).max()) if pos.shape[0] > spp else float("nan")
        periodicity = drift / max(float(np.ptp(pos, axis=0).max()), 1e-12)
    else:
        periodicity = float("nan")
    keep = np.arange(nodes.size)
    keep = keep[(keep >= EXCLUDE_ELEMENTS) & (keep <= nodes.size - 1 - EXCLUDE_ELEMENTS)]
    out = {"label": spec.label, "H": spec.H, "T": spec.T, "design": spec.design, "s": np.asarray(s_arc, float),
           "damage_rate": np.asarray(dmg.values, float), "theta": np.asarray(dmg.theta.values, float),
           "curvature_max": curv.max(axis=0), "curvature_min": curv.min(axis=0),
           "tension_max": ten.max(axis=0), "tension_min": ten.min(axis=0),
           "min_clearance": float(clear[:, keep].min()), "min_clearance_node": int(keep[np.argmin(clear[:, keep].min(
               axis=0))]), "heave_range": float(np.ptp(pose[:, 2])), "surge_range": float(np.ptp(pose[:, 0])),
           "surge_mean": float(np.mean(pose[:, 0])), "pitch_range": float(np.ptp(pose[:, 4])),
           "roll_range": float(np.ptp(pose[:, 3])), "yaw_range": float(np.ptp(pose[:, 5])),
           "z_mean": float(np.mean(pose[:, 2])),
           "cable_z_min": float(pos[:, :, 2].min()), "periodicity": periodicity, "ic": dict(s.ic_report),
           "wall_time_s": time.perf_counter() - wall0}
    if spec.keep_series:
        out["series"] = {"t": an.time.values, "pose": pose, "pos": pos}
    return out
