"""MoorDyn-style output: OUTPUTS channels, per-line output files and the ``.out`` text tables.

Three parts:

* :func:`decompose` cuts a word into MoorDyn's ``let1 num1 let2 num2 let3`` pieces and
  :func:`parse_channels` turns the OUTPUTS channel names of a deck (``FairTen1``, ``L2N5T``,
  ``Point3PZ``, ...) into :class:`Channel` objects; :func:`evaluate` reads their current values from
  a running :class:`moorline.system.System`.
* :func:`line_file_columns` and :func:`line_file_values` give the columns of the per-line file
  ``<base>_Line<n>.out`` selected by the line's output flags (``p K v U D V t c s d b``).
* :func:`write_main_out` and :func:`write_line_out` write MoorDyn's fixed-width text tables
  (time ``%10.4f``, values ``%20.7e``, a title row and an optional units row), and
  :class:`OutputRecorder` collects rows during a run and writes every file atomically.

This module only reads from a system through the public views of :mod:`moorline.system`
(``system.lines[i]``, ``system.points[i]``, ``system.model``, ``system.t``); it does not import
the coupling layer, so the dependency direction ``io -> model`` holds.

Channel rules (MoorDyn-C v2.7 behaviour, checked against the ``moordyn`` 2.7.2 wheel):

* a name that cannot be interpreted (a v1 ``END`` row, v1 ``Con3vY`` names, an unknown prefix, a
  missing or unknown quantity code) is skipped with a warning on the ``moorline.io`` logger;
* a reference to a line, point, rod, body or node that does not exist raises
  :class:`moorline.errors.DeckError`;
* a known quantity code that is not defined for the object (e.g. ``L1N2AX``, ``P1RX``, ``P1TA``)
  keeps its column, as MoorDyn does, and is written as zeros (with a warning).
"""

from __future__ import annotations

import logging
import math
import os
import secrets
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import DeckError

log = logging.getLogger("moorline.io")

__all__ = [
    "Channel",
    "OutputRecorder",
    "decompose",
    "evaluate",
    "has_line_file",
    "body_file_values",
    "has_rod_file",
    "line_file_columns",
    "line_file_values",
    "rod_file_columns",
    "rod_file_values",
    "write_body_out",
    "output_due",
    "parse_channels",
    "write_line_out",
    "write_main_out",
    "write_table",
]

# ---------------------------------------------------------------------------------------- words


def decompose(word: str) -> list[str]:
    """Cut a word into MoorDyn's alternating letter/number pieces (spec 1.1 rule 13).

    The word is upper-cased; a new piece starts whenever the character class switches between
    letter and digit, giving at most five pieces ``let1 num1 let2 num2 let3``. Other characters
    (``_``, ``.``, ...) stay in the current piece, and everything after the fourth switch goes into
    ``let3``. A word that starts with a digit has an empty ``let1``.

    Parameters
    ----------
    word : str

    Returns
    -------
    list of str
        The pieces found, 1 to 5 of them (no trailing empty pieces).

    Examples
    --------
    >>> decompose("Body1Pinned")
    ['BODY', '1', 'PINNED']
    >>> decompose("L1N5T")
    ['L', '1', 'N', '5', 'T']
    >>> decompose("12")
    ['', '12']
    """
    pieces = [""]
    for ch in word.upper():
        if len(pieces) < 5:
            is_digit = "0" <= ch <= "9"
            is_letter = ch.isalpha()
            current_is_digit = len(pieces) % 2 == 0  # pieces 0, 2, 4 are letters; 1, 3 numbers
            if (is_digit and not current_is_digit) or (is_letter and current_is_digit):
                pieces.append("")
        pieces[-1] += ch
    return pieces


# ---------------------------------------------------------------------------------------- channels

