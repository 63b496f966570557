"""The RM3 lazy-wave power umbilical (Hall, Srinivas & Yu, IOWTC 2020; section 3 of issue 16),
driven by moorline's own coupled RM3 (validation/rm3) and, one-way, by the recorded spar motion.

    python validation/rm3_umbilical/run.py [--quick]

Three sections in series from a hang-off on the spar (assumed: the column's side at z = -20 m,
facing the cable, the connector pointing 45 deg down and out): 57 m cable (the first 4 m at
EI 60 kN m^2, a bend-stiffener stand-in), 25 m buoyancy section, 55 m cable to the anchor 105.1 m
from the centreline at 70 m depth, opposite the wave direction; 1 m elements. JONSWAP Hs 8.25 m,
Tp 14.5 s, 600 s, waves on the bodies and on the lines. The coupled run is the RM3 (float, spar,
PTO, public MoorDyn mooring) with the umbilical; the one-way run drives the same umbilical from
the spar pose recorded in the coupled run.

Writes ``results.json`` and ``umbilical_*.png`` beside this script; exits 1 when a check fails.
``--quick``: 60 s records with a 20 s ramp (a few minutes; the comparison of the two runs keeps a looser
tolerance).

The three runs (coupled, the RM3 without the umbilical, one-way) go in chunks of ``--chunk``
simulated seconds (default 30 s), each ending with a checkpoint (:meth:`moorline.System.save`) and
its samples appended to a NetCDF file in ``out/<mode>/`` beside the results. ``--stop-after
SECONDS`` ends the run at the first chunk boundary after that much wall time (at least one chunk
per invocation; exit code 3, no results written); ``--resume`` continues from the checkpoints
(the runs already complete are read back), so the 600 s study can proceed across sessions:

    python validation/rm3_umbilical/run.py --stop-after 1800          # then, later:
    python validation/rm3_umbilical/run.py --resume --stop-after 1800  # ... until it finishes
"""

from __future__ import annotations

import argparse
import ast
import hashlib
import importlib.util
import json
import logging
import math
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
OUT = HERE  # where results.json and the figures go (--out)
sys.path.insert(0, str(HERE.parent))

import common  # noqa: E402

import moorline  # noqa: E402
from moorline import hydro  # noqa: E402
from moorline.model import Model  # noqa: E402
from moorline.model.water import Waves  # noqa: E402
from moorline.motion import Trajectory  # noqa: E402
from moorline.results import NetCDFStream  # noqa: E402

_spec = importlib.util.spec_from_file_location("rm3_study", HERE.parent / "rm3" / "run.py")
rm3 = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(rm3)

DEPTH = 70.0
ANCHOR_X = -105.1  # [m] the anchor, opposite the waves (which travel toward +x)
HANG_OFF = (-3.0, 0.0, -20.0)  # [m] global, at the mean pose: on the spar column (radius 3 m), assumed
STIFFENER_L = 4.0
SECTIONS = {  # name: (length [m], diameter [m], mass [kg/m], EI [N m^2])
    "stiffener": (STIFFENER_L, 0.176, 77.3, 60.0e3),
    "cable_upper": (57.0 - STIFFENER_L, 0.176, 77.3, 11.71e3),
    "buoyancy": (25.0, 0.559, 184.5, 11.71e3),
    "cable_lower": (55.0, 0.176, 77.3, 11.71e3),
}
EA, CDN, CAN = 751.0e6, 1.2, 1.0
HS, TP, GAMMA, SEED, N_COMPONENTS = 8.25, 14.5, 3.3, 3, 40
RAMP = 30.0  # [s] the wave ramp; statistics after it (quick: QUICK_RAMP)
QUICK_DURATION, QUICK_RAMP = 60.0, 20.0
DTM = 0.05
DT_OUT = 0.2


#: axial stiffness of the statics solve (see equilibrium_state)
EA_STATICS = EA / 100.0


