"""CableDyn (CableDyn 0.3.0, an implicit finite-element cable solver) as a benchmark baseline.

    python benchmarks/cabledyn_driver.py [--cases catenary,lazy_wave] [--quick]

Runs CableDyn in-process (the ``cabledyn.CableDyn`` class over its C ABI) on the two benchmark
cases of the issue "Speed", with the same prescribed fairlead motion the MoorDyn and moorline runs
use, and MoorDyn (the ``moordyn`` package) for references:

``catenary``
    the OC3-Hywind three-line chain catenary of ``conformance/inputs/catenary_3line/lines.txt``
    (3 x 902.2 m chain, 320 m of water); every fairlead surges x(t) = X0 + 5 m s(t) sin(2 pi t / 20 s).
``lazy_wave``
    the lazy-wave power cable of ``benchmarks/decks/lazy_wave_cable.dat``; the top point heaves
    z(t) = Z0 + 2 m s(t) sin(2 pi t / 8 s).

s(t) is the smoothstep ramp u^3 (6 u^2 - 15 u + 10), u = min(t / T_ramp, 1), with T_ramp = one
period.

The CableDyn deck is translated from the MoorDyn deck (:func:`write_cabledyn_deck`): the same line
types (mass, EA, EI, diameter, drag and added-mass coefficients), points, water density, gravity,
depth and seabed stiffness and damping. Differences that follow from the two formulations:

- CableDyn's LINE TYPES columns are ``Cd_n Cd_t Ca_n Ca_t`` (MoorDyn's ``Cd Ca CdAx CaAx``); both
  codes take the tangential drag on the area pi d per metre.
- A negative BA (-zeta) is a damping ratio of each segment's axial mode in both codes, so the damping
  coefficient BA = zeta l sqrt(EA w) depends on the segment length l. The translation gives CableDyn
  the absolute BA MoorDyn computes for the deck's own segments (``damping="deck"``), so that the
  physical damping does not change with CableDyn's mesh; MoorDyn references refined from the deck
  get the same absolute BA.
- Lines joined end to end by free zero-length rods (the lazy-wave joints) become one CableDyn line
  with one SECTIONS row per MoorDyn line: CableDyn's cubic-Hermite element is C1 across sections,
  which is what the rods' clamps give the lumped-mass model. A cable end on a fixed rod (the hub
  connector) becomes a Fixed point with a Rigid END CONNECTION along the rod axis.
- CableDyn lists a line from End A = fairlead to End B = anchor; its seabed damping acts only on
  nodes moving into the seabed (MoorDyn's on any contacting node).

The fairlead tension is CableDyn's ``FairTen<L>`` channel: the magnitude of the force the line
exerts on its End A point (end element force with damping and bending shear, plus the end node's
share of weight, seabed and drag loads, without its inertia). MoorDyn's counterpart is the force it
returns for the coupled point (sum of the attached line end nodes' net forces, also without
inertia), which is what :func:`run_moordyn` records.

CableDyn's ``CableDyn_Step`` takes the coupled kinematics (position, velocity, acceleration) at the
end of the step; they are given exactly from the analytic motion. MoorDyn's ``Step`` takes the
position at the start of the step and a velocity held over it (x_k, (X(t_{k+1}) - X(t_k)) / dt).

Not part of the test suite: timings depend on the machine and on what else runs on it.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from bench_vs_moordyn import moordyn_coupled_points, moordyn_nodes, quiet_in

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("MOORLINE_SHARED", ROOT.parent / "shared"))


@dataclass(frozen=True)
class Case:
    """A benchmark case: a MoorDyn deck and the motion of its coupled points.

    Every coupled point moves by ``amplitude * s(t) * sin(2 pi t / period)`` along global axis
    ``axis`` (0 = x, 2 = z), s(t) being the smoothstep ramp over ``ramp`` seconds.
    """

    name: str
    deck: Path
    amplitude: float
    period: float
    ramp: float
    axis: int
    duration: float


CASES = {
    "catenary": Case("catenary", SHARED / "conformance" / "inputs" / "catenary_3line" / "lines.txt",
                     amplitude=5.0, period=20.0, ramp=20.0, axis=0, duration=100.0),
    "lazy_wave": Case("lazy_wave", ROOT / "benchmarks" / "decks" / "lazy_wave_cable.dat",
                      amplitude=2.0, period=8.0, ramp=8.0, axis=2, duration=60.0),
}


# ----------------------------------------------------------------------------------------- motion
def smoothstep(t: float, ramp: float) -> tuple[float, float, float]:
    """The ramp s(t) = u^3 (6 u^2 - 15 u + 10), u = min(t / ramp, 1), and its first two time
    derivatives."""
    if ramp <= 0.0 or t >= ramp:
        return 1.0, 0.0, 0.0
    if t <= 0.0:
        return 0.0, 0.0, 0.0
    u = t / ramp
    s = u**3 * (6.0 * u * u - 15.0 * u + 10.0)
    ds = 30.0 * u * u * (u - 1.0) ** 2 / ramp
    dds = 60.0 * u * (u - 1.0) * (2.0 * u - 1.0) / ramp**2
    return s, ds, dds


class Motion:
    """Prescribed motion of the coupled points of a case.

    Parameters
    ----------
    case : Case
    x0 : array_like (3 n,)
        Positions of the n coupled points at rest [m].
    """

    def __init__(self, case: Case, x0):
        self.x0 = np.asarray(x0, dtype=float).copy()
        self.case = case
        self.direction = np.zeros_like(self.x0)
        self.direction[case.axis::3] = 1.0

    def _parts(self, t: float) -> tuple[float, float, float, float, float, float]:
        c = self.case
        w = 2.0 * math.pi / c.period
        s, ds, dds = smoothstep(t, c.ramp)
        return s, ds, dds, math.sin(w * t), w * math.cos(w * t), -w * w * math.sin(w * t)

    def position(self, t: float) -> np.ndarray:
        """Coupled positions at time t [m]."""
        s, _, _, f, _, _ = self._parts(t)
        return self.x0 + self.direction * (self.case.amplitude * s * f)

    def velocity(self, t: float) -> np.ndarray:
        """Coupled velocities at time t [m/s]."""
        s, ds, _, f, df, _ = self._parts(t)
        return self.direction * (self.case.amplitude * (ds * f + s * df))

    def acceleration(self, t: float) -> np.ndarray:
        """Coupled accelerations at time t [m/s^2]."""
        s, ds, dds, f, df, ddf = self._parts(t)
        return self.direction * (self.case.amplitude * (dds * f + 2.0 * ds * df + s * ddf))


# ------------------------------------------------------------------------------- deck translation
def _distribute(n_total: int, lengths: list[float]) -> list[int]:
    """Split ``n_total`` segments over sections in proportion to their lengths (at least one
    each, largest remainders first)."""
    n_total = max(int(n_total), len(lengths))
    total = sum(lengths)
    raw = [n_total * length / total for length in lengths]
    out = [max(1, int(math.floor(r))) for r in raw]
    order = sorted(range(len(lengths)), key=lambda i: raw[i] - math.floor(raw[i]), reverse=True)
    k = 0
    while sum(out) < n_total:
        out[order[k % len(order)]] += 1
        k += 1
    while sum(out) > n_total:
        i = max(range(len(out)), key=lambda j: out[j])
        out[i] -= 1
    return out


def _absolute_ba(lt, segment_length: float) -> float:
    """MoorDyn's axial damping coefficient [N s] of a line type on segments of the given length
    (a negative BA is -zeta: BA = zeta l sqrt(EA w))."""
    ba = float(lt.BA)
    if ba >= 0.0:
        return ba
    return -ba * segment_length * math.sqrt(float(lt.EA) * float(lt.w))


@dataclass
class _Chain:
    """One physical line: MoorDyn lines joined end to end by free zero-length rods, listed from the
    coupled end (CableDyn End A) to the other end (End B)."""

    lines: list[int]            # MoorDyn line indices (0-based), from End A to End B
    coupled_point: int          # model point index of End A
    end_b: np.ndarray           # position of End B
    end_b_direction: np.ndarray | None  # cable direction arriving at a clamping rod end (None: pinned)


def _chains(model) -> list[_Chain]:
    """Group the deck's lines into physical lines between a coupled point and a fixed end."""
    from moorline.model.types import PointKind, RodKind

    if model.bodies:
        raise NotImplementedError("decks with bodies are not translated")
    for p in model.points:
        if p.kind not in (PointKind.FIXED, PointKind.COUPLED):
            raise NotImplementedError("only Fixed and Coupled points are translated")

    def is_joint(att) -> bool:
        return att.kind == "rod" and model.rods[att.index].kind == RodKind.FREE and model.rods[att.index].N == 0

    # the line on the other side of a joint rod end
    at_rod_end = {}
    for i, ln in enumerate(model.lines):
        for which, att in (("a", ln.end_a), ("b", ln.end_b)):
            if att.kind == "rod":
                at_rod_end.setdefault(att.index, []).append((i, which, att.end))
    chains = []
    used = set()
    for i, ln in enumerate(model.lines):
        if i in used:
            continue
        ends = [ln.end_a, ln.end_b]
        coupled = [att for att in ends if att.kind == "point" and model.points[att.index].kind == PointKind.COUPLED]
        if not coupled:
            continue
        # walk from the coupled end through the joints
        seq = [i]
        cur, came_from_end = i, ("a" if ln.end_a is coupled[0] else "b")
        while True:
            cl = model.lines[cur]
            far = cl.end_b if came_from_end == "a" else cl.end_a
            if not is_joint(far):
                break
            nxt = [(j, w) for j, w, _ in at_rod_end[far.index] if j != cur]
            if len(nxt) != 1:
                raise NotImplementedError("a joint rod must join exactly two lines")
            cur, came_from_end = nxt[0]
            seq.append(cur)
        used.update(seq)
        last = model.lines[cur]
        far = last.end_b if came_from_end == "a" else last.end_a
        direction = None
        if far.kind == "point":
            if model.points[far.index].kind != PointKind.FIXED:
                raise NotImplementedError("a line must run from a Coupled point to a Fixed end")
            pos = np.asarray(model.points[far.index].r, dtype=float)
        elif far.kind == "rod" and model.rods[far.index].kind == RodKind.FIXED:
            rod = model.rods[far.index]
            ra, rb = np.asarray(rod.rA, dtype=float), np.asarray(rod.rB, dtype=float)
            pos = rb if far.end == "B" else ra
            axis = (rb - ra) / np.linalg.norm(rb - ra)
            # a cable end on a rod end leaves the rod straight: away from rod end B along +axis,
            # away from rod end A along -axis (spec 3.10); CableDyn's direction at End B is the
            # cable's arriving there (End A -> End B), the opposite
            direction = -axis if far.end == "B" else axis
        else:
            raise NotImplementedError(f"unsupported line end {far}")
        chains.append(_Chain(lines=seq, coupled_point=coupled[0].index, end_b=pos, end_b_direction=direction))
    return chains