#: unit of each quantity code (main-file units row: bare strings, ``(frac)`` for SUB, as in MoorDyn)
_QUANTITY_UNITS = {
    **dict.fromkeys(("PX", "PY", "PZ"), "m"),
    **dict.fromkeys(("VX", "VY", "VZ"), "m/s"),
    **dict.fromkeys(("AX", "AY", "AZ"), "m/s^2"),
    **dict.fromkeys(("RX", "RY", "RZ"), "deg"),
    **dict.fromkeys(("RVX", "RVY", "RVZ"), "deg/s"),
    **dict.fromkeys(("RAX", "RAY", "RAZ"), "deg/s^2"),
    **dict.fromkeys(("T", "TA", "TB", "FX", "FY", "FZ"), "N"),
    **dict.fromkeys(("MX", "MY", "MZ"), "N*m"),
    "SUB": "(frac)",
}
#: long spellings of the tension codes
_ALIASES = {"TEN": "T", "TENA": "TA", "TENB": "TB"}
#: quantities defined for a line node and for a point (spec 1.13)
_LINE_QUANTITIES = frozenset(("PX", "PY", "PZ", "VX", "VY", "VZ", "T", "TA", "TB", "FX", "FY", "FZ"))
_POINT_QUANTITIES = frozenset(("PX", "PY", "PZ", "VX", "VY", "VZ", "AX", "AY", "AZ", "T", "FX", "FY", "FZ"))
_ROD_QUANTITIES = frozenset(("PX", "PY", "PZ", "VX", "VY", "VZ", "AX", "AY", "AZ", "RX", "RY", "RVX", "RVY", "RVZ",
                             "RAX", "RAY", "RAZ", "TA", "TB", "FX", "FY", "FZ", "MX", "MY", "MZ", "SUB"))
_ROD_NODE_QUANTITIES = frozenset(("PX", "PY", "PZ", "VX", "VY", "VZ", "FX", "FY", "FZ"))
_BODY_QUANTITIES = frozenset(("PX", "PY", "PZ", "VX", "VY", "VZ", "AX", "AY", "AZ", "RX", "RY", "RZ", "RVX", "RVY",
                              "RVZ", "RAX", "RAY", "RAZ", "T", "FX", "FY", "FZ", "MX", "MY", "MZ"))

_PREFIXES = {"L": "line", "LINE": "line", "P": "point", "POINT": "point", "R": "rod", "ROD": "rod",
             "B": "body", "BODY": "body"}


@dataclass(frozen=True)
class Channel:
    """One column of the main output file.

    Attributes
    ----------
    name : str
        The channel name exactly as typed in the deck (also the column title).
    unit : str
        Unit string of the units row (``m``, ``m/s``, ``m/s^2``, ``N``, ...).
    kind : str
        ``'line'``, ``'point'``, ``'rod'`` or ``'body'``: the object the value is read from.
    index : int
        0-based index of the object.
    quantity : str
        Canonical quantity code: ``PX PY PZ VX VY VZ AX AY AZ FX FY FZ`` (vector components),
        ``T`` (node tension / point net-force magnitude), ``TA``/``TB`` (net-force magnitude on
        line node 0 / node N), or ``ZERO`` for a known code that is not defined for the object.
    node : int or None
        Node index 0..N for line and rod-node channels, None for points, bodies and whole rods.
    """

    name: str
    unit: str
    kind: str
    index: int
    quantity: str
    node: int | None = None


def _model_of(system_or_model):
    return getattr(system_or_model, "model", system_or_model)


def _to_int(piece: str) -> int | None:
    return int(piece) if piece.isascii() and piece.isdigit() else None


def _split_node(rest: str) -> tuple[str | None, str]:
    """``'NAT'`` -> ``('A', 'T')``, ``'NBPX'`` -> ``('B', 'PX')``, ``'TEN'`` -> ``(None, 'TEN')``."""
    if rest[:2] in ("NA", "NB") and _ALIASES.get(rest[2:], rest[2:]) in _QUANTITY_UNITS:
        return rest[1], rest[2:]
    return None, rest


def _interpret(name: str):
    """Syntax of one channel name: ``(kind, number, node, quantity)`` or a reason string.

    ``node`` is an int, ``'A'``, ``'B'`` or None; ``quantity`` is canonical (aliases resolved).
    """
    p = decompose(name)
    head = p[0]
    num = _to_int(p[1]) if len(p) > 1 else None
    if head in ("FAIRTEN", "ANCHTEN"):
        if num is None:
            return "line number missing"
        if len(p) > 2:
            log.warning("output channel %r: trailing text %r ignored (read as %s%d)", name, "".join(p[2:]),
                        head, num)
        return "line", num, ("B" if head == "FAIRTEN" else "A"), ("TB" if head == "FAIRTEN" else "TA")
    kind = _PREFIXES.get(head)
    if kind is None:
        return f"unknown output specifier {head!r}"
    if num is None:
        return f"{kind} number missing"
    node: int | str | None = None
    if len(p) == 3:
        node, q = _split_node(p[2]) if kind in ("line", "rod") else (None, p[2])
    elif len(p) == 5 and p[2] == "N" and kind in ("line", "rod"):
        node, q = _to_int(p[3]), p[4]
        if node is None:
            return "node number missing"
    else:
        return "quantity code missing or not understood"
    q = _ALIASES.get(q, q)
    if q not in _QUANTITY_UNITS:
        return f"invalid quantity specifier {q!r}"
    return kind, num, node, q