def add_umbilical(m: Model, hang_off_body: int | None, spar_ref, *, ea: float = EA) -> list[int]:
    """Add the umbilical to model ``m``: a connector rod on body ``hang_off_body`` (its reference
    point at ``spar_ref`` in the deck), then the four sections joined by short free connector rods
    (so the joints keep their bending stiffness: a line end on a rod end is clamped), the last one
    to a fixed anchor. Returns the line indices (0-based) in order from the hang-off."""
    spar_ref = np.asarray(spar_ref, dtype=float)
    for name, (_, d, w, ei) in SECTIONS.items():
        m.add_line_type(name, d=d, w=w, EA=ea, BA=-0.5, EI=ei, Cd=CDN, Ca=CAN, CdAx=0.0, CaAx=0.0)
    m.add_rod_type("connector", d=0.176, w=77.3, Cd=CDN, Ca=CAN)
    out = np.array([-1.0, 0.0, -1.0]) / math.sqrt(2.0)  # 45 deg down and away from the spar (-x)
    top = np.array(HANG_OFF) - spar_ref
    _, start = m.add_rod("connector", "body", top - 0.5 * out, top, N=1, body=hang_off_body)
    # initial layout: straight pieces along a rough lazy-wave path; statics finds the shape
    path = [np.array(HANG_OFF), np.array([-25.0, 0.0, -55.0]), np.array([-45.0, 0.0, -40.0]),
            np.array([-50.0, 0.0, -DEPTH + 0.5]), np.array([ANCHOR_X, 0.0, -DEPTH])]
    names = list(SECTIONS)
    lines = []
    a = start
    joints = [np.array(HANG_OFF) + 3.5 * out, path[1], path[2]]
    for k, name in enumerate(names):
        L = SECTIONS[name][0]
        if k < len(names) - 1:
            p = joints[k]
            nxt = joints[k + 1] if k + 1 < len(joints) else path[3]
            axis = (nxt - p) / np.linalg.norm(nxt - p)
            ra, rb = m.add_rod("connector", "free", p, p + 0.3 * axis, N=1)
            b = ra
        else:
            b = m.add_point("fixed", (ANCHOR_X, 0.0, -DEPTH))
        m.add_line(name, a, b, L=L - (0.3 if k < len(names) - 1 else 0.0), N=max(1, int(round(L))))
        lines.append(len(m.lines) - 1)
        if k < len(names) - 1:
            a = rb
    return lines


def coupled_model(ds, deck, waves, *, with_cable: bool = True, ea: float = EA) -> tuple[Model, list[int]]:
    m = rm3.build(ds, deck, moored=True, waves=waves, dtM=DTM)
    m.env.waves_on_lines = True
    lines = add_umbilical(m, 0, m.bodies[0].r, ea=ea) if with_cable else []
    return m, lines


def equilibrium_state(make, x0=None) -> moorline.System:
    """A System of ``make(EA)`` started from the static equilibrium of ``make(EA_STATICS)``.

    Newton statics does not converge for the lazy wave at EA 751 MN (one-way model: residual
    24 m/s^2 after 430 iterations; coupled with the RM3 even at 75 MN: 0.01 m/s^2; README "gaps");
    at a hundredth of it, it does, and the stiffer line differs by its stretch at the static
    tension (about 0.3 m over 137 m), which the first seconds of the run take up (inside the
    30 s wave ramp)."""
    zero = None if x0 is None else np.zeros_like(x0)
    soft = moorline.System(make(EA_STATICS)[0])
    soft.init(x0, zero)
    s = unsolved_state(make, x0)
    s.y[:] = soft.y
    s.set_state()
    return s


def unsolved_state(make, x0=None) -> moorline.System:
    """A System of ``make(EA)`` initialised without statics (a checkpoint then sets its state)."""
    s = moorline.System(make(EA)[0])
    s.init(x0, None if x0 is None else np.zeros_like(x0), solve_ic=False)
    return s


_CHUNKS_RUN = [0]  # chunks simulated by this invocation


class Unfinished(Exception):
    """A run stopped at a chunk boundary by ``--stop-after`` (its checkpoint is kept)."""