def write_cabledyn_deck(case: Case, n_elements_per_line: int, dt: float, path, *, damping: str = "deck") -> Path:
    """Write the CableDyn deck of ``case`` with ``n_elements_per_line`` elements per physical line
    (split over its sections in proportion to their lengths).

    Parameters
    ----------
    case : Case
    n_elements_per_line : int
    dt : float
        CableDyn's step (``dtM``; a deck with finite-EI lines needs it) [s].
    path : str or Path
    damping : {"deck", "ratio"}
        "deck": absolute BA as MoorDyn computes it for the deck's own segments; "ratio": pass a
        negative BA (-zeta) through, so that CableDyn applies it per element of its own mesh.

    Returns
    -------
    Path
        The deck written.
    """
    from cabledyn import DeckWriter

    from moorline.io import read_deck
    from moorline.model.types import PointKind

    model = read_deck(case.deck)
    env = model.env
    chains = _chains(model)
    w = DeckWriter(title=f"{case.name}: translated from {case.deck.name} by benchmarks/cabledyn_driver.py")
    types_written = {}
    # coupled points first, in the deck's order (the order of the coupled DOFs in both codes)
    coupled_order = [i for i, p in enumerate(model.points) if p.kind == PointKind.COUPLED]
    chains.sort(key=lambda c: coupled_order.index(c.coupled_point))
    for k, ch in enumerate(chains, 1):
        w.add_point(k, "Coupled", *model.points[ch.coupled_point].r)
    for k, ch in enumerate(chains, 1):
        w.add_point(len(chains) + k, "Fixed", *ch.end_b)
    for k, ch in enumerate(chains, 1):
        w.add_line(k, node_a=k, node_b=len(chains) + k)
        lengths = [model.lines[i].L for i in ch.lines]
        for i, n in zip(ch.lines, _distribute(n_elements_per_line, lengths), strict=True):
            ln = model.lines[i]
            lt = model.line_types[ln.line_type]
            ba = _absolute_ba(lt, ln.L / ln.N) if damping == "deck" else float(lt.BA)
            key = (ln.line_type, round(ba, 9))
            if key not in types_written:
                name = f"{ln.line_type}{len(types_written) + 1}"
                types_written[key] = name
                w.add_line_type(name, diam=lt.d, mass=lt.w, ea=float(lt.EA), ba=ba, ei=float(lt.EI),
                                cdn=lt.Cd, cdt=lt.CdAx, can=lt.Ca, cat=lt.CaAx)
            w.add_section(line_id=k, line_type=types_written[key], length=ln.L, num_segs=n)
        if ch.end_b_direction is not None:
            w.add_end_connection(k, "B", "Rigid", tuple(ch.end_b_direction))
        w.add_output(f"FairTen{k}")
    w.set_option(env.g, "g")
    w.set_option(env.rho, "rhoW")
    w.set_option(env.depth, "WtrDpth")
    w.set_option(env.kBot, "kBot")
    w.set_option(env.cBot, "cBot")
    w.set_option(float(dt), "dtM")
    w.set_option(float(dt) * max(1, round(case.duration / dt)), "TMax")
    return w.write(path, caller_driven=True)