def parse_channels(names, system_or_model) -> list[Channel]:
    """Interpret the OUTPUTS channel names of a deck (spec 1.13).

    Parameters
    ----------
    names : iterable of str
        Channel names as typed (case-insensitive), e.g. ``model.outputs``.
    system_or_model : System or Model
        Gives the lines (and their segment counts) and points the names refer to.

    Returns
    -------
    list of Channel
        In the order given, names that cannot be interpreted left out (with a warning).

    Raises
    ------
    moorline.errors.DeckError
        A name refers to a line, point, rod, body or node that does not exist. The message names
        the channel and the deck file (``model.source``).
    """
    model = _model_of(system_or_model)
    source = getattr(model, "source", None)
    n_lines, n_points = len(model.lines), len(model.points)
    out: list[Channel] = []
    for name in names:
        what = _interpret(name)
        if isinstance(what, str):
            log.warning("output channel %r skipped: %s", name, what)
            continue
        kind, num, node, q = what
        count = {"line": n_lines, "point": n_points, "rod": len(model.rods), "body": len(model.bodies)}[kind]
        if not 1 <= num <= count:
            raise DeckError(f"OUTPUTS channel {name!r}: no {kind} {num} (the model has {count} "
                            f"{'bodies' if kind == 'body' and count != 1 else kind + ('' if count == 1 else 's')})",
                            file=source)
        unit = _QUANTITY_UNITS[q]
        if kind in ("line", "rod") and node is not None or kind == "line":
            obj = model.lines[num - 1] if kind == "line" else model.rods[num - 1]
            n_seg = int(obj.N)
            node = {None: 0, "A": 0, "B": n_seg}.get(node, node)
            if not 0 <= node <= n_seg:
                raise DeckError(f"OUTPUTS channel {name!r}: no node {node} on {kind} {num} "
                                f"(nodes 0 to {n_seg})", file=source)
            defined = q in (_LINE_QUANTITIES if kind == "line" else _ROD_NODE_QUANTITIES)
            where = f"{kind} node"
        else:
            node = None
            defined = q in {"point": _POINT_QUANTITIES, "rod": _ROD_QUANTITIES, "body": _BODY_QUANTITIES}[kind]
            where = kind
        if not defined:
            log.warning("output channel %r: %s is not defined for a %s; written as zeros (as MoorDyn does)",
                        name, q, where)
            q = "ZERO"
        out.append(Channel(name, unit, kind, num - 1, q, node))
    return out


_COMPONENT = {"X": 0, "Y": 1, "Z": 2}


def evaluate(channels, system) -> np.ndarray:
    """Current values of channels on a running system.

    Line node ``T``: at an internal node the magnitude of the mean of the two adjacent segment
    forces (tension plus internal damping, ``line.node_tensions()[m]``), at an end node the
    magnitude of the net force on that node. ``TA``/``TB``, ``FairTen``, ``AnchTen``: magnitude of
    the net force on node 0 / node N (``line.end_force``). Point ``T``: magnitude of the net force.

    Parameters
    ----------
    channels : list of Channel
    system : System
        Values are those of its last evaluation (after ``init`` or ``step``).

    Returns
    -------
    ndarray, shape (len(channels),)
        In the channels' units.
    """
    out = np.zeros(len(channels))
    cache: dict[tuple, np.ndarray] = {}

    def get(kind: str, index: int, what: str) -> np.ndarray:
        key = (kind, index, what)
        if key not in cache:
            obj = {"line": system.lines, "point": system.points, "rod": system.rods, "body": system.bodies}[kind][index]
            cache[key] = np.asarray(getattr(obj, what)())
        return cache[key]

    for k, ch in enumerate(channels):
        q = ch.quantity
        if q == "ZERO":
            continue
        if ch.kind == "line":
            forces = get("line", ch.index, "node_forces")
            last = forces.shape[0] - 1
            if q == "TA":
                out[k] = np.linalg.norm(forces[0])
            elif q == "TB":
                out[k] = np.linalg.norm(forces[last])
            elif q == "T":
                if ch.node in (0, last):
                    out[k] = np.linalg.norm(forces[ch.node])
                else:
                    out[k] = get("line", ch.index, "node_tensions")[ch.node]
            else:
                what = {"P": "node_positions", "V": "node_velocities", "F": "node_forces"}[q[0]]
                out[k] = get("line", ch.index, what)[ch.node, _COMPONENT[q[1]]]
        elif ch.kind == "point":
            if q == "T":
                out[k] = np.linalg.norm(get("point", ch.index, "force"))
            else:
                what = {"P": "position", "V": "velocity", "A": "acceleration", "F": "force"}[q[0]]
                out[k] = get("point", ch.index, what)[_COMPONENT[q[1]]]
        elif ch.kind == "rod" and ch.node is not None:
            what = {"P": "node_positions", "V": "node_velocities", "F": "node_forces"}[q[0]]
            out[k] = get("rod", ch.index, what)[ch.node, _COMPONENT[q[1]]]
        else:
            out[k] = _rigid_value(ch, get)
    return out


