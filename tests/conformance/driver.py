"""Drive moorline exactly as ../shared/conformance/README.md describes MoorDyn's driver, and write
its results in the corpus' column conventions, so that the corpus' own ``gen_reference.py``
judges them.

Used by ``test_conformance.py`` and runnable by hand::

    python tests/conformance/driver.py CASE [--own-ic] [--out DIR]

which prints the comparison report of ``gen_reference.py``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

from moorline.io import read_deck
from moorline.motion import Trajectory
from moorline.system import System

ROOT = Path(__file__).resolve().parents[2]
SHARED = Path(os.environ.get("MOORLINE_SHARED", ROOT.parent / "shared"))
CONF = SHARED / "conformance"


def gen_reference():
    """The corpus' own comparison module (needs numpy and pyyaml)."""
    if str(CONF) not in sys.path:
        sys.path.insert(0, str(CONF))
    import gen_reference as gr

    return gr


def load_case(name: str) -> dict:
    return gen_reference().load_cases()["cases"][name]


# ----------------------------------------------------------------------------- initial state
def read_initial_state(system: System, path: Path):
    """Line node and free point positions/velocities from a corpus ``<case>_initial.csv``."""
    ref = gen_reference().read_initial(str(path))
    lp, lv = [], []
    for li, ln in enumerate(system.lines):
        pos = np.zeros((ln.n_segments + 1, 3))
        vel = np.zeros_like(pos)
        for j in range(ln.n_segments + 1):
            r = ref[("line", li + 1, j)]
            pos[j] = [float(r[c]) for c in ("x", "y", "z")]
            vel[j] = [float(r[c]) for c in ("vx", "vy", "vz")]
        lp.append(pos)
        lv.append(vel)
    pp = np.zeros((len(system.points), 3))
    pv = np.zeros_like(pp)
    for p in range(len(system.points)):
        r = ref[("point", p + 1, 0)]
        pp[p] = [float(r[c]) for c in ("x", "y", "z")]
        pv[p] = [float(r[c]) for c in ("vx", "vy", "vz")]
    return lp, lv, pp, pv


def initial_rows(system: System) -> list[list]:
    """The corpus' initial-state table (README: kind,id,node,x,...,T,curv,...)."""
    rows = []
    for ln in system.lines:
        r = ln.node_positions()
        v = ln.node_velocities()
        sv = ln.segment_tension_vectors()
        tv = np.vstack([sv[:1], 0.5 * (sv[:-1] + sv[1:]), sv[-1:]])
        k = ln.node_curvatures()
        for j in range(len(r)):
            rows.append(["line", ln.number, j, *r[j], *v[j], *tv[j], np.linalg.norm(tv[j]), k[j]] + [""] * 6)
    for p in system.points:
        f = p.force()
        rows.append(["point", p.number, 0, *p.position(), *p.velocity(), *f, np.linalg.norm(f), ""] + [""] * 6)
    for rod in system.rods:
        r = rod.node_positions()
        v = rod.node_velocities()
        for j in range(len(r)):
            rows.append(["rod", rod.number, j, *r[j], *v[j]] + [""] * 11)
    for b in system.bodies:
        rows.append(["body", b.number, 0, *b.position(), *b.velocity()] + [""] * 5 + [*b.angles(),
                                                                                    *b.angular_velocity()])
    return rows


def set_rigid_initial_state(system: System, path: Path) -> None:
    """Rod and body states from a corpus ``<case>_initial.csv`` (rod end nodes give end A and the
    axis; bodies their position, Euler XYZ angles and velocities)."""
    ref = gen_reference().read_initial(str(path))

    def vec(row, cols):
        return np.array([float(row[c]) for c in cols])

    for i in range(len(system.bodies)):
        r = ref[("body", i + 1, 0)]
        system.set_body_state(i, position=vec(r, "xyz"), angles=vec(r, ("rx", "ry", "rz")),
                              velocity=vec(r, ("vx", "vy", "vz")), angular_velocity=vec(r, ("wx", "wy", "wz")))
    for k, rod in enumerate(system.model.rods):
        a = ref[("rod", k + 1, 0)]
        pa = vec(a, "xyz")
        axis = None
        if rod.N > 0:
            # from node 1, not node N: MoorDyn reports the end-B node of a free rod wrongly at t = 0
            pb = vec(ref[("rod", k + 1, 1)], "xyz")
            axis = (pb - pa) / np.linalg.norm(pb - pa)
        system.set_rod_state(k, end_a=pa, axis=axis, velocity=vec(a, ("vx", "vy", "vz")))


def write_initial(system: System, path: Path) -> None:
    gr = gen_reference()
    with open(path, "w") as f:
        f.write(",".join(gr.INITIAL_HEADER) + "\n")
        for row in initial_rows(system):
            f.write(",".join(gr.fmt(v) for v in row) + "\n")


