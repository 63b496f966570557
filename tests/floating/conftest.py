"""Shared builders of the floating-body tests: an analytic one-pole radiation body, the RM3 WAMIT set."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from moorline import hydro
from moorline.model import Model

SHARED = Path(__file__).resolve().parents[2].parent / "shared"
RM3 = SHARED / "data" / "rm3" / "rm3"

#: the analytic body: mass, heave stiffness, infinite-frequency added mass and a radiation damping
#: shaped as a real hull's, B33(w) = BETA w^2 / prod_k (L_k^2 + w^2): zero at w = 0, peaked, decaying
#: as w^-4 (so the computed band holds it). Its kernel is exactly three exponentials,
#: K33(t) = sum_k C_k exp(-L_k t) with C_k L_k the partial-fraction residues of B33 in w^2, and
#: A33(w) = A_INF - sum_k C_k / (L_k^2 + w^2) (Ogilvie's relations, exact)
MASS = 1.0e5
C33 = 1.0e6
C_ROT = 5.0e6  # roll and pitch stiffness [N m/rad]
A_INF = 5.0e4
BETA = 2.0e5
L = (0.5, 1.0, 2.0)
C = tuple(BETA * (-lk**2) / np.prod([lm**2 - lk**2 for lm in L if lm != lk]) / lk for lk in L)
X33 = 1.0e5  # heave excitation per metre of wave amplitude, Capytaine convention (real: in phase)
RHO = 1025.0
G = 9.80665


def added_mass_33(w):
    return A_INF - sum(ck / (lk**2 + w**2) for ck, lk in zip(C, L, strict=True))


def damping_33(w):
    return sum(ck * lk / (lk**2 + w**2) for ck, lk in zip(C, L, strict=True))


def three_pole_dataset(omega=None) -> object:
    """A single body whose only radiation is the three-pole heave kernel; heave excitation X33 at every
    frequency (a long-wave-like, in-phase force); buoyancy rho g V = MASS g at the reference point."""
    w = np.linspace(0.02, 8.0, 400) if omega is None else np.asarray(omega, dtype=float)
    nw = w.size
    A = np.zeros((nw, 6, 6))
    B = np.zeros((nw, 6, 6))
    ainf = np.diag([2.0e4, 2.0e4, A_INF, 1.0e5, 1.0e5, 1.0e5])
    A[:] = ainf
    A[:, 2, 2] = added_mass_33(w)
    B[:, 2, 2] = damping_33(w)
    X = np.zeros((nw, 1, 6), dtype=complex)
    X[:, 0, 2] = X33
    Ch = np.diag([0.0, 0.0, C33, C_ROT, C_ROT, 0.0])
    return hydro.build_dataset(omega=w, wave_direction=[0.0], body_names=["buoy"], added_mass=A, radiation_damping=B,
                               added_mass_inf=ainf, excitation_force=X, hydrostatic_stiffness=Ch,
                               displaced_volume=[MASS / RHO], center_of_buoyancy=[[0.0, 0.0, 0.0]],
                               rotation_center=[[0.0, 0.0, 0.0]], rho=RHO, g=G, water_depth=np.inf)


def three_pole_model(scheme="RK4", dtM=0.01, **hydro_options) -> Model:
    m = Model()
    m.env.rho = RHO
    m.env.g = G
    m.env.depth = 500.0
    m.options.tScheme = scheme
    m.options.dtM = dtM
    b = m.add_body("free", (0, 0, 0), m=MASS, I=(1.0e6, 1.0e6, 1.0e6))
    m.add_hydro([b], three_pole_dataset(), **hydro_options)
    return m


@pytest.fixture(scope="session")
def rm3():
    if not RM3.with_suffix(".1").exists():
        pytest.skip("../shared/data/rm3 (the public RM3 WAMIT set) is not present")
    return hydro.read_wamit(RM3, rho=1000.0, g=9.81)


#: RM3 mass properties (public RM3 reference values): masses are rho V of the WAMIT volumes
RM3_CG = ((0.0, 0.0, -0.72), (0.0, 0.0, -21.29))
RM3_I = ((20907301.0, 21306090.66, 37085481.11), (94419614.57, 94407091.24, 28542224.82))
RM3_PTO_DAMPING = 1.2e6


def rm3_model(ds, *, scheme="RK4", dtM=0.01, pto=True, **hydro_options) -> Model:
    """Float and spar/plate on their WAMIT coefficients, the float sliding on the spar with a linear
    PTO damper (no moorings), rho 1000 kg/m^3 and deep water as the WAMIT run."""
    V = ds["displaced_volume"].values
    m = Model()
    m.env.rho = 1000.0
    m.env.g = 9.81
    m.env.depth = 1000.0
    m.options.tScheme = scheme
    m.options.dtM = dtM
    f = m.add_body("free", RM3_CG[0], m=1000.0 * V[0], I=RM3_I[0])
    s = m.add_body("free", RM3_CG[1], m=1000.0 * V[1], I=RM3_I[1])
    m.add_hydro([f, s], ds, **hydro_options)
    if pto:
        m.add_joint(f, s, axis=(0.0, 0.0, 1.0), pto_damping=RM3_PTO_DAMPING)
    return m


def rm3_mass_matrix(ds):
    V = ds["displaced_volume"].values
    return hydro.mass_matrix([1000.0 * V[0], 1000.0 * V[1]], RM3_CG, RM3_I, RM3_CG)


def steady_amplitude(t, x, omega, periods: float):
    """Complex amplitude (cos - i sin convention: x ~ Re(c exp(-i w t)) + mean + drift) of the
    last ``periods`` periods of ``x`` by least squares."""
    T = 2 * np.pi / omega
    sel = t >= t[-1] - periods * T - 1e-9
    X = np.column_stack([np.ones(sel.sum()), t[sel], np.cos(omega * t[sel]), np.sin(omega * t[sel])])
    coef, *_ = np.linalg.lstsq(X, x[sel], rcond=None)
    return coef[2] + 1j * coef[3]


# ------------------------------------------------------------------ a spar on three catenaries
SPAR_DEPTH = 320.0
SPAR_MASS = 8.066e6  # platform with a rigid turbine [kg]
SPAR_RCG = (0.0, 0.0, -78.0)
SPAR_INERTIA = (6.0e9, 6.0e9, 1.6e8)
YAW_SPRING = 98.34e6  # the OC3 delta connection's yaw stiffness [N m/rad]


def _profile():
    """Meridian of the OC3 hull: 9.4 m diameter to 120 m draft, tapering between 12 m and 4 m below
    the surface to 6.5 m; panels of about 4 m along it."""
    pts = [(0.0, -120.0)]
    for a, b, n in (((0.0, -120.0), (4.7, -120.0), 3), ((4.7, -120.0), (4.7, -12.0), 27),
                    ((4.7, -12.0), (3.25, -4.0), 4), ((3.25, -4.0), (3.25, 0.0), 2)):
        for s in np.linspace(0.0, 1.0, n + 1)[1:]:
            pts.append((a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])))
    return np.array(pts)


@pytest.fixture(scope="session")
def spar(tmp_path_factory):
    """OC3-Hywind-like spar hull: Capytaine coefficients (once per session)."""
    pytest.importorskip("capytaine")
    return hydro.compute_coefficients(hydro.mesh_axisymmetric(_profile(), n_theta=24),
                                      omega=np.linspace(0.05, 3.0, 40), rho=1025.0, g=9.80665, water_depth=SPAR_DEPTH,
                                      rotation_center=[0.0, 0.0, 0.0], cache_dir=tmp_path_factory.mktemp("hydro"))


def spar_model(ds, scheme="GenAlpha", dtM=0.1, waves=None, **floating) -> Model:
    m = Model()
    m.env.depth = SPAR_DEPTH
    m.options.tScheme = scheme
    m.options.dtM = dtM
    m.add_line_type("chain", d=0.09, w=77.7066, EA=384.243e6, BA=-0.8, Cd=1.6, Ca=1.0, CdAx=0.1, CaAx=0.0)
    b = m.add_body("free", (0.0, 0.0, 0.0), m=SPAR_MASS, rCG=SPAR_RCG, I=SPAR_INERTIA)
    for k in range(3):
        a = np.radians(180.0 + 120.0 * k)
        fl = m.add_point("body", (5.2 * np.cos(a), 5.2 * np.sin(a), -70.0), body=b)
        an = m.add_point("fixed", (853.87 * np.cos(a), 853.87 * np.sin(a), -SPAR_DEPTH))
        m.add_line("chain", an, fl, L=902.2, N=20)
    m.add_hydro([b], ds)
    floating.setdefault("stiffness", [0, 0, 0, 0, 0, YAW_SPRING])
    m.add_floating(b, **floating)
    m.env.waves = waves
    m.env.waves_on_lines = False
    return m