def _rigid_value(ch, get) -> float:
    """Value of a whole-rod or body channel (angles and rates in degrees)."""
    q = ch.quantity
    kind = ch.kind
    if q == "SUB":
        return float(get("rod", ch.index, "submergence"))
    if q in ("TA", "TB"):
        return float(get("rod", ch.index, "end_tensions")[0 if q == "TA" else 1])
    if q == "T":
        return float(np.linalg.norm(get(kind, ch.index, "force")[:3]))
    if q in ("PX", "PY", "PZ"):
        pos = get("rod", ch.index, "end_positions")[0] if kind == "rod" else get("body", ch.index, "position")
        return float(pos[_COMPONENT[q[1]]])
    if q in ("VX", "VY", "VZ"):
        return float(get(kind, ch.index, "velocity")[_COMPONENT[q[1]]])
    if q in ("AX", "AY", "AZ"):
        return float(get(kind, ch.index, "acceleration")[_COMPONENT[q[1]]])
    if q in ("RX", "RY", "RZ"):
        ang = get("rod", ch.index, "roll_pitch") if kind == "rod" else get("body", ch.index, "angles")
        return math.degrees(float(ang[_COMPONENT[q[1]]]))
    if q in ("RVX", "RVY", "RVZ"):
        return math.degrees(float(get(kind, ch.index, "angular_velocity")[_COMPONENT[q[2]]]))
    if q in ("RAX", "RAY", "RAZ"):
        return math.degrees(float(get(kind, ch.index, "acceleration")[3 + _COMPONENT[q[2]]]))
    # FX FY FZ MX MY MZ
    return float(get(kind, ch.index, "force")[(0 if q[0] == "F" else 3) + _COMPONENT[q[1]]])


# ---------------------------------------------------------------------------------------- per-line files

#: flags that cause a per-line file to be created (``b`` alone does not, as in MoorDyn-C)
LINE_FILE_TRIGGERS = frozenset("pvUDVKctsd")
#: per-line blocks in the fixed order of the file: flag -> (per node?, components, title suffix(es), unit)
_LINE_BLOCKS = (
    ("p", True, ("px", "py", "pz"), "(m)"),
    ("K", True, ("Ku",), "(1/m)"),
    ("v", True, ("vx", "vy", "vz"), "(m/s)"),
    ("U", True, ("Ux", "Uy", "Uz"), "(m/s)"),
    ("D", True, ("Dx", "Dy", "Dz"), "(N)"),
    ("V", True, ("Vx", "Vy", "Vz"), "(N)"),
    ("t", False, ("Te",), "(N)"),
    ("c", False, ("cx", "cy", "cz"), "(N)"),
    ("s", False, ("St",), "(-)"),
    ("d", False, ("dSt",), "(-/s)"),
    ("b", True, ("bx", "by", "bz"), "(N)"),
)


def _line_flags(system_or_model, i: int) -> str:
    flags = _model_of(system_or_model).lines[i].outputs or ""
    return "" if flags.strip() == "-" else flags


def has_line_file(system_or_model, i: int) -> bool:
    """Whether line ``i`` (0-based) gets a ``<base>_Line<i+1>.out`` file.

    True when its output flags contain at least one of ``p v U D V K c t s d`` (flags are
    case-sensitive; ``b`` alone does not create the file).
    """
    return bool(LINE_FILE_TRIGGERS.intersection(_line_flags(system_or_model, i)))