# ------------------------------------------------------------------------------------- CableDyn run
def run_cabledyn(case: str | Case, n_elements_per_line: int, dt: float, duration: float | None = None, *,
                 damping: str = "deck", workdir=None) -> dict:
    """Run CableDyn in-process on a benchmark case.

    Parameters
    ----------
    case : str or Case
        "catenary", "lazy_wave" or a :class:`Case`.
    n_elements_per_line : int
        Elements per physical line (fairlead to anchor or hub).
    dt : float
        Time step [s] (one implicit generalised-alpha step per coupling step).
    duration : float, optional
        Simulated time [s]; the case's by default.
    damping : {"deck", "ratio"}
        See :func:`write_cabledyn_deck`.
    workdir : path, optional
        Where the translated deck is written (a temporary folder by default).

    Returns
    -------
    dict
        ``wall``: wall time of the time loop [s] (steps, motion and tension sampling);
        ``wall_steps``: the part spent inside ``CableDyn.step``; ``startup``: deck parsing, meshing
        and the static solve (``CableDyn(deck)``) [s]; ``t``: sample times (0, dt, ...) [s];
        ``fairlead_tension``: (n_t, n_lines) FairTen of each line (coupled end) [N];
        ``newton_iterations``: total Newton iterations (``CableDyn.step`` reports 0 for decks with
        finite-EI lines); ``nodes``: nodes of all lines after CableDyn's static solve (it refines a
        finite-EI mesh too coarse for the curvature of the equilibrium: 17 requested elements of the
        lazy-wave cable become 168); ``layout``: the coupled DOF blocks; ``deck``: the translated
        deck's text.
    """
    from cabledyn import CableDyn

    c = CASES[case] if isinstance(case, str) else case
    duration = c.duration if duration is None else duration
    nsteps = int(round(duration / dt))
    with tempfile.TemporaryDirectory(prefix="cabledyn_") as tmp:
        folder = Path(workdir) if workdir else Path(tmp)
        deck = write_cabledyn_deck(c, n_elements_per_line, dt, folder / f"{c.name}.dat", damping=damping)
        t0 = time.perf_counter()
        model = CableDyn(deck)
        startup = time.perf_counter() - t0
        text = deck.read_text()
    try:
        layout = model.coupled_layout()
        host = model.host_dofs()
        q, v, a = model.get_coupled_motion()
        x0 = q[host].copy()
        motion = Motion(c, x0)
        lines = [ln.id for ln in model.lines]
        channels = [f"FairTen{i}" for i in lines]
        ten = np.empty((nsteps + 1, len(lines)))
        ten[0] = model.channels(channels)
        nodes = sum(ln.n_nodes for ln in model.lines)
        its = 0
        wall_steps = 0.0
        t_loop = time.perf_counter()
        for k in range(1, nsteps + 1):
            t = k * dt
            q[host] = motion.position(t)
            v[host] = motion.velocity(t)
            a[host] = motion.acceleration(t)
            t1 = time.perf_counter()
            its += model.step(dt, q, v, a)
            wall_steps += time.perf_counter() - t1
            ten[k] = model.channels(channels)
        wall = time.perf_counter() - t_loop
    finally:
        model.close()
    return {"code": "CableDyn", "case": c.name, "n_elements_per_line": n_elements_per_line, "dt": dt,
            "wall": wall, "wall_steps": wall_steps, "startup": startup, "t": np.arange(nsteps + 1) * dt,
            "fairlead_tension": ten, "newton_iterations": its, "nodes": nodes, "layout": layout, "deck": text}


