"""The RM3 two-body point absorber (public WAMIT run, float sliding on the spar with a 1200 kN s/m PTO
damper, no moorings) in regular waves: the time-domain steady response against the frequency-domain
solve of the same constrained system (moorline.hydro.rao), energy conservation, and the joint.

The waves are ramped in over 10 periods and run for 80: the surge-pitch mode of the free pair is
lightly damped, and without the ramp its transient still leaks into the last periods (20 % on
pitch at 5 s). Two frequency-domain references:
- the WAMIT coefficients as they are (the issue's check, 2 %): the file's A_inf is not quite
  consistent with its A(w) and B(w) (a constant offset, -3.8 % of the peak in float surge) and its B
  is not positive semi-definite at high frequency, so a time-domain model, which must use A_inf and
  a passive kernel, differs from it by up to 0.5 % here;
- the same solve with A(w), B(w) of the fitted state-space model, i.e. the system the time loop
  integrates: this isolates the time integration (RK4 at 0.01 s: 0.3 %; generalized-alpha at
  0.05 s: 0.7 %).
"""

from __future__ import annotations

import numpy as np
import pytest

import moorline
from moorline import hydro
from moorline.model.water import Waves

from .conftest import RM3_PTO_DAMPING, rm3_mass_matrix, rm3_model, steady_amplitude

PERIODS = (11.0, 9.5, 8.0, 6.5, 5.0)  # through the peaks of absorbed power (7 s) and relative motion (8.5 s)
AMPLITUDE = 0.25  # [m]
IRF_T = np.arange(0.0, 60.0 + 0.025, 0.05)  # the model's default impulse-response window and sampling
SS_RTOL = 0.01


def _pto():
    return hydro.LinearPTO(0, 1, (0.0, 0.0, 1.0), 0.0, RM3_PTO_DAMPING)


def _run(ds, T, scheme, dtM, n_periods=80, samples=40, record_energy=False):
    m = rm3_model(ds, scheme=scheme, dtM=dtM, ss_rtol=SS_RTOL)
    m.env.waves = Waves.regular(2 * AMPLITUDE, T, ramp_time=10 * T)
    s = moorline.System(m)
    s.init()
    t = np.arange(0.0, n_periods * T + 1e-9, T / samples)
    poses, energy = [], []
    for k in range(t.size):
        if k:
            s.step(None, None, t[k - 1], t[k] - t[k - 1])
        poses.append(np.concatenate([s.bodies[0].pose(), s.bodies[1].pose()]))
        if record_energy:
            fw = s.fwork
            energy.append((fw.vel.copy(), fw.F.copy(), fw.jt[0, 2]))
    return t, np.array(poses), energy, s


@pytest.fixture(scope="module")
def references(rm3):
    w = 2 * np.pi / np.array(PERIODS)
    M = rm3_mass_matrix(rm3)
    raw = hydro.rao(rm3, M, wave_direction=0.0, omega=w, pto=_pto())
    fit = hydro.fit_state_space(rm3, t=IRF_T, rtol=SS_RTOL, max_order=10)
    A, B = fit.frequency_response(w)
    dss = rm3.interp(omega=w)
    dss["added_mass"].values[:] = A
    dss["radiation_damping"].values[:] = B
    ss = hydro.rao(dss, M, wave_direction=0.0, omega=w, pto=_pto())
    return {"raw": raw.rao.values, "ss": ss.rao.values, "raw_rel": raw.pto_displacement.values,
            "ss_rel": ss.pto_displacement.values}


#: surge, heave, pitch of the float, then of the spar (pose columns and DOF rows)
DOFS = [0, 2, 4, 6, 8, 10]