def line_file_columns(system_or_model, i: int) -> tuple[list[str], list[str]]:
    """Column titles and units of the per-line file of line ``i`` (0-based), without the time column.

    Blocks are always in the order p, K, v, U, D, V, t, c, s, d, b whatever the order of the flags
    (spec 2.3): node blocks have 3(N+1) columns (``Node0px Node0py Node0pz Node1px ...``; ``K`` has
    N+1 columns ``Node<i>Ku``), segment blocks N columns (``Seg<j>Te``, ``Seg<j>St``, ``Seg<j>dSt``,
    j = 1..N) or 3N (``Seg<j>cx cy cz``). Units are in parentheses, as MoorDyn writes them in
    per-line files (``(m)``, ``(1/m)``, ``(m/s)``, ``(N)``, ``(-)``, ``(-/s)``).

    Returns
    -------
    titles, units : list of str
        Both empty when the line has no per-line file (see :func:`has_line_file`).
    """
    if not has_line_file(system_or_model, i):
        return [], []
    flags = _line_flags(system_or_model, i)
    n_seg = int(_model_of(system_or_model).lines[i].N)
    titles: list[str] = []
    units: list[str] = []
    for flag, per_node, suffixes, unit in _LINE_BLOCKS:
        if flag not in flags:
            continue
        if per_node:
            titles += [f"Node{n}{s}" for n in range(n_seg + 1) for s in suffixes]
        else:
            titles += [f"Seg{j}{s}" for j in range(1, n_seg + 1) for s in suffixes]
        units += [unit] * ((n_seg + 1 if per_node else n_seg) * len(suffixes))
    return titles, units


def line_file_values(system, i: int) -> np.ndarray:
    """Current values of the per-line file columns of line ``i`` (0-based), in the order of
    :func:`line_file_columns`.

    Contents: ``p`` node positions [m], ``K`` nodal curvature [1/m], ``v`` node velocities [m/s],
    ``U`` water velocity at the nodes [m/s], ``D`` hydrodynamic (drag + fluid inertia) node forces
    [N], ``V`` VIV cross-flow lift [N] -- always zero in this version, which has no VIV model --,
    ``t`` elastic segment tension magnitude, damping excluded [N], ``c`` segment internal damping
    force vectors [N], ``s`` segment strain [-], ``d`` segment strain rate [1/s], ``b`` seabed
    contact plus friction node forces [N].

    Returns
    -------
    ndarray, shape (n_columns,)
        Empty when the line has no per-line file.
    """
    if not has_line_file(system, i):
        return np.zeros(0)
    flags = _line_flags(system, i)
    line = system.lines[i]
    getters = {
        "p": line.node_positions, "K": line.node_curvatures, "v": line.node_velocities,
        "U": line.node_water_velocities, "D": line.node_hydro_forces,
        "V": lambda: np.zeros((line.n_segments + 1, 3)),
        "t": line.segment_elastic_tensions, "c": line.segment_damping_forces, "s": line.segment_strains,
        "d": line.segment_strain_rates, "b": line.node_seabed_forces,
    }
    parts = [np.asarray(getters[flag](), dtype=float).ravel() for flag, *_ in _LINE_BLOCKS if flag in flags]
    return np.concatenate(parts)


# ---------------------------------------------------------------------------------------- rod and body files

#: per-rod blocks in file order: flag -> node-force component index in RodView.node_force_components order
#: (spec 2.4; moorline writes X before Y, as the header says, where MoorDyn-C swaps the two blocks)
_ROD_BLOCKS = (("p", "p"), ("v", "v"), ("f", "f"), ("W", "weight"), ("B", "buoyancy"), ("X", "drag_transverse"),
               ("Y", "drag_axial"), ("A", "inertia_transverse"), ("a", "inertia_axial"), ("P", "dynamic_pressure"),
               ("b", "seabed"))


def _rod_flags(system_or_model, k: int) -> str:
    flags = _model_of(system_or_model).rods[k].outputs or ""
    return "" if flags.strip() == "-" else flags


def has_rod_file(system_or_model, k: int) -> bool:
    """Whether rod ``k`` gets a ``<base>_Rod<k+1>.out`` file: any known rod flag (spec 2.4; moorline
    creates the file for every known flag, where MoorDyn-C needs one of ``p v U D c t s d``)."""
    return any(f in _rod_flags(system_or_model, k) for f, _ in _ROD_BLOCKS)