# -------------------------------------------------------------------------------------- MoorDyn run
_TABLES = {"LINE TYPES": "types", "LINE DICTIONARY": "types", "LINES": "lines", "LINE PROPERTIES": "lines",
           "OPTIONS": "options", "SOLVER OPTIONS": "options"}


def refine_moordyn_deck(text: str, model, n_segments_per_line: int | None = None, dtM: float | None = None,
                        *, damping: str = "deck", options: dict | None = None) -> str:
    """A MoorDyn deck with other segment counts, time step or options.

    Parameters
    ----------
    text : str
        The deck's text.
    model : moorline Model
        The same deck read by moorline (for line lengths and chains).
    n_segments_per_line : int, optional
        Segments per physical line (split over joined lines in proportion to their lengths).
    dtM : float, optional
    damping : {"deck", "ratio"}
        "deck": when the segments change, replace a negative BA by the absolute BA of the deck's
        own segments, so that the physical damping stays that of the deck.
    options : dict, optional
        Further OPTIONS rows ``{keyword: value}`` (replaced or added).

    Returns
    -------
    str
    """
    new_n = {}
    if n_segments_per_line is not None:
        for ch in _chains(model):
            lengths = [model.lines[i].L for i in ch.lines]
            for i, n in zip(ch.lines, _distribute(n_segments_per_line, lengths), strict=True):
                new_n[i] = n
    ba_of_type = {}
    if damping == "deck" and n_segments_per_line is not None:
        for ln in model.lines:
            lt = model.line_types[ln.line_type]
            ba = _absolute_ba(lt, ln.L / ln.N)
            if ln.line_type in ba_of_type and not math.isclose(ba_of_type[ln.line_type], ba, rel_tol=1e-12):
                raise NotImplementedError(f"line type {ln.line_type} has different segment lengths")
            ba_of_type[ln.line_type] = ba
    opts = dict(options or {})
    if dtM is not None:
        opts["dtM"] = dtM
    out = []
    section, row = None, 0
    line_no = 0
    for raw in text.splitlines():
        if "---" in raw:
            if section == "options":
                out.extend(f"{v} {k}" for k, v in opts.items())
                opts = {}
            up = raw.upper()
            section = next((v for k, v in _TABLES.items() if re.search(rf"\b{k}\b", up)), None)
            if section == "lines" and "ROD" in up:
                section = None
            row = 0
            out.append(raw)
            continue
        row += 1
        tok = raw.split()
        if section == "types" and row > 2 and len(tok) >= 10 and tok[0] in ba_of_type:
            tok[4] = repr(ba_of_type[tok[0]])
            raw = " ".join(tok)
        elif section == "lines" and row > 2 and len(tok) >= 6:
            if line_no in new_n:
                tok[5] = str(new_n[line_no])
                raw = " ".join(tok)
            line_no += 1
        elif section == "options" and len(tok) >= 2:
            key = next((k for k in opts if k.lower() == tok[1].lower()), None)
            if key is not None:
                raw = f"{opts.pop(key)} {tok[1]}"
        out.append(raw)
    return "\n".join(out) + "\n"


