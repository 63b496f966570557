"""Save and restart (System.save / System.load, ``moorline run --checkpoint-every / --resume``) and
outputs streamed as a run goes.

A run restarted from a checkpoint must continue bitwise identically to one that never stopped:
compared with ``==`` on the state and on every recorded sample, for an explicit scheme (RK2), the
implicit scheme (GenAlpha, whose carried acceleration, factored Jacobian and step size are in the
checkpoint) and a sea drawn without a seed (the checkpoint restores the drawn components).
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import moorline
from moorline.cli import main as cli_main
from moorline.errors import CheckpointError
from moorline.model.water import Waves
from moorline.motion import Trajectory
from moorline.system import System

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "catenary_3line" / "catenary_3line.dat"
MOTION = EXAMPLE.with_name("surge.csv")


def _system(scheme=None, waves=None):
    s = System.from_file(EXAMPLE, **({"scheme": scheme, "dtM": 0.1} if scheme else {}))
    if waves is not None:
        s.model.env.waves = waves
        s = System(s.model, **({"scheme": scheme, "dtM": 0.1} if scheme else {}))
    return s


def _same(a: xr.Dataset, b: xr.Dataset):
    for name, var in a.data_vars.items():
        assert np.array_equal(var.values, b[name].values), f"{name} differs"
    assert np.array_equal(a.time.values, b.time.values)


@pytest.mark.parametrize("scheme, waves", [(None, None), ("GenAlpha", None),
                                           (None, {"Hs": 4.0, "Tp": 9.0, "n_components": 30})],
                         ids=["RK2", "GenAlpha", "RK2-random-sea"])
def test_restart_continues_bitwise(tmp_path, scheme, waves):
    motion = Trajectory.from_csv(MOTION, n_dof=9)
    sea = Waves.jonswap(waves["Hs"], waves["Tp"], n_components=waves["n_components"]) if waves else None
    whole = _system(scheme, sea)
    ref = moorline.simulate(whole, 3.0, motion, dt_out=0.5, progress=False)

    first = _system(scheme, sea)
    moorline.simulate(first, 1.5, motion, dt_out=0.5, progress=False, checkpoint=tmp_path / "c.npz",
                      checkpoint_every=1.5)
    # a new process would draw another sea without a seed: the checkpoint brings the first one back
    other_sea = Waves.jonswap(waves["Hs"], waves["Tp"], n_components=waves["n_components"]) if waves else None
    resumed = _system(scheme, other_sea)
    assert resumed.load(tmp_path / "c.npz") == {"outputs": {}}
    assert resumed.t == 1.5
    rest = moorline.simulate(resumed, 1.5, motion, dt_out=0.5, progress=False)
    assert np.array_equal(resumed.y, whole.y)
    _same(ref.isel(time=slice(3, None)), rest)
    if scheme:
        assert resumed.solver_stats["step"] == whole.solver_stats["step"]


def test_checkpoint_of_another_model_is_refused(tmp_path):
    s = _system()
    s.init(solve_ic=False)
    s.save(tmp_path / "c.npz")
    other = System.from_file(EXAMPLE, dtM=0.001)
    with pytest.raises(CheckpointError, match="dtM: 0.002 in the checkpoint, 0.001 here"):
        other.load(tmp_path / "c.npz")
    (tmp_path / "junk.npz").write_bytes(b"not a checkpoint")
    with pytest.raises(CheckpointError, match="not a readable moorline checkpoint"):
        s.load(tmp_path / "junk.npz")


def test_streamed_outputs_are_the_files_written_at_the_end(tmp_path):
    """The .out tables and NetCDF file written as the run goes hold what a run writing them at its
    end wrote (same rows, same values), and the NetCDF file is marked complete."""
    from moorline.io.outputs import OutputRecorder
    from moorline.results import write_netcdf

    out = tmp_path / "stream"
    assert cli_main(["run", str(EXAMPLE), "--duration", "3", "--motion", str(MOTION), "--out", str(out),
                     "--quiet-progress"]) == 0
    s = System.from_file(EXAMPLE)
    recs = []

    def record(sys_):
        if not recs:
            recs.append(OutputRecorder(sys_))
        recs[0].record()

    ds = moorline.simulate(s, 3.0, Trajectory.from_csv(MOTION, n_dof=9), progress=False, on_output=[record])
    at_end = tmp_path / "end"
    for p in recs[0].write(at_end, "catenary_3line"):
        assert p.read_bytes() == (out / p.name).read_bytes(), p.name
    write_netcdf(ds, at_end / "catenary_3line.nc")
    streamed = xr.load_dataset(out / "catenary_3line.nc", engine="h5netcdf")
    assert streamed.attrs["complete"] == 1 and streamed.attrs["simulated_until"] == 3.0
    _same(xr.load_dataset(at_end / "catenary_3line.nc", engine="h5netcdf"), streamed)


def test_failed_run_keeps_its_outputs_marked_incomplete(tmp_path, capsys):
    out = tmp_path / "out"
    code = cli_main(["run", str(EXAMPLE), "--duration", "5", "--dtM", "0.05", "--out", str(out), "--no-ic",
                     "--quiet-progress"])
    assert code == 3
    err = capsys.readouterr().err
    assert "simulation failed" in err and "Partial results up to t =" in err and "complete = 0" in err
    ds = xr.load_dataset(out / "catenary_3line.nc", engine="h5netcdf")
    assert ds.attrs["complete"] == 0 and "stopped at t =" in ds.attrs["status"]
    assert ds.time.size >= 1 and float(ds.time[-1]) == ds.attrs["simulated_until"]


@pytest.mark.slow
def test_killed_run_resumes_bitwise_from_the_command_line(tmp_path):
    """``moorline run --checkpoint-every`` killed with SIGKILL leaves readable outputs (NetCDF marked
    incomplete); ``--resume`` continues it, and the files end byte for byte (tables) and value for
    value (NetCDF) as those of a run that was never interrupted."""
    args = ["run", str(EXAMPLE), "--duration", "120", "--motion", str(MOTION), "--dtM", "0.001",
            "--quiet-progress"]
    ref = tmp_path / "ref"
    assert cli_main([*args, "--out", str(ref)]) == 0
    out = tmp_path / "killed"
    ckpt = out / "catenary_3line.checkpoint.npz"
    proc = subprocess.Popen([sys.executable, "-m", "moorline.cli", *args, "--out", str(out), "--checkpoint-every",
                             "10"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 600
    while time.monotonic() < deadline and proc.poll() is None:
        if ckpt.exists() and System.from_file(EXAMPLE, dtM=0.001).load(ckpt) is not None:
            break
        time.sleep(0.02)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert proc.returncode == -signal.SIGKILL, "the run ended before it could be killed: make it longer"
    partial = xr.load_dataset(out / "catenary_3line.nc", engine="h5netcdf")
    assert partial.attrs["complete"] == 0 and 10.0 <= float(partial.time[-1]) < 120.0
    rows = (out / "catenary_3line.out").read_text().splitlines()
    assert all(len(r.split()) == 8 for r in rows[2:])  # every row whole
    assert cli_main([*args, "--out", str(out), "--resume", str(ckpt), "--checkpoint-every", "10"]) == 0
    for name in ("catenary_3line.out", "catenary_3line_Line1.out"):
        assert (out / name).read_bytes() == (ref / name).read_bytes(), name
    _same(xr.load_dataset(ref / "catenary_3line.nc", engine="h5netcdf"),
          xr.load_dataset(out / "catenary_3line.nc", engine="h5netcdf"))
    assert os.path.getsize(ckpt) > 0


#: MoorDyn's public Syrope and viscoelastic rope decks (../shared/public_decks), which carry line
#: states (Syrope working curves and peak tensions, viscoelastic stretch states) across steps
ROPE_DECKS = Path(os.environ.get("MOORLINE_SHARED", Path(__file__).resolve().parents[3] / "shared")) / \
    "public_decks" / "FloatingArrayDesign+MoorDyn" / "tests" / "Mooring"


@pytest.mark.parametrize("rel", ["syrope/exp_wc/line.txt", "polyester/visco.txt"])
def test_restart_with_line_states_continues_bitwise(tmp_path, monkeypatch, rel):
    src = ROPE_DECKS / rel
    if not src.is_file():
        pytest.skip(f"public deck {src} not available")
    root = src.parents[1] if rel.startswith("syrope") else src.parent  # Syrope decks read ../owc.dat
    work = tmp_path / root.name
    shutil.copytree(root, work, ignore=shutil.ignore_patterns("*.out", "*.log", "*.vtk", "*.vtp"))
    monkeypatch.chdir(work / src.parent.relative_to(root))
    path = Path(src.name)

    whole = System.from_file(path)
    t = np.linspace(0.0, 4.0, 41)
    X = np.tile(whole.deck_coupled_positions(), (t.size, 1))
    if X.shape[1]:
        # surge the first coupled DOF, harder before the checkpoint than after: the history the
        # first half leaves (Syrope peak tension and working curve, viscoelastic stretch) then
        # sets the second half
        X[:, 0] += np.where(t < 2.0, 3.0, 0.5) * np.sin(np.pi * t)
    mo = Trajectory.from_samples(t, X)
    ref = moorline.simulate(whole, 4.0, mo, dt_out=0.5, progress=False)
    assert whole.layout.lines.xs_s0.size > 0  # the deck has line states
    first = System.from_file(path)
    moorline.simulate(first, 2.0, mo, dt_out=0.5, progress=False, checkpoint=tmp_path / "c.npz", checkpoint_every=2.0)
    resumed = System.from_file(path)
    resumed.load(tmp_path / "c.npz")
    rest = moorline.simulate(resumed, 2.0, mo, dt_out=0.5, progress=False)
    assert np.array_equal(resumed.y, whole.y)
    _same(ref.isel(time=slice(4, None)), rest)