def rod_file_columns(system_or_model, k: int) -> tuple[list[str], list[str]]:
    """Titles and units of the per-rod file of rod ``k`` (0-based), without the time column."""
    if not has_rod_file(system_or_model, k):
        return [], []
    flags = _rod_flags(system_or_model, k)
    n_nodes = int(_model_of(system_or_model).rods[k].N) + 1
    titles: list[str] = []
    units: list[str] = []
    for flag, _ in _ROD_BLOCKS:
        if flag in flags:
            titles += [f"Node{n}{flag}{c}" for n in range(n_nodes) for c in "xyz"]
            units += [{"p": "(m)", "v": "(m/s)"}.get(flag, "(N)")] * (3 * n_nodes)
    return titles, units


def rod_file_values(system, k: int) -> np.ndarray:
    """Current values of the per-rod file columns of rod ``k``, in the order of :func:`rod_file_columns`."""
    if not has_rod_file(system, k):
        return np.zeros(0)
    rod = system.rods[k]
    flags = _rod_flags(system, k)
    comps = rod.node_force_components()
    parts = []
    for flag, what in _ROD_BLOCKS:
        if flag not in flags:
            continue
        if what == "p":
            parts.append(rod.node_positions().ravel())
        elif what == "v":
            parts.append(rod.node_velocities().ravel())
        elif what == "f":
            parts.append(rod.node_forces().ravel())
        else:
            parts.append(comps[what].ravel())
    return np.concatenate(parts)


def body_file_values(system, i: int) -> np.ndarray:
    """Row of ``<base>_Body<i+1>.out``: reference-point position [m] and roll, pitch, yaw [deg]."""
    b = system.bodies[i]
    return np.concatenate([b.position(), np.degrees(b.angles())])


def _body_text(times, values, write_units: bool, header: bool = True) -> str:
    rows = []
    if header:
        rows.append("Time\tx\ty\tz\troll\tpitch\tyaw\n")
        if write_units:
            rows.append("(s)\t(m)\t(m)\t(m)\t(deg)\t(deg)\t(deg)\n")
    for t, v in zip(np.asarray(times, dtype=float), np.asarray(values, dtype=float).reshape(-1, 6), strict=True):
        rows.append("\t".join([f"{t:.4f}"] + [f"{x:.7e}" for x in v]) + "\n")
    return "".join(rows)


def write_body_out(path, times, values, write_units: bool = True) -> Path:
    """Write a tab-separated per-body file (spec 2.5): ``Time x y z roll pitch yaw``."""
    _write_atomic(Path(path), _body_text(times, values, write_units))
    return Path(path)


# ---------------------------------------------------------------------------------------- writers

TIME_WIDTH = 10
VALUE_WIDTH = 20


def _table_text(titles, units, times, values, write_units: bool, time_unit: str, header: bool = True) -> str:
    times = np.asarray(times, dtype=float).ravel()
    values = np.asarray(values, dtype=float)
    ncol = len(titles)
    if values.size == 0:
        values = values.reshape(times.size, ncol)
    if values.ndim != 2 or values.shape != (times.size, ncol):
        raise ValueError(f"values have shape {values.shape}; expected ({times.size}, {ncol}) "
                         "(one row per time, one column per title)")
    if len(units) != ncol:
        raise ValueError(f"{len(units)} units for {ncol} columns")
    rows = []
    if header:
        rows.append(f"{'Time':>{TIME_WIDTH}}" + "".join(f"{t:>{VALUE_WIDTH}}" for t in titles) + "\n")
    if header and write_units:
        rows.append(f"{time_unit:>{TIME_WIDTH}}" + "".join(f"{u:>{VALUE_WIDTH}}" for u in units) + "\n")
    fmt = f"%{TIME_WIDTH}.4f" + f"%{VALUE_WIDTH}.7e" * ncol + "\n"
    table = np.column_stack([times, values])
    rows.extend(fmt % tuple(r) for r in table.tolist())
    return "".join(rows)