def run_moordyn(case: str | Case, n_segments_per_line: int | None = None, dtM: float | None = None,
                duration: float | None = None, outer_dt: float = 0.05, *, scheme: str | None = None,
                damping: str = "deck", options: dict | None = None) -> dict:
    """Run MoorDyn (the ``moordyn`` package) on a benchmark case, for references and comparisons.

    Parameters
    ----------
    case : str or Case
    n_segments_per_line : int, optional
        Segments per physical line; the deck's by default.
    dtM : float, optional
        MoorDyn's time step; the deck's by default.
    duration : float, optional
    outer_dt : float
        Coupling step [s]: MoorDyn_Step(x_k, (X(t_{k+1}) - X(t_k)) / outer_dt); tensions are sampled
        at its ends.
    scheme : str, optional
        ``tScheme`` (the deck's by default).
    damping : {"deck", "ratio"}
        See :func:`refine_moordyn_deck`.
    options : dict, optional
        Further OPTIONS rows.

    Returns
    -------
    dict
        ``wall`` (time loop) and ``startup`` (Create + Init) [s], ``t``, ``fairlead_tension``
        (n_t, n_coupled_points): magnitude of the force on each coupled point [N], ``nodes``.
    """
    import moordyn as md

    from moorline.io import read_deck

    c = CASES[case] if isinstance(case, str) else case
    duration = c.duration if duration is None else duration
    model = read_deck(c.deck)
    opts = dict(options or {})
    if scheme:
        opts["tScheme"] = scheme
    text = refine_moordyn_deck(c.deck.read_text(), model, n_segments_per_line, dtM, damping=damping, options=opts)
    nsteps = int(round(duration / outer_dt))
    with tempfile.TemporaryDirectory(prefix="moordyn_") as tmp:
        deck = Path(tmp) / c.deck.name
        deck.write_text(text)
        with quiet_in(tmp):
            t0 = time.perf_counter()
            s = md.Create(deck.name)
            n = md.NCoupledDOF(s)
            x0 = [x for p in moordyn_coupled_points(md, s) for x in md.GetPointPos(p)]
            motion = Motion(c, x0)
            f = md.Init(s, list(motion.position(0.0)), [0.0] * n)
            f = md.Step(s, list(motion.position(0.0)), [0.0] * n, 0.0, 0.0)
            startup = time.perf_counter() - t0
            ten = np.empty((nsteps + 1, n // 3))
            ten[0] = np.linalg.norm(np.reshape(f, (-1, 3)), axis=1)
            t0 = time.perf_counter()
            for k in range(nsteps):
                xk = motion.position(k * outer_dt)
                vk = (motion.position((k + 1) * outer_dt) - xk) / outer_dt
                f = md.Step(s, list(xk), list(vk), k * outer_dt, outer_dt)
                ten[k + 1] = np.linalg.norm(np.reshape(f, (-1, 3)), axis=1)
            wall = time.perf_counter() - t0
            nodes = moordyn_nodes(md, s)
            md.Close(s)
    return {"code": "MoorDyn", "case": c.name, "n_segments_per_line": n_segments_per_line, "dtM": dtM,
            "wall": wall, "startup": startup, "t": np.arange(nsteps + 1) * outer_dt, "fairlead_tension": ten,
            "nodes": nodes}


# ------------------------------------------------------------------------------------- comparison
def tension_error(reference: dict, result: dict, t_start: float) -> float:
    """Largest over the lines of RMS(result - reference) / mean(reference), on the result's sample
    times from ``t_start`` on (the reference interpolated linearly onto them)."""
    t = result["t"]
    keep = (t >= t_start - 1e-9) & (t <= reference["t"][-1] + 1e-9)
    worst = 0.0
    for j in range(result["fairlead_tension"].shape[1]):
        ref = np.interp(t[keep], reference["t"], reference["fairlead_tension"][:, j])
        diff = result["fairlead_tension"][keep, j] - ref
        worst = max(worst, float(np.sqrt(np.mean(diff**2)) / np.mean(ref)))
    return worst


# ------------------------------------------------------------------------------------------ study
#: references and grids of the study (:func:`main`): segments or elements per line, steps [s]
STUDY = {
    "catenary": {"cd_ref": (160, 0.01), "md_ref": (160, 1e-4, 0.01), "md_outer": 0.1,
                 "cd_grid": ((5, 8, 10, 12, 15, 20, 30, 40), (2.0, 1.0, 0.5, 0.25, 0.1)),
                 "md_grid": ((8, 10, 12, 15, 20, 30), (0.005, 0.002))},
    "lazy_wave": {"cd_ref": (274, 0.01), "md_ref": (274, 5e-5, 0.005), "md_outer": 0.01,
                  "cd_grid": ((17, 34, 64, 100, 137), (0.5, 0.2, 0.1, 0.05)),
                  "md_grid": ((23, 35, 46, 69, 137), (0.005, 0.002, 0.0005))},
}
#: the same with coarse references and few settings (``--quick``)
QUICK = {
    "catenary": {"cd_ref": (80, 0.02), "md_ref": (80, 2.5e-4, 0.02), "md_outer": 0.1,
                 "cd_grid": ((10, 15, 20), (1.0, 0.5)), "md_grid": ((12, 15), (0.005,))},
    "lazy_wave": {"cd_ref": (137, 0.02), "md_ref": (137, 2e-4, 0.005), "md_outer": 0.01,
                  "cd_grid": ((17, 64), (0.5, 0.2)), "md_grid": ((35, 69), (0.005,))},
}


def _timed(func, args: tuple, kwargs: dict, repeat: int) -> dict:
    """Call ``func(*args, **kwargs)`` ``repeat`` times; the first result with the median wall and
    startup times."""
    results = [func(*args, **kwargs) for _ in range(max(1, repeat))]
    out = dict(results[0])
    for key in ("wall", "startup"):
        out[key] = float(np.median([r[key] for r in results]))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", default="catenary,lazy_wave", help="comma-separated subset")
    ap.add_argument("--repeat", type=int, default=3, help="timing repeats (median)")
    ap.add_argument("--quick", action="store_true", help="coarse references, few settings")
    ap.add_argument("--tol", type=float, default=0.01, help="accuracy target: RMS error / mean tension")
    args = ap.parse_args(argv)
    study = QUICK if args.quick else STUDY
    for name in args.cases.split(","):
        case, st = CASES[name], study[name]
        t_start = case.ramp
        motion = "surge" if case.axis == 0 else "heave"
        print(f"== {name}: {case.duration:g} s, {case.amplitude:g} m {motion} of {case.period:g} s period after a "
              f"{case.ramp:g} s ramp; tensions compared from t = {t_start:g} s ==")
        n, dt = st["cd_ref"]
        ref_cd = run_cabledyn(case, n, dt)
        print(f"reference CableDyn: {n} elements per line ({ref_cd['nodes']} nodes), dt {dt:g} s: "
              f"wall {ref_cd['wall']:.2f} s")
        n, dtm, outer = st["md_ref"]
        ref_md = run_moordyn(case, n, dtm, outer_dt=outer)
        print(f"reference MoorDyn: {n} segments per line ({ref_md['nodes']} nodes), dtM {dtm:g} s, coupling step "
              f"{outer:g} s: wall {ref_md['wall']:.2f} s")
        print(f"references: RMS difference {100 * tension_error(ref_md, ref_cd, t_start):.3f} % of the mean tension")
        head = (f"{'code':<9} {'n/line':>6} {'nodes':>6} {'step s':>8} {'startup s':>9} {'wall s':>8} "
                f"{'err vs CD':>9} {'err vs MD':>9}")
        print(head)
        print("-" * len(head))
        ns, dts = st["cd_grid"]
        rows = [("CableDyn", n, dt, run_cabledyn, {}) for n in ns for dt in dts]
        ns, dtms = st["md_grid"]
        rows += [("MoorDyn", n, dtm, run_moordyn, {"outer_dt": max(st["md_outer"], dtm)}) for n in ns for dtm in dtms]
        best = {}
        for code, n, step, func, kw in rows:
            try:
                r = _timed(func, (case, n, step), kw, args.repeat)
            except Exception as exc:  # an unstable run is a result too
                print(f"{code:<9} {n:>6} {'':>6} {step:>8g}  failed: {str(exc).splitlines()[0][:70]}")
                continue
            e_cd, e_md = tension_error(ref_cd, r, t_start), tension_error(ref_md, r, t_start)
            print(f"{code:<9} {n:>6} {r['nodes']:>6} {step:>8g} {r['startup']:>9.3f} {r['wall']:>8.3f} "
                  f"{100 * e_cd:>8.3f}% {100 * e_md:>8.3f}%")
            if max(e_cd, e_md) <= args.tol and (code not in best or r["wall"] < best[code][2]):
                best[code] = (n, step, r["wall"], r["startup"])
        for code, (n, step, wall, startup) in best.items():
            print(f"cheapest {code} within {100 * args.tol:g} % of both references: {n} per line, step {step:g} s, "
                  f"wall {wall:.3f} s (+ start-up {startup:.3f} s)")
        print()
    return 0


if __name__ == "__main__":
    sys.exit(main())
