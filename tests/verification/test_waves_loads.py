"""Wave and current loads on structures against independent integrals.

* A fixed vertical rod (a pile) in a regular Airy wave: the horizontal load history is the
  Morison integral of 0.5 rho Cd d |u| u + rho (1 + Ca) A du/dt over the submerged length, with
  the closed-form Airy kinematics, integrated here with scipy's quad. The rod's lumped nodes are
  a trapezoid rule of that integral: with 60 segments on 28 m and k = 0.06 1/m the rule's error is
  (k dz)^2 / 12 ~ 3e-5 of the inertia part; Wheeler stretching leaves z unchanged at the nodes
  because the whole rod stays below the trough (z' = h (z + h) / (zeta + h) - h differs from z by
  at most |zeta| (z + h) / h, and the rod top is 2 m below the trough: the test evaluates the
  reference with the same stretching, so the tolerance only covers the quadrature, 1 %).
* The same pile in a uniform current: steady drag 0.5 rho Cd d U^2 L exactly.
* A vertical line held at both ends in a current: its node drag sums to the same integral.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from moorline import Model, System
from moorline.model.water import Current, Waves

RHO, G, DEPTH = 1025.0, 9.80665, 50.0
D, CD, CA = 1.2, 0.9, 1.0
Z_BOT, Z_TOP = -30.0, -2.0
H, T = 2.0, 8.0


def pile_model(waves=None, current=None, N=60) -> Model:
    m = Model()
    m.env.depth, m.env.rho, m.env.g = DEPTH, RHO, G
    m.env.waves, m.env.current = waves, current
    m.add_rod_type("pile", d=D, w=500.0, Cd=CD, Ca=CA, CdEnd=0.0, CaEnd=0.0)
    m.add_rod("pile", "fixed", (0.0, 0.0, Z_BOT), (0.0, 0.0, Z_TOP), N=N)
    m.options.dtM = 0.01
    m.options.TmaxIC = 0.0
    return m


def airy(t, z, k, w, a):
    """Horizontal velocity and acceleration at x = 0 of zeta = a cos(w t - k x), Wheeler-stretched."""
    zeta = a * math.cos(w * t)
    zs = DEPTH * (z + DEPTH) / (zeta + DEPTH) - DEPTH
    ch = math.cosh(k * (zs + DEPTH)) / math.sinh(k * DEPTH)
    return w * a * math.cos(w * t) * ch, -w * w * a * math.sin(w * t) * ch


def wave_number(w):
    k = w * w / G
    for _ in range(50):
        f = G * k * math.tanh(k * DEPTH) - w * w
        k -= f / (G * math.tanh(k * DEPTH) + G * k * DEPTH / math.cosh(k * DEPTH) ** 2)
    return k


def test_pile_in_regular_wave_matches_the_morison_integral():
    s = System(pile_model(Waves.regular(H, T)))
    s.init(solve_ic=False)
    w = 2.0 * math.pi / T
    k = wave_number(w)
    A = 0.25 * math.pi * D * D
    ours, ref = [], []
    for t in np.arange(0.0, 2 * T, 0.4):
        s.step(None, None, float(t), 0.0)  # dt = 0: evaluate the loads at time t
        ours.append(s.rods[0].force()[0])

        def dF(z, t=t):
            u, du = airy(t, z, k, w, 0.5 * H)
            return 0.5 * RHO * CD * D * abs(u) * u + RHO * (1.0 + CA) * A * du

        ref.append(quad(dF, Z_BOT, Z_TOP, epsabs=1e-6, epsrel=1e-10)[0])
    ours, ref = np.array(ours), np.array(ref)
    scale = np.abs(ref).max()
    assert scale > 1e3  # a real load: about 20 kN peak here
    np.testing.assert_allclose(ours, ref, rtol=0, atol=0.01 * scale)
    # no vertical load from waves beyond weight and buoyancy, which are steady
    assert np.ptp([s.rods[0].force()[2]]) == 0.0


def test_pile_in_uniform_current_steady_drag():
    U = 1.3
    s = System(pile_model(current=Current.uniform(U, heading=90.0)))
    s.init(solve_ic=False)
    F = s.rods[0].force()
    expected = 0.5 * RHO * CD * D * U * U * (Z_TOP - Z_BOT)
    assert F[1] == pytest.approx(expected, rel=1e-12)
    assert abs(F[0]) < 1e-9 * expected


def test_waves_are_off_during_the_initial_conditions_and_on_after():
    """MoorDyn's convention (spec 6.1): the IC solve sees the current, not the waves; the loads
    reported after init are those of waves plus current at t = 0 (a crest at the pile: the wave
    velocity is largest, the acceleration zero), i.e. pure drag on the summed velocity."""
    Uc = 0.5
    s = System(pile_model(Waves.regular(H, T), Current.uniform(Uc)))
    s.init()
    assert s.layout.env_ic.water.wave_mode == 0 and s.layout.env_ic.water.current_mode != 0
    assert s.layout.env.water.wave_mode != 0
    w = 2.0 * math.pi / T
    k = wave_number(w)

    def dF(z):
        u = Uc + airy(0.0, z, k, w, 0.5 * H)[0]
        return 0.5 * RHO * CD * D * abs(u) * u

    ref = quad(dF, Z_BOT, Z_TOP, epsrel=1e-10)[0]
    assert s.rods[0].force()[0] == pytest.approx(ref, rel=0.01)
    drag_current_only = 0.5 * RHO * CD * D * Uc * Uc * (Z_TOP - Z_BOT)
    assert ref > 1.5 * drag_current_only  # the waves really add to it


def test_line_drag_in_current_matches_integral():
    """A taut vertical line held at both ends in a uniform current: the horizontal node drag sums
    to 0.5 rho Cd d U^2 times the unstretched length (MoorDyn's drag area is d times the
    unstretched segment length, spec 3.7; the lumped nodes integrate a constant exactly)."""
    U = 0.8
    m = Model()
    m.env.depth, m.env.rho = DEPTH, RHO
    m.env.current = Current.uniform(U)
    m.add_line_type("wire", d=0.08, w=30.0, EA=1e9, BA=-0.5, Cd=1.1, Ca=1.0, CdAx=0.0, CaAx=0.0)
    a = m.add_point("fixed", (0.0, 0.0, -40.0))
    b = m.add_point("fixed", (0.0, 0.0, -10.0))
    m.add_line("wire", a, b, L=29.9, N=30)
    m.options.dtM = 1e-4
    m.options.TmaxIC = 0.0
    s = System(m)
    s.init(solve_ic=False)
    Fx = s.lines[0].node_hydro_forces()[:, 0].sum()
    assert Fx == pytest.approx(0.5 * RHO * 1.1 * 0.08 * U * U * 29.9, rel=1e-9)


def test_water_probes_record_the_sea():
    """Probes in the results give the sea's own kinematics: at a surface probe the elevation of a
    regular wave is H/2 cos(w t) (crest at the origin at t = 0), the current adds to the velocity."""
    from moorline import simulate

    s = System(pile_model(Waves.regular(H, T), Current.uniform(0.3, heading=90.0), N=4))
    ds = simulate(s, 4.0, dt_out=0.5, solve_ic=False, water_probes=[(0.0, 0.0, 0.0), (0.0, 0.0, -20.0)])
    w = 2.0 * math.pi / T
    np.testing.assert_allclose(ds.probe_elevation.sel(probe=0), 0.5 * H * np.cos(w * ds.time), atol=1e-9)
    k = wave_number(w)
    u = [airy(float(t), -20.0, k, w, 0.5 * H)[0] for t in ds.time]
    np.testing.assert_allclose(ds.probe_velocity.isel(probe=1, xyz=0), u, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(ds.probe_velocity.isel(xyz=1), 0.3, rtol=1e-12)