def _write_atomic(path: Path, text: str) -> None:
    """Write ``text`` to a temporary file next to ``path``, then rename it over ``path``.

    The temporary file is created with mode ``'x'`` under a unique hidden name, so it gets the
    usual permissions (umask) rather than the owner-only mode of :func:`tempfile.mkstemp`.
    """
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp")
    try:
        with open(tmp, "x", encoding="utf-8", newline="\n") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def write_table(path, titles, units, times, values, *, write_units: bool = True,
                time_unit: str = "(s)") -> Path:
    """Write a MoorDyn fixed-width output table (atomically).

    Row 1: ``Time`` right-aligned in 10 characters, then each title right-aligned in 20. Row 2 (if
    ``write_units``): ``time_unit`` in 10 characters, then each unit in 20. Then one row per time:
    time ``%10.4f`` [s] and values ``%20.7e``. Every row ends with a newline.

    Parameters
    ----------
    path : path-like
    titles, units : sequence of str
        One per value column (time column excluded).
    times : array_like, shape (n_rows,)
        Output times [s].
    values : array_like, shape (n_rows, n_columns)
    write_units : bool
        MoorDyn's ``WriteUnits`` option.
    time_unit : str
        Units-row entry of the time column.

    Returns
    -------
    Path
        The written file.
    """
    text = _table_text(list(titles), list(units), times, values, bool(write_units), time_unit)
    path = Path(path)
    _write_atomic(path, text)
    return path


def write_main_out(path, channels, times, values, write_units: bool = True) -> Path:
    """Write the main file ``<base>.out``: ``Time`` and one column per channel (spec 2.1).

    Parameters
    ----------
    path : path-like
    channels : list of Channel
        Column titles are the names as typed; the units row has ``(s)`` then the bare units.
    times : array_like, shape (n_rows,)
        [s]
    values : array_like, shape (n_rows, len(channels))
        Channel values, e.g. from repeated :func:`evaluate` calls.
    write_units : bool
        Write the units row (option ``WriteUnits``).

    Returns
    -------
    Path
    """
    return write_table(path, [c.name for c in channels], [c.unit for c in channels], times, values,
                       write_units=write_units)


def write_line_out(path, titles, units, times, values, write_units: bool = True) -> Path:
    """Write a per-line file ``<base>_Line<n>.out`` (spec 2.3).

    Parameters
    ----------
    path : path-like
    titles, units : list of str
        From :func:`line_file_columns`.
    times : array_like, shape (n_rows,)
        [s]
    values : array_like, shape (n_rows, len(titles))
        Rows from :func:`line_file_values`.
    write_units : bool
        Write the units row (option ``WriteUnits``).

    Returns
    -------
    Path
    """
    return write_table(path, titles, units, times, values, write_units=write_units)


def output_due(t: float, dt: float, dt_out: float) -> bool:
    """Whether a row is due after a step of length ``dt`` ending at time ``t`` (spec 2.6).

    With ``dt_out`` = 0 every step writes a row. Otherwise a row is written if a multiple of
    ``dt_out`` lies in (t - dt, t], i.e. if t >= (floor((t - dt) / dt_out) + 1) dt_out; the test is
    made with a tolerance of 1e-9 dt_out so that sums of rounded steps (0.1 + 0.2 ...) behave as
    the exact times. Init uses ``dt`` = 0, so with ``dt_out`` > 0 no t = 0 row is written.

    Parameters
    ----------
    t : float
        Time at the end of the step [s].
    dt : float
        Step length [s] (0 for the row written by init).
    dt_out : float
        Output interval [s] (option ``dtOut``).
    """
    if dt_out <= 0:
        return True
    eps = 1e-9 * dt_out
    return t + eps >= (math.floor((t - dt + eps) / dt_out) + 1) * dt_out


# ---------------------------------------------------------------------------------------- recorder