# ----------------------------------------------------------------------------- series
def channels(system: System, spec: dict, coupled_force: list) -> list[tuple[list[str], object]]:
    """(column names, getter) pairs for the case's ``outputs`` block."""
    gr = gen_reference()
    out_spec = spec.get("outputs", {})
    ch = []
    nl = len(system.lines)
    npnt = len(system.points)
    for i in gr._ids(out_spec.get("line_end_tensions"), nl):
        ln = system.lines[i - 1]
        ch.append(([f"L{i}_TA", f"L{i}_TB"], lambda ln=ln: (ln.anchor_tension(), ln.fairlead_tension())))
    for item in out_spec.get("line_nodes", []) or []:
        sel = item["line"]
        for i in gr._ids(sel if (isinstance(sel, list) or sel == "all") else [sel], nl):
            ln = system.lines[i - 1]
            for j in gr._nodes(item.get("nodes", "all"), ln.n_segments + 1):
                for fld in item.get("fields", ["pos"]):
                    p = f"L{i}_n{j}"
                    if fld == "pos":
                        ch.append(([p + "_x", p + "_y", p + "_z"], lambda ln=ln, j=j: ln.node_positions()[j]))
                    elif fld == "ten":
                        ch.append(([p + "_T"], lambda ln=ln, j=j: (ln.node_tensions()[j],)))
                    elif fld == "curv":
                        ch.append(([p + "_curv"], lambda ln=ln, j=j: (ln.node_curvatures()[j],)))
                    elif fld == "force":
                        ch.append(([p + "_F"], lambda ln=ln, j=j: (np.linalg.norm(ln.node_forces()[j]),)))
    for i in gr._ids(out_spec.get("points"), npnt):
        pt = system.points[i - 1]
        ch.append(([f"P{i}_x", f"P{i}_y", f"P{i}_z"], pt.position))
    for i in gr._ids(out_spec.get("point_forces"), npnt):
        pt = system.points[i - 1]
        ch.append(([f"P{i}_Fx", f"P{i}_Fy", f"P{i}_Fz", f"P{i}_F"],
                    lambda pt=pt: (*pt.force(), np.linalg.norm(pt.force()))))
    for i in gr._ids(out_spec.get("rods"), len(system.rods)):
        rod = system.rods[i - 1]
        ch.append(([f"R{i}_{e}_{c}" for e in "AB" for c in "xyz"], lambda rod=rod: rod.end_positions().ravel()))
    for i in gr._ids(out_spec.get("bodies"), len(system.bodies)):
        b = system.bodies[i - 1]
        ch.append(([f"B{i}_{c}" for c in ("x", "y", "z", "rx", "ry", "rz")], b.pose))
    if out_spec.get("coupled_forces") and system.n_coupled_dof:
        ch.append((["Fc_" + lab for lab in system.coupled_dof_labels], lambda: coupled_force[0]))
    return ch


