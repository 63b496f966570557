"""Save and restart with floating bodies: a run restarted from a checkpoint continues bitwise
identically (``==`` on the state and on every recorded sample, radiation states and joint outputs
included) for both time-scheme families, state-space radiation and direct convolution (whose
velocity history lives in the floating work), in waves, and with a joint and its PTO; the
quasi-static mooring mode, which a checkpoint cannot restore, is refused before the run."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import moorline
from moorline.errors import CheckpointError
from moorline.model.water import Waves

from .conftest import rm3_model, three_pole_model


def _same(a: xr.Dataset, b: xr.Dataset):
    assert set(a.data_vars) == set(b.data_vars)
    for name, var in a.data_vars.items():
        assert np.array_equal(var.values, b[name].values), f"{name} differs"
    assert np.array_equal(a.time.values, b.time.values)


def _restart_matches(build, tmp_path, t_split=1.5, t_end=3.0, dt_out=0.25):
    ref_sys = moorline.System(build())
    ref = moorline.simulate(ref_sys, t_end, dt_out=dt_out, progress=False)
    first = moorline.System(build())
    moorline.simulate(first, t_split, dt_out=dt_out, progress=False, checkpoint=tmp_path / "c.npz",
                      checkpoint_every=t_split)
    resumed = moorline.System(build())
    resumed.load(tmp_path / "c.npz")
    assert resumed.t == t_split
    rest = moorline.simulate(resumed, t_end - t_split, dt_out=dt_out, progress=False)
    assert np.array_equal(resumed.y, ref_sys.y)
    zoff = resumed.layout.u_offset + 3 * resumed.layout.n_rows + 6 * resumed.layout.n_blocks
    return ref, rest, ref_sys, zoff


@pytest.mark.parametrize("scheme, dtM, radiation", [("RK4", 0.01, "state_space"), ("GenAlpha", 0.05, "state_space"),
                                                    ("RK2", 0.01, "convolution")])
def test_floating_body_in_waves_restarts_bitwise(tmp_path, scheme, dtM, radiation):
    opts = {"radiation": "convolution", "irf_dt": 0.02, "irf_duration": 10.0} if radiation == "convolution" else {}

    def build():
        m = three_pole_model(scheme, dtM, **opts)
        m.env.waves = Waves.regular(1.0, 6.0)
        return m

    ref, rest, s, zoff = _restart_matches(build, tmp_path)
    _same(ref.isel(time=slice(6, None)), rest)
    if radiation == "state_space":  # the radiation states are in the state vector, and moving
        assert s.y.size > zoff and np.abs(s.y[zoff:]).max() > 0
    else:  # the velocity history that the convolution reads was restored
        assert s.fwork.hctl[0] > 100


def test_joint_and_pto_restart_bitwise(rm3, tmp_path):
    def build():
        m = rm3_model(rm3, scheme="RK4", dtM=0.01)
        m.env.waves = Waves.regular(2.0, 8.0)
        return m

    ref, rest, _, _ = _restart_matches(build, tmp_path, t_split=1.0, t_end=2.0)
    assert "pto_power" in rest and np.abs(rest.pto_power.values).max() > 0
    _same(ref.isel(time=slice(4, None)), rest)


def test_checkpoints_of_the_quasistatic_mode_are_refused(tmp_path):
    m = three_pole_model("RK4", 0.01)
    p_b = m.add_point("body", (0.0, 0.0, -1.0), body=0)
    p_a = m.add_point("fixed", (300.0, 0.0, -500.0))
    m.add_line_type("chain", d=0.09, w=77.7, EA=3.8e8, BA=-0.8, Cd=1.6, Ca=1.0, CdAx=0.1, CaAx=0.0)
    m.add_line("chain", p_a, p_b, L=560.0, N=10)
    s = moorline.System(m, mooring="quasistatic")
    with pytest.raises(CheckpointError, match="quasi-static mooring mode"):
        moorline.simulate(s, 1.0, progress=False, checkpoint=tmp_path / "c.npz", checkpoint_every=0.5)
    assert not (tmp_path / "c.npz").exists()