class OutputRecorder:
    """Collects MoorDyn-style output rows during a run and writes the ``.out`` files.

    Channels (``system.model.outputs``) and per-line column sets are built once, at construction;
    bad channel names raise :class:`~moorline.errors.DeckError` there.

    Parameters
    ----------
    system : System
        An initialised system.
    write_units : bool, optional
        Default: the model's ``WriteUnits`` option.

    Examples
    --------
    >>> rec = OutputRecorder(sys)              # doctest: +SKIP
    >>> rec.record()                           # the t = 0 row after init  # doctest: +SKIP
    >>> for k in range(n):                     # doctest: +SKIP
    ...     sys.step(x, xd, k * dt, dt)
    ...     rec.record_if_due(dt)
    >>> rec.write("out", "mooring")            # mooring.out, mooring_Line1.out, ...  # doctest: +SKIP
    """

    def __init__(self, system, *, write_units: bool | None = None):
        self.system = system
        model = system.model
        self.write_units = bool(model.options.WriteUnits if write_units is None else write_units)
        self.dt_out = float(getattr(model.options, "dtOut", 0.0) or 0.0)
        self.channels = parse_channels(model.outputs, system)
        #: {line index: (titles, units)} for the lines that have a per-line file
        self.line_columns = {i: line_file_columns(system, i) for i in range(len(model.lines))
                             if has_line_file(system, i)}
        self.rod_columns = {k: rod_file_columns(system, k) for k in range(len(model.rods)) if has_rod_file(system, k)}
        self.times: list[float] = []
        self._main: list[np.ndarray] = []
        self._lines: dict[int, list[np.ndarray]] = {i: [] for i in self.line_columns}
        self._rods: dict[int, list[np.ndarray]] = {k: [] for k in self.rod_columns}
        self._bodies: dict[int, list[np.ndarray]] = {i: [] for i in range(len(model.bodies))}

    def record(self) -> None:
        """Append one row with the system's current time and values."""
        self.times.append(float(self.system.t))
        self._main.append(evaluate(self.channels, self.system))
        for i, rows in self._lines.items():
            rows.append(line_file_values(self.system, i))
        for k, rows in self._rods.items():
            rows.append(rod_file_values(self.system, k))
        for i, rows in self._bodies.items():
            rows.append(body_file_values(self.system, i))

    def record_if_due(self, dt: float) -> bool:
        """Record a row if one is due after a step of length ``dt`` [s] (see :func:`output_due`).

        Returns whether a row was recorded.
        """
        if output_due(float(self.system.t), dt, self.dt_out):
            self.record()
            return True
        return False

    @property
    def main_values(self) -> np.ndarray:
        """Recorded channel values, shape (n_rows, n_channels)."""
        return np.array(self._main).reshape(len(self.times), len(self.channels))

    def line_values(self, i: int) -> np.ndarray:
        """Recorded per-line values of line ``i`` (0-based), shape (n_rows, n_columns)."""
        return np.array(self._lines[i]).reshape(len(self.times), len(self.line_columns[i][0]))

    def texts(self, base: str, start: int = 0, stop: int | None = None, *, header: bool = True) -> dict[str, str]:
        """Text of every ``.out`` file: ``{file name: text}`` with the title (and units) rows when
        ``header``, then the recorded rows ``start:stop``; the main file ``<base>.out`` first,
        then ``<base>_Line<n>.out``, ``<base>_Rod<n>.out`` and ``<base>_Body<n>.out``. Appending
        the texts of consecutive row ranges (the first with its header) gives the whole file."""
        rows = slice(start, stop)
        times = self.times[rows]
        n = len(times)
        wu = self.write_units
        out = {f"{base}.out": _table_text([c.name for c in self.channels], [c.unit for c in self.channels], times,
                                          np.array(self._main[rows]).reshape(n, len(self.channels)), wu, "(s)",
                                          header)}
        for i, (titles, units) in self.line_columns.items():
            out[f"{base}_Line{i + 1}.out"] = _table_text(titles, units, times, np.array(self._lines[i][rows]).reshape(
                n, len(titles)), wu, "(s)", header)
        for k, (titles, units) in self.rod_columns.items():
            out[f"{base}_Rod{k + 1}.out"] = _table_text(titles, units, times, np.array(self._rods[k][rows]).reshape(
                n, len(titles)), wu, "(s)", header)
        for i, body_rows in self._bodies.items():
            out[f"{base}_Body{i + 1}.out"] = _body_text(times, np.array(body_rows[rows]).reshape(n, 6), wu, header)
        return out

    def write(self, out_dir, base: str) -> list[Path]:
        """Write ``<base>.out`` and every ``<base>_Line<n>.out`` into ``out_dir``.

        Each file is written to a temporary file in ``out_dir`` and renamed into place, so a file
        with the final name is always complete.

        Returns
        -------
        list of Path
            The files written, main file first.
        """
        out_dir = Path(out_dir)
        out_dir.mkdir(parents=True, exist_ok=True)
        written = []
        for name, text in self.texts(base).items():
            _write_atomic(out_dir / name, text)
            written.append(out_dir / name)
        log.info("wrote %d output file(s) to %s", len(written), out_dir)
        return written

    def __repr__(self) -> str:
        return (f"OutputRecorder({len(self.channels)} channels, {len(self.line_columns)} line files, "
                f"{len(self.times)} rows)")