def study_fingerprint() -> str:
    """Hash of this script's and validation/rm3/run.py's syntax trees (comments and layout left out)."""
    h = hashlib.sha256()
    for f in (Path(__file__).resolve(), HERE.parent / "rm3" / "run.py"):
        h.update(ast.dump(ast.parse(f.read_text()), annotate_fields=False).encode())
    return h.hexdigest()[:16]


def run_in_chunks(name: str, folder: Path, make_started, make_unsolved, duration: float, *, motion=None,
                  record_nodes: bool = True, chunk: float, deadline: float | None, settings: dict, resume: bool):
    """Simulate ``duration`` seconds in chunks of ``chunk`` simulated seconds, each ending with a
    checkpoint (``<name>.checkpoint.npz``) and its samples appended to ``<name>.nc`` in ``folder``.

    ``resume``: continue from the checkpoint (a complete run is read back); otherwise start afresh.
    ``settings`` are stored beside the files and must match to resume. ``deadline`` (epoch s): stop
    at the first chunk boundary after it, raising :class:`Unfinished`. Returns the whole record.
    """
    import xarray as xr

    folder.mkdir(parents=True, exist_ok=True)
    nc, ck, tag = folder / f"{name}.nc", folder / f"{name}.checkpoint.npz", folder / f"{name}.settings.json"
    text = json.dumps(settings, sort_keys=True)
    if resume and tag.exists() and tag.read_text() != text:
        raise SystemExit(f"--resume: {tag} was written with other settings or another version of the study "
                         f"(stored {tag.read_text()}, now {text}); run without --resume to start over")
    if not resume or not tag.exists():
        for f in (nc, ck):
            f.unlink(missing_ok=True)
    tag.write_text(text)

    def whole():
        with xr.open_dataset(nc, engine="h5netcdf") as ds:
            return ds.load()

    if nc.exists() and ck.exists():
        with xr.open_dataset(nc, engine="h5netcdf") as ds:
            done = float(ds.attrs.get("simulated_until", -1.0)) >= duration - 1e-6 and int(ds.attrs["complete"]) == 1
        if done:
            print(f"    {name}: complete in {nc}, read back", flush=True)
            return whole()
    cursor = None
    if ck.exists():
        s = make_unsolved()
        cursor = s.load(ck).get("outputs", {}).get("netcdf")
        print(f"    {name}: resumed from {ck} at t = {s.t:g} s", flush=True)
    else:
        nc.unlink(missing_ok=True)
        s = make_started()
    wall0 = time.perf_counter()
    t0 = s.t
    while s.t < duration - 1e-6:
        # at least one chunk per invocation, so that every session makes progress
        if deadline is not None and time.time() > deadline and _CHUNKS_RUN[0]:
            raise Unfinished(f"{name}: stopped at t = {s.t:g} s of {duration:g} s (--stop-after); continue with "
                             "--resume")
        step = min(chunk, duration - s.t)
        stream = NetCDFStream(nc, resume=cursor)
        moorline.simulate(s, step, motion, dt_out=DT_OUT, progress=False, record_nodes=record_nodes,
                          writers=[stream], checkpoint=ck, checkpoint_every=step)
        cursor = stream.cursor()
        _CHUNKS_RUN[0] += 1
        print(f"    {name}: t = {s.t:g} s of {duration:g} s ({time.perf_counter() - wall0:.0f} s wall for "
              f"{s.t - t0:g} s simulated)", flush=True)
    return whole()


def oneway_model(spar_pose0, waves, spar_ref, *, ea: float = EA) -> tuple[Model, list[int]]:
    """The umbilical alone on a prescribed ("coupled") spar placed at ``spar_pose0``, its hang-off
    at the same place in body axes as in the coupled model (``spar_ref``: the spar's reference point
    in the deck, from which add_umbilical takes the hang-off's body-axis position)."""
    m = Model()
    m.env.rho, m.env.g, m.env.depth = rm3.RHO, rm3.G, DEPTH
    m.options.tScheme = "GenAlpha"
    m.options.dtM = DTM
    b = m.add_body("coupled", spar_pose0[:3], np.degrees(spar_pose0[3:]))
    lines = add_umbilical(m, b, spar_ref, ea=ea)
    m.env.waves = waves
    m.env.waves_on_lines = True
    return m, lines


