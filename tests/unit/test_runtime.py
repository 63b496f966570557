"""System, Trajectory, simulate() and the command line: contracts, schema and failure handling."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import moorline
from moorline.cli import main as cli_main
from moorline.errors import DeckError, SimulationError
from moorline.model import Environment, Model, Options
from moorline.motion import Trajectory
from moorline.results import write_netcdf
from moorline.system import System

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "catenary_3line" / "catenary_3line.dat"


def small_model(dtM=0.002, **opt) -> Model:
    """One chain line, anchor to a coupled fairlead, in 100 m of water."""
    m = Model(env=Environment(depth=100.0), options=Options(dtM=dtM, TmaxIC=20.0, **opt))
    m.add_line_type("chain", d=0.1, w=60.0, EA=5e8, BA=-0.8, Cd=1.2, Ca=1.0, CdAx=0.2, CaAx=0.5)
    a = m.add_point("fixed", (300.0, 0.0, -100.0))
    f = m.add_point("coupled", (0.0, 0.0, -10.0))
    m.add_line("chain", a, f, L=330.0, N=15)
    return m


# --------------------------------------------------------------------------- Trajectory
def test_linear_trajectory_is_the_moordyn_driver_path():
    t = np.array([0.0, 0.1, 0.2])
    X = np.array([[0.0], [1.0], [3.0]])
    tr = Trajectory.from_samples(t, X, "linear")
    assert tr.position(0.05)[0] == pytest.approx(0.5)
    assert tr.velocity(0.05)[0] == pytest.approx(10.0)
    assert tr.velocity(0.15)[0] == pytest.approx(20.0)
    # holds still outside the samples
    assert tr.position(5.0)[0] == pytest.approx(3.0) and tr.velocity(5.0)[0] == 0.0
    assert tr.position(-1.0)[0] == pytest.approx(0.0)


def test_cubic_trajectory_is_smooth_and_interpolates():
    t = np.linspace(0.0, 10.0, 101)
    X = np.sin(t)[:, None]
    tr = Trajectory.from_samples(t, X, "cubic")
    for tk in (0.55, 3.21, 7.77):
        assert tr.position(tk)[0] == pytest.approx(np.sin(tk), abs=1e-5)
        assert tr.velocity(tk)[0] == pytest.approx(np.cos(tk), abs=1e-3)
    # velocity continuous across a knot
    assert tr.velocity(5.0 - 1e-9)[0] == pytest.approx(tr.velocity(5.0 + 1e-9)[0], abs=1e-6)


@pytest.mark.parametrize("text, line, what", [
    ("x,P1_x\n0,1\n", 1, "first column must be the time"),
    ("t,P1_x,P1_y\n0,1,2\n", 1, "expected 3 DOF columns"),
    ("t,a,b,c\n0,1,2,3\n0.1,1,2\n", 3, "expected 4 comma-separated values"),
    ("t,a,b,c\n0,1,2,3\n0.1,1,abc,3\n", 3, "expected a number, got 'abc'"),
    ("t,a,b,c\n0,1,2,3\n0,1,2,3\n", 3, "times must increase"),
    ("t,a,b,c\n", None, "no data rows"),
])
def test_motion_csv_errors_name_file_and_line(tmp_path, text, line, what):
    p = tmp_path / "motion.csv"
    p.write_text(text)
    with pytest.raises(DeckError) as e:
        Trajectory.from_csv(p, n_dof=3)
    msg = str(e.value)
    assert "motion.csv" in msg and what in msg
    assert e.value.line == line


# --------------------------------------------------------------------------- System contract
def test_system_contract():
    s = System(small_model())
    assert s.n_coupled_dof == 3 and s.coupled_dof_labels == ["P2_x", "P2_y", "P2_z"]
    with pytest.raises(RuntimeError):
        s.step(np.zeros(3), np.zeros(3), 0.0, 0.1)
    with pytest.raises(ValueError, match="3 coupled DOF"):
        s.init(np.zeros(4))
    f0 = s.init()
    assert f0.shape == (3,)
    # the line pulls the fairlead down and toward the anchor
    assert f0[0] > 0 and f0[2] < 0
    # dt <= 0: nothing integrated, current forces back
    x = s.deck_coupled_positions()
    f1 = s.step(x, np.zeros(3), 0.0, 0.0)
    assert s.t == 0.0 and np.allclose(f1, f0)
    f2 = s.step(x, np.zeros(3), 0.0, 0.1)
    assert s.t == pytest.approx(0.1)
    # static equilibrium holds: the force barely changes in 0.1 s
    assert np.allclose(f2, f0, rtol=2e-3)
    ln = s.lines[0]
    assert ln.node_positions().shape == (16, 3)
    assert ln.segment_tensions().shape == (15,)
    assert ln.fairlead_tension() == pytest.approx(ln.segment_tensions()[-1])
    assert ln.anchor_tension() == pytest.approx(ln.segment_tensions()[0])
    assert ln.node_curvatures().shape == (16,)
    # the coupled point's force is what step returns
    assert np.allclose(s.points[1].force(), f2)
    assert np.allclose(s.points[1].position(), x)


def test_step_moves_coupled_point_linearly_within_a_step():
    s = System(small_model())
    s.init()
    x = s.deck_coupled_positions()
    xd = np.array([2.0, 0.0, 0.5])
    s.step(x, xd, 0.0, 0.25)
    assert np.allclose(s.points[1].position(), x + 0.25 * xd)
    # the velocity reported at the end of a step is the one imposed during it
    assert np.allclose(s.points[1].velocity(), xd)


# --------------------------------------------------------------------------- instability
def test_instability_names_time_line_node_and_suggests_dtM():
    s = System(small_model(dtM=0.05))  # far beyond the axial stability limit (~0.003 s)
    s.init(solve_ic=False)
    x = s.deck_coupled_positions()
    with pytest.raises(SimulationError) as e:
        for k in range(200):
            s.step(x, np.zeros(3), 0.1 * k, 0.1)
    err = e.value
    assert err.time is not None and 0 < err.time <= 20.0
    assert err.line == 1 and 1 <= err.node <= 14
    assert err.suggested_dtM < 0.05
    assert "line 1 node" in str(err) and "try dtM <=" in str(err)


def test_cli_unstable_run_writes_no_result_files(tmp_path, capsys):
    out = tmp_path / "out"
    code = cli_main(["run", str(EXAMPLE), "--duration", "5", "--dtM", "0.05", "--out", str(out), "--no-ic"])
    assert code == 3
    err = capsys.readouterr().err
    assert "simulation failed" in err and "No result files were written" in err
    assert not out.exists() or not any(out.iterdir())


# --------------------------------------------------------------------------- simulate / results
def test_simulate_dataset_schema(tmp_path):
    m = small_model()
    ds = moorline.simulate(m, duration=1.0, dt_out=0.25, progress=False)
    assert list(ds.time.values) == pytest.approx([0.0, 0.25, 0.5, 0.75, 1.0])
    assert ds.node_position.dims == ("time", "node", "xyz")
    assert ds.sizes["node"] == 16 and ds.sizes["segment"] == 15
    assert list(ds.node_line.values) == [1] * 16
    assert ds.node_s.values[-1] == pytest.approx(330.0)
    assert ds.coupled_force.dims == ("time", "dof")
    assert list(ds.dof.values) == ["P2_x", "P2_y", "P2_z"]
    assert ds.attrs["time_scheme"] == "RK2" and ds.attrs["dtM"] == 0.002
    assert len(ds.attrs["input_sha256"]) == 64
    assert float(ds.line_tension_b.isel(time=-1, line=0)) == pytest.approx(
        float(ds.segment_tension.isel(time=-1, segment=-1)))
    p = write_netcdf(ds, tmp_path / "r.nc")
    back = xr.load_dataset(p, engine="h5netcdf")
    assert np.allclose(back.node_position.values, ds.node_position.values)
    assert not list(tmp_path.glob("*.part"))


def test_simulate_follows_motion_and_without_nodes():
    m = small_model()
    t = np.linspace(0.0, 2.0, 21)
    X = np.column_stack([0.5 * t, np.zeros_like(t), np.full_like(t, -10.0)])
    ds = moorline.simulate(m, 2.0, Trajectory.from_samples(t, X, "linear"), dt_out=0.5, record_nodes=False,
                           progress=False)
    assert "node_position" not in ds
    assert ds.coupled_position.sel(dof="P2_x").values == pytest.approx([0.0, 0.25, 0.5, 0.75, 1.0])
    # the fairlead moves 1 m toward the anchor (at x = 300 m): the line is slacker than when held still
    held = moorline.simulate(small_model(), 2.0, None, dt_out=0.5, record_nodes=False, progress=False)
    assert ds.line_tension_b.values[-1, 0] < 0.97 * held.line_tension_b.values[-1, 0]


# --------------------------------------------------------------------------- CLI
def test_cli_run_example_writes_outputs(tmp_path, capsys):
    out = tmp_path / "ex"
    motion = EXAMPLE.with_name("surge.csv")
    code = cli_main(["run", str(EXAMPLE), "--duration", "2", "--motion", str(motion), "--out", str(out),
                     "--quiet-progress"])
    assert code == 0
    names = sorted(p.name for p in out.iterdir())
    assert names == ["catenary_3line.nc", "catenary_3line.out", "catenary_3line_Line1.out"]
    rows = (out / "catenary_3line.out").read_text().splitlines()
    assert rows[0].split() == ["Time", "FairTen1", "FairTen2", "FairTen3", "AnchTen1", "L1N20PZ", "Point4FX",
                               "Point4FZ"]
    assert len(rows) == 2 + 5  # header, units, t = 0, 0.5, ..., 2.0 (dtOut 0.5 in the deck)
    text = capsys.readouterr().out
    assert "fairlead tension" in text


def test_cli_bad_deck_exit_2(tmp_path, capsys):
    bad = tmp_path / "bad.dat"
    bad.write_text(EXAMPLE.read_text().replace("850.0     40", "850.0     0"))
    assert cli_main(["check", str(bad)]) == 2
    err = capsys.readouterr().err
    assert "bad.dat" in err and "NumSegs" in err


def test_cli_statics_and_check(capsys):
    assert cli_main(["statics", str(EXAMPLE)]) == 0
    assert "fairlead tension" in capsys.readouterr().out
    assert cli_main(["check", str(EXAMPLE)]) == 0
    assert "governing mode" in capsys.readouterr().out


def test_simulate_with_bathymetry_records_the_grid_in_the_attributes():
    """Regression: the provenance attributes once tried to JSON-encode the grid arrays and every run
    with a bathymetry failed at its end."""
    import json

    from moorline.model import Bathymetry

    m = small_model()
    m.env.bathymetry = Bathymetry([-50.0, 400.0], [-50.0, 50.0], [[-100.0, -100.0], [-100.0, -100.0]], "flat")
    ds = moorline.simulate(m, 0.2, dt_out=0.1, progress=False)
    env = json.loads(ds.attrs["environment"])
    assert env["bathymetry"] == {"source": "flat", "nx": 2, "ny": 2, "x_range": [-50.0, 400.0],
                                 "y_range": [-50.0, 50.0], "z_range": [-100.0, -100.0]}


def test_cli_run_with_a_native_sea_state(tmp_path, capsys):
    """``--waves jonswap:...`` and ``--current SPEED@HEADING`` put a sea on the deck's lines: the
    run records them in the results and the fairlead tension differs from still water."""

    runs = {}
    for tag, extra in (("still", []), ("sea", ["--waves", "jonswap:Hs=3,Tp=9,heading=180,seed=2,n=40",
                                              "--current", "1.0@180"])):
        out = tmp_path / tag
        # a 1 m/s current across the chain lying on the (frictionless) seabed: the initial
        # conditions (found with the current, spec 6.1) do not reach rest within TmaxIC, which this
        # test is not about
        code = cli_main(["run", str(EXAMPLE), "--duration", "2", "--out", str(out), "--quiet-progress",
                         "--accept-unconverged-ic", *extra])
        assert code == 0
        runs[tag] = xr.open_dataset(out / "catenary_3line.nc", engine="h5netcdf")
    env = json.loads(runs["sea"].attrs["environment"])
    assert "JONSWAP" in env["waves"] and "1 m/s toward 180 deg" in env["current"]
    diff = np.abs(runs["sea"].line_tension_b.values - runs["still"].line_tension_b.values).max()
    assert diff > 100.0  # N: a 1 m/s current on 3 x 850 m of chain moves the fairlead tension


@pytest.mark.parametrize("arg, value, words", [
    ("--waves", "storm:Hs=3", ["regular, jonswap, pm"]),
    ("--waves", "jonswap:Hs=3", ["missing tp"]),
    ("--waves", "jonswap:Hs=three,Tp=9", ["key=number"]),
    ("--current", "fast@north", ["SPEED@HEADING"]),
])
def test_cli_bad_sea_state_exit_2(arg, value, words, capsys):
    assert cli_main(["run", str(EXAMPLE), "--duration", "1", arg, value, "--quiet-progress"]) == 2
    err = capsys.readouterr().err
    assert all(w in err for w in words)