def run_case(name: str, *, own_ic: bool = False, out_dir: Path | None = None, env: dict | None = None) -> dict:
    """Run one corpus case; returns paths of the series/initial CSVs and timings.

    With ``own_ic`` False the dynamics start from MoorDyn's initial state
    (``reference/<case>_initial.csv``), as the README recommends for a like-for-like comparison of
    the dynamics; with True moorline's own initial-condition solver is used. ``env`` overrides
    fields of the model's Environment (e.g. ``{"contact": "vertical"}``).
    """
    gr = gen_reference()
    spec = load_case(name)
    deck = CONF / spec["input"]
    case_dir = deck.parent
    model = read_deck(deck)
    for key, value in (env or {}).items():
        setattr(model.env, key, value)
    if own_ic and model.options.ICNewton == -1:
        # the corpus' references start from MoorDyn's initial-condition methods, which stop at
        # threshIC or TmaxIC (lowe_langley: 30 s, 9 cm from equilibrium); moorline's default Newton
        # start goes to equilibrium (a documented difference, docs/moordyn_differences.md), so the
        # like-for-like check runs MoorDyn's methods
        model.options.ICNewton = 0
    # MoorDyn reports the loads of the last stage of its last step; compare like with like
    system = System(model, loads_at="last_stage")
    X0 = system.deck_coupled_positions()
    Xf = gr.make_motion(spec.get("coupled"), X0, str(case_dir))
    dt = float(spec["dt"])
    duration = float(spec["duration"])
    nsteps = int(round(duration / dt))
    every = max(1, int(round(float(spec.get("sample_dt", dt)) / dt)))
    traj = Trajectory.from_function(Xf, nsteps * dt, dt, interpolation="linear") if system.n_coupled_dof \
        else Trajectory.hold(X0)

    t0 = time.perf_counter()
    if own_ic:
        system.init(Xf(0.0), np.zeros(system.n_coupled_dof), solve_ic=True)
    else:
        system.init(Xf(0.0), np.zeros(system.n_coupled_dof), solve_ic=False)
        lp, lv, pp, pv = read_initial_state(system, CONF / "reference" / f"{name}_initial.csv")
        system.set_state(lp, lv, pp, pv)
        if system.rods or system.bodies:
            set_rigid_initial_state(system, CONF / "reference" / f"{name}_initial.csv")
    t_init = time.perf_counter() - t0

    out_dir = Path(out_dir or ROOT / "out" / "conformance")
    out_dir.mkdir(parents=True, exist_ok=True)
    tag = ("_ownic" if own_ic else "") + "".join(f"_{k}-{v}" for k, v in (env or {}).items())
    ini_path = out_dir / f"{name}{tag}_initial.csv"
    write_initial(system, ini_path)

    cf = [system.coupled_forces()]
    ch = channels(system, spec, cf)
    names = ["time"] + [n for ns, _ in ch for n in ns]

    def sample(t):
        row = [t]
        for _, g in ch:
            row += [float(v) for v in g()]
        return row

    rows = [sample(0.0)]
    motion = traj.as_motion()
    ext = spec.get("external_waves")
    kin = gr.airy_lowe_langley(ext) if ext else None
    t1 = time.perf_counter()
    if kin is None:
        for k in range(every, nsteps + 1, every):
            system.advance_to(k * dt, motion)
            cf[0] = system.coupled_forces()
            rows.append(sample(k * dt))
    else:
        # MoorDyn's external kinematics: at the start of every outer step, evaluated at the points'
        # current positions at mid-step, held during the step
        for k in range(nsteps):
            u, a = kin(k * dt + 0.5 * dt, system.water_node_positions())
            system.set_water_kinematics(u, a)
            system.advance_to((k + 1) * dt, motion)
            cf[0] = system.coupled_forces()
            if (k + 1) % every == 0:
                rows.append(sample((k + 1) * dt))
    t_run = time.perf_counter() - t1
    ser_path = out_dir / f"{name}{tag}_series.csv"
    with open(ser_path, "w") as f:
        f.write(",".join(names) + "\n")
        for row in rows:
            f.write(",".join(gr.FMT % v for v in row) + "\n")
    return {"series": ser_path, "initial": ini_path, "init_s": t_init, "run_s": t_run, "system": system,
            "spec": spec}


def compare(name: str, result: dict, *, initial: bool) -> list[dict]:
    """The corpus' own verdicts: series groups, and (``initial``) the initial-state checks."""
    gr = gen_reference()
    spec = result["spec"]
    rn, r = gr.read_series(str(CONF / "reference" / f"{name}_series.csv"))
    sn, s = gr.read_series(str(result["series"]))
    res = gr.compare_series(spec, rn, r, sn, s)
    if initial:
        ref0 = gr.read_initial(str(CONF / "reference" / f"{name}_initial.csv"))
        res += gr.compare_initial_state(spec, ref0, gr.read_initial(str(result["initial"])))
    return res


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("cases", nargs="+")
    ap.add_argument("--own-ic", action="store_true", help="use moorline's IC instead of MoorDyn's initial state")
    ap.add_argument("--out", type=Path)
    ap.add_argument("--env", action="append", default=[], metavar="KEY=VALUE",
                    help="override an Environment field, e.g. contact=vertical")
    a = ap.parse_args(argv)
    env = dict(kv.split("=", 1) for kv in a.env)
    ok = True
    for name in a.cases:
        res = run_case(name, own_ic=a.own_ic, out_dir=a.out, env=env)
        md = json.loads((CONF / "reference" / "manifest.json").read_text())["cases"][name]
        print(f"{name}: init {res['init_s']:.2f} s, run {res['run_s']:.2f} s "
              f"(MoorDyn: init {md.get('runtime_init_s')} s, steps {md.get('runtime_steps_s')} s)")
        for v in compare(name, res, initial=a.own_ic):
            ok &= bool(v["pass"])
            ratio = v.get("ratio", v.get("max_abs_err", math.nan) / max(v.get("allowed", math.nan), 1e-300))
            what = ",".join(v["group"]) if "group" in v else "initial " + v["check"]
            print(f"  {'ok  ' if v['pass'] else 'FAIL'} {what:<36} worst {str(v.get('column', v.get('where'))):<18}"
                  f" err {v.get('max_abs_err', math.nan):.4g} allowed {v.get('allowed', math.nan):.4g}"
                  f" ratio {ratio:.3f}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