def cable_series(r, lines) -> dict:
    """Positions, tensions and curvatures of the umbilical's nodes in order from the hang-off,
    with their arc length (the junction rods' 0.3 m included)."""
    idx, s, off = [], [], 0.0
    for k, ln in enumerate(lines):
        nodes = np.flatnonzero(r.node_line.values == ln + 1)
        if k:
            nodes = nodes[1:]  # the rod end shared with the previous section's last node (0.3 m apart)
            off += 0.3
        idx.extend(nodes)
        s.extend(off + r.node_s.values[nodes])
        off = s[-1]
    idx = np.array(idx)
    return {"s": np.array(s), "pos": r.node_position.values[:, idx], "tension": r.node_tension.values[:, idx],
            "curvature": r.node_curvature.values[:, idx], "t": r.time.values,
            "top_tension": r.line_tension_a.values[:, lines[0]]}


def main(argv=None) -> int:
    global OUT
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="60 s records, 20 s ramp (CI)")
    ap.add_argument("--out", type=Path, default=None, help="folder for results.json and the figures (default: beside "
                    "this script); the runs' checkpoints and records go to out/<mode>/ in it")
    ap.add_argument("--chunk", type=float, default=30.0, help="simulated seconds between checkpoints (default 30)")
    ap.add_argument("--stop-after", type=float, default=None, metavar="SECONDS",
                    help="stop at the first chunk boundary after this much wall time (exit 3; continue with --resume)")
    ap.add_argument("--resume", action="store_true", help="continue the runs from their checkpoints in out/<mode>/")
    a = ap.parse_args(argv)
    OUT = a.out or HERE
    OUT.mkdir(parents=True, exist_ok=True)
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    started = time.perf_counter()
    deadline = None if a.stop_after is None else time.time() + a.stop_after
    stem, deck = rm3.rm3_data()
    ds = hydro.read_wamit(stem, rho=rm3.RHO, g=rm3.G)
    duration, ramp = (QUICK_DURATION, QUICK_RAMP) if a.quick else (600.0, RAMP)
    waves = Waves.jonswap(HS, TP, GAMMA, seed=SEED, n_components=N_COMPONENTS, ramp_time=ramp)
    chk = common.Checks()
    folder = OUT / "out" / ("quick" if a.quick else "full")
    settings = {"duration": duration, "ramp": ramp, "dt_out": DT_OUT, "dtM": DTM, "chunk": a.chunk,
                "study": study_fingerprint(), "moorline": moorline.__version__}
    runs = {"chunk": a.chunk, "folder": str(folder)}

    def chunked(name, started_, unsolved, **kw):
        t0 = time.perf_counter()
        r = run_in_chunks(name, folder, started_, unsolved, duration, chunk=a.chunk, deadline=deadline,
                          settings=settings, resume=a.resume, **kw)
        runs[name] = {"wall_s_this_invocation": time.perf_counter() - t0,
                      "loop_wall_s_last_chunk": float(r.attrs.get("wall_time_s", float("nan")))}
        return r

    try:
        # ------------------------------------------------------------ coupled
        m, lines = coupled_model(ds, deck, waves)
        make = lambda ea: coupled_model(ds, deck, waves, ea=ea)  # noqa: E731
        rc = chunked("coupled", lambda: equilibrium_state(make), lambda: unsolved_state(make))
        cab_c = cable_series(rc, lines)
        spar = rc.body_pose.values[:, 0, :]

        # ------------------------------------------------------------ RM3 without the umbilical (its influence)
        def bare(solve):
            s0 = moorline.System(coupled_model(ds, deck, waves, with_cable=False)[0])
            s0.init(solve_ic=solve)
            return s0

        r0 = chunked("without_umbilical", lambda: bare(True), lambda: bare(False), record_nodes=False)
        # ------------------------------------------------------------ one-way from the recorded spar pose
        # the hang-off in body axes as in the coupled model (taking it relative to the recorded start pose
        # instead moved it by the spar's static offset and sink from the deck pose: +73 N, 0.3 %, on the
        # mean top tension of the quick run, most of the one-way/coupled difference)
        spar_ref = np.array(m.bodies[0].r, dtype=float)
        _, lines_o = oneway_model(spar[0], waves, spar_ref)
        traj = Trajectory.from_samples(rc.time.values, spar)
        make_o = lambda ea: oneway_model(spar[0], waves, spar_ref, ea=ea)  # noqa: E731
        ro = chunked("oneway", lambda: equilibrium_state(make_o, traj.position(0.0)),
                     lambda: unsolved_state(make_o, traj.position(0.0)), motion=traj)
    except Unfinished as e:
        print(f"RM3 umbilical: not finished, no results written: {e}", flush=True)
        return 3
    cab_o = cable_series(ro, lines_o)
    wall_c = runs["coupled"]["wall_s_this_invocation"]
    wall_o = runs["oneway"]["wall_s_this_invocation"]

    sel = cab_c["t"] >= ramp
    res = {"top_tension_mean_n": float(cab_c["top_tension"][sel].mean()),
           "top_tension_max_n": float(cab_c["top_tension"][sel].max()),
           "top_tension_std_n": float(cab_c["top_tension"][sel].std()),
           "max_curvature_per_m": float(cab_c["curvature"][sel].max()),
           "max_curvature_s_m": float(cab_c["s"][np.argmax(cab_c["curvature"][sel].max(axis=0))]),
           "min_tension_n": float(cab_c["tension"][sel].min()),
           "oneway": {"top_tension_mean_n": float(cab_o["top_tension"][sel].mean()),
                      "top_tension_max_n": float(cab_o["top_tension"][sel].max()),
                      "top_tension_std_n": float(cab_o["top_tension"][sel].std()),
                      "max_curvature_per_m": float(cab_o["curvature"][sel].max())},
           "lowest_buoyancy_hump_z_m": None,
           "spar_surge_std_m": {"with_umbilical": float(np.std(spar[sel, 0])),
                                "without": float(np.std(r0.body_pose.values[sel, 0, 0]))},
           "relative_motion_std_m": {"with_umbilical": float(np.std(rc.joint_slide.values[sel, 0])),
                                     "without": float(np.std(r0.joint_slide.values[sel, 0]))},
           "hang_off_m": HANG_OFF, "anchor_m": (ANCHOR_X, 0.0, -DEPTH),
           "sea": {"Hs_m": HS, "Tp_s": TP, "gamma": GAMMA, "seed": SEED, "components": N_COMPONENTS,
                   "duration_s": duration, "ramp_s": ramp},
           "case_wall_time_s": {"coupled": wall_c, "oneway": wall_o}, "runs": runs}
    d_rms = float(np.sqrt(np.mean((cab_c["top_tension"][sel] - cab_o["top_tension"][sel]) ** 2)))
    res["oneway_vs_coupled_top_tension_rms_difference_n"] = d_rms
    tol = 0.05 if a.quick else 0.03
    chk.add("one-way vs coupled: RMS difference of the top tension / its std", d_rms / res["top_tension_std_n"], 0.0,
            tol, relative=False, why="the same spar motion drives both; they differ only by the cable's feedback on "
            "the spar (absent one-way) and the interpolation of the recorded pose (0.2 s, cubic)")
    chk.add("one-way vs coupled: largest curvature", res["oneway"]["max_curvature_per_m"],
            res["max_curvature_per_m"], 0.05, why="as above")
    chk.add("the umbilical barely changes the relative motion (hence power)",
            res["relative_motion_std_m"]["with_umbilical"], res["relative_motion_std_m"]["without"], 0.02,
            why="its weight and stiffness act on the spar; the PTO sees the float-spar motion")
    chk.bound("the cable section rests on the seabed: anchor-end segment lowest height", float(
        cab_c["pos"][sel, -10:, 2].max()) + DEPTH, hi=1.0, why="lazy wave: the last 55 m section lies on the seabed")
    z_hump = cab_c["pos"][0, :, 2]
    s = cab_c["s"]
    buoy = (s > 57.0) & (s < 82.0)
    res["lowest_buoyancy_hump_z_m"] = float(z_hump[buoy].max())
    res["checks"], res["comparisons"], res["passed"] = chk.items, chk.comparisons, chk.passed
    out = common.write_results(OUT / "results.json", res, quick=a.quick, started=started)
    paths = figures(cab_c, cab_o, sel)
    print(f"RM3 umbilical ({out['mode']}, {out['wall_time_s']} s): top tension mean "
          f"{res['top_tension_mean_n'] / 1e3:.1f} kN, "
          f"max {res['top_tension_max_n'] / 1e3:.1f} kN (one-way {res['oneway']['top_tension_max_n'] / 1e3:.1f} kN); "
          f"largest curvature {res['max_curvature_per_m']:.3f} 1/m at s = {res['max_curvature_s_m']:.1f} m")
    print(chk.report())
    for p in paths:
        print(f"  wrote {p}")
    return 0 if chk.passed else 1