@pytest.mark.parametrize("k", range(len(PERIODS)))
def test_regular_waves_match_the_frequency_domain_rk4(rm3, references, k):
    T = PERIODS[k]
    w = 2 * np.pi / T
    t, X, _, _ = _run(rm3, T, "RK4", 0.01)
    td = np.array([steady_amplitude(t, X[:, i], w, 8) for i in DOFS]) / AMPLITUDE
    rel = steady_amplitude(t, X[:, 2] - X[:, 8], w, 8) / AMPLITUDE
    ss = references["ss"][k, DOFS]
    raw = references["raw"][k, DOFS]
    assert np.abs(np.abs(td) - np.abs(ss)) / np.abs(ss) == pytest.approx(0.0, abs=5e-3)
    assert abs(td - ss).max() <= 5e-3 * np.abs(ss).max()
    assert np.abs(np.abs(td) - np.abs(raw)) / np.abs(raw) == pytest.approx(0.0, abs=0.02)
    assert abs(abs(rel) - abs(references["raw_rel"][k])) < 0.02 * abs(references["raw_rel"][k])
    assert abs(rel - references["ss_rel"][k]) < 5e-3 * abs(references["ss_rel"][k])


@pytest.mark.parametrize("k", [0, 2])
def test_regular_waves_match_the_frequency_domain_implicit(rm3, references, k):
    T = PERIODS[k]
    w = 2 * np.pi / T
    t, X, _, _ = _run(rm3, T, "GenAlpha", 0.05)
    td = np.array([steady_amplitude(t, X[:, i], w, 8) for i in DOFS]) / AMPLITUDE
    ss = references["ss"][k, DOFS]
    assert np.abs(np.abs(td) - np.abs(ss)) / np.abs(ss) == pytest.approx(0.0, abs=0.01)
    assert np.abs(np.abs(td) - np.abs(references["raw"][k, DOFS])) / np.abs(ss) == pytest.approx(0.0, abs=0.02)


def test_energy_balance_in_regular_waves(rm3):
    """Over the last 20 whole periods the work of the excitation equals the energy radiated plus
    the energy the PTO absorbs, within 1 % (the bodies' mechanical energy is periodic; sampling at
    T/100 with the trapezoidal rule is exact for the periodic products up to harmonic 50)."""
    T = 8.0
    t, _, rec, _ = _run(rm3, T, "RK4", 0.01, n_periods=60, samples=100, record_energy=True)
    sel = t >= t[-1] - 20 * T - 1e-9
    vel = np.array([r[0] for r in rec])[sel]
    F = np.array([r[1] for r in rec])[sel]  # (n, nf, components, 6)
    P = np.array([r[2] for r in rec])[sel]
    v = vel.reshape(len(vel), 2, 6)
    w_exc = np.trapezoid(np.einsum("nfd,nfd->n", F[:, :, 0], v), t[sel])
    e_rad = -np.trapezoid(np.einsum("nfd,nfd->n", F[:, :, 1], v), t[sel])
    e_pto = np.trapezoid(P, t[sel])
    assert w_exc > 0 and e_rad > 0 and e_pto > 0
    assert abs(w_exc - e_rad - e_pto) < 0.01 * w_exc
    # and the mean absorbed power is the frequency-domain one within 2 %
    M = rm3_mass_matrix(rm3)
    fd = hydro.rao(rm3, M, wave_direction=0.0, omega=[2 * np.pi / T], pto=_pto())
    assert e_pto / (20 * T) == pytest.approx(float(fd.pto_power.values[0]) * AMPLITUDE**2, rel=0.02)


def test_the_float_stays_on_its_joint(rm3):
    """After every step the float is on the spar's axis with the spar's orientation: the joint is
    exact (to round-off), not a penalty spring."""
    t, X, _, s = _run(rm3, 8.0, "RK4", 0.01, n_periods=5)
    f, sp = s.bodies
    R = sp.rotation_matrix()
    d = R.T @ (f.position() - sp.position())
    assert np.abs(d[:2]).max() < 1e-12
    assert np.abs(f.rotation_matrix() - R).max() < 1e-12
    rel_v = f.velocity() - sp.velocity() - np.cross(sp.angular_velocity(), f.position() - sp.position())
    axis = R[:, 2]
    assert np.linalg.norm(rel_v - np.dot(rel_v, axis) * axis) < 1e-12
    assert np.abs(f.angular_velocity() - sp.angular_velocity()).max() < 1e-15
    # the recorded slide is the float's heave relative to the spar (small pitch: cos ~ 1)
    assert np.abs((X[:, 2] - X[:, 8]) - (X[0, 2] - X[0, 8])).max() > 0.01