def figures(cab_c, cab_o, sel) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    paths = []
    t = cab_c["t"]
    top = cab_c["top_tension"]
    k_max = int(np.argmax(np.where(sel, top, -np.inf)))
    k_min = int(np.argmin(np.where(sel, top, np.inf)))
    # the first sample is the EA/100 equilibrium at the real EA (2 MN at the top until released): not shown
    k_ramp = int(np.argmax(sel))
    instants = [("end of the wave ramp", k_ramp), ("largest top tension", k_max), ("smallest top tension", k_min)]
    fig, axes = plt.subplots(3, 1, figsize=(10, 9))
    for label, k in instants:
        axes[0].plot(cab_c["pos"][k, :, 0], cab_c["pos"][k, :, 2], label=f"{label} (t = {t[k]:.1f} s)")
        axes[1].plot(cab_c["s"], cab_c["tension"][k] / 1e3)
        axes[2].plot(cab_c["s"], cab_c["curvature"][k])
    axes[0].axhline(-DEPTH, color="k", lw=0.8)
    axes[0].set_xlabel("x [m]")
    axes[0].set_ylabel("z [m]")
    axes[0].legend(fontsize=8)
    axes[0].set_title("lazy-wave umbilical on the coupled RM3: profile, tension and curvature at three instants",
                      fontsize=9)
    axes[1].set_ylabel("tension [kN]")
    axes[2].set_ylabel("curvature [1/m]")
    axes[2].set_xlabel("arc length from the hang-off [m]")
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.tight_layout()
    paths.append(OUT / "umbilical_profiles.png")
    fig.savefig(paths[-1], dpi=90)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(10, 3.6))
    ax.plot(t, top / 1e3, label="coupled")
    ax.plot(cab_o["t"], cab_o["top_tension"] / 1e3, "--", label="one-way (recorded spar motion)")
    lo, hi = float(top[sel].min()) / 1e3, float(top[sel].max()) / 1e3
    ax.set_ylim(lo - 0.5 * (hi - lo), hi + 0.5 * (hi - lo))  # the start (from the EA/100 statics) is off the scale
    ax.axvline(t[sel][0], color="k", lw=0.8, ls=":")
    ax.set_title("top tension; statistics after the dotted line (the wave ramp); the first second, the release "
                 "from the EA/100 statics, is off the scale", fontsize=8)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("top tension [kN]")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    paths.append(OUT / "umbilical_top_tension.png")
    fig.savefig(paths[-1], dpi=90)
    plt.close(fig)
    return paths


if __name__ == "__main__":
    sys.exit(main())
