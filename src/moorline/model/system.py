"""The :class:`Model`: a complete, validated description of a mooring system.

A Model is what a deck says, as Python objects. It is built by the deck reader or by hand::

    m = Model(env=Environment(depth=200.0))
    m.add_line_type("chain", d=0.15, w=140.0, EA=1.2e9, BA=-0.8, Cd=2.4, Ca=1.0, CdAx=1.15, CaAx=0.5)
    a = m.add_point("fixed", (800.0, 0.0, -200.0))
    f = m.add_point("coupled", (40.0, 0.0, -15.0))
    m.add_line("chain", a, f, L=850.0, N=40)

The runtime object that integrates it is :class:`moorline.System`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .floating import FloatingBody, HydroBodies, Joint, MorisonStrip
from .types import (
    BODY_KIND_WORDS,
    ELASTIC,
    POINT_KIND_WORDS,
    SYROPE,
    VISCO_CONSTANT,
    VISCO_MEAN,
    Attachment,
    Body,
    BodyKind,
    Curve,
    Environment,
    Failure,
    Line,
    LineType,
    ModelError,
    Options,
    Point,
    PointKind,
    Rod,
    RodKind,
    RodType,
    SyropeCurve,
)


@dataclass
class Model:
    """Line types, points and lines, with the environment, options and output channels."""

    line_types: dict[str, LineType] = field(default_factory=dict)
    rod_types: dict[str, RodType] = field(default_factory=dict)
    rods: list[Rod] = field(default_factory=list)
    bodies: list[Body] = field(default_factory=list)
    points: list[Point] = field(default_factory=list)
    lines: list[Line] = field(default_factory=list)
    env: Environment = field(default_factory=Environment)
    options: Options = field(default_factory=Options)
    #: main-file output channel names (the OUTPUTS section), as typed
    outputs: list[str] = field(default_factory=list)
    #: deck file this model was read from, if any
    source: Path | None = None
    #: floating bodies (:mod:`moorline.model.floating`): per-body settings, coefficient sets, joints
    floating: list[FloatingBody] = field(default_factory=list)
    hydro: list[HydroBodies] = field(default_factory=list)
    joints: list[Joint] = field(default_factory=list)
    #: line failures (MoorDyn's FAILURE section, :class:`Failure`)
    failures: list[Failure] = field(default_factory=list)

    # ------------------------------------------------------------------ builders
    def add_line_type(self, name: str, *, d: float, w: float, EA, BA=0.0, EI=0.0, Cd=0.0, Ca=0.0,
                      CdAx=0.0, CaAx=0.0, Cl=0.0, dF=0.0, cF=0.0, EA_D=0.0, EA_D_Lm=0.0, BA_D=0.0,
                      syrope: SyropeCurve | None = None, elastic: int | None = None) -> LineType:
        """Add (or replace) a line type; see :class:`LineType` for the arguments.

        The axial model follows from the arguments unless ``elastic`` is given: Syrope when
        ``syrope`` is given (``EA`` is then ignored: the original working curve is the stiffness),
        viscoelastic with a mean-load dependent dynamic stiffness when ``EA_D_Lm`` is non-zero,
        with a constant one when ``EA_D`` is non-zero, else elastic."""
        if elastic is None:
            elastic = VISCO_MEAN if EA_D_Lm else (VISCO_CONSTANT if EA_D else ELASTIC)
            if syrope is not None:
                elastic = SYROPE
        if syrope is not None:
            EA = syrope.owc
        lt = LineType(name, float(d), float(w), _num_or_curve(EA), _num_or_curve(BA), _num_or_curve(EI),
                      float(Cd), float(Ca), float(CdAx), float(CaAx), float(Cl), float(dF), float(cF), int(elastic),
                      float(EA_D), float(EA_D_Lm), float(BA_D), syrope)
        self.line_types[name] = lt
        return lt

    def add_rod_type(self, name: str, *, d: float, w: float, Cd=0.0, Ca=0.0, CdEnd=0.0, CaEnd=0.0) -> RodType:
        """Add (or replace) a rod type; see :class:`RodType`."""
        rt = RodType(name, float(d), float(w), float(Cd), float(Ca), float(CdEnd), float(CaEnd))
        self.rod_types[name] = rt
        return rt

    def add_body(self, kind, r, angles=(0.0, 0.0, 0.0), *, m=0.0, rCG=(0.0, 0.0, 0.0), I=(0.0, 0.0, 0.0),  # noqa: E741
                 V=0.0, CdA=(0.0,) * 6, Ca=(0.0, 0.0, 0.0)) -> int:
        """Add a 6-DOF body and return its index (for ``add_point(..., body=)`` and ``add_rod``).

        ``kind`` is a :class:`BodyKind` or a word: fixed, coupled, coupledpinned, free. See
        :class:`Body` for the other arguments (``angles`` in degrees).
        """
        if isinstance(kind, str):
            try:
                kind = BODY_KIND_WORDS[kind.upper()]
            except KeyError:
                raise ModelError(f"unknown body kind {kind!r}; expected one of "
                                 f"{sorted(w.lower() for w in BODY_KIND_WORDS)}") from None
        self.bodies.append(Body(BodyKind(kind), r, angles, float(m), rCG, I, float(V), CdA, Ca))
        return len(self.bodies) - 1

    def add_rod(self, rod_type: str, kind, rA, rB, *, N: int, outputs: str = "",
                body: int | None = None) -> tuple[Attachment, Attachment]:
        """Add a rod and return the attachments of its ends A and B (lines attached to a rod end
        with bending stiffness are clamped to the rod's direction).

        ``kind`` is a :class:`RodKind` or a word: fixed, pinned, coupled, coupledpinned, free,
        body, bodypinned. For rods on a body (``body`` = its index) the end coordinates are in body
        axes relative to its reference point.
        """
        if isinstance(kind, str):
            words = {"fixed": RodKind.FIXED, "anchor": RodKind.FIXED, "pinned": RodKind.PINNED,
                     "coupled": RodKind.COUPLED, "vessel": RodKind.COUPLED, "coupledpinned": RodKind.COUPLED_PINNED,
                     "free": RodKind.FREE, "body": RodKind.BODY, "bodypinned": RodKind.BODY_PINNED}
            try:
                kind = words[kind.lower()]
            except KeyError:
                raise ModelError(f"unknown rod kind {kind!r}; expected one of {sorted(words)}") from None
        self.rods.append(Rod(rod_type, RodKind(kind), rA, rB, int(N), outputs, body))
        k = len(self.rods) - 1
        return Attachment("rod", k, "A"), Attachment("rod", k, "B")

    def add_point(self, kind, r, *, m=0.0, V=0.0, CdA=0.0, Ca=0.0, F_ext=(0.0, 0.0, 0.0),
                  body: int | None = None) -> Attachment:
        """Add a point and return the :class:`Attachment` that lines use to refer to it.

        ``kind`` is a :class:`PointKind` or one of the words fixed/anchor, coupled/vessel/fairlead,
        free/connect, body (then ``body`` is the body's index and ``r`` is in body axes).
        """
        if isinstance(kind, str):
            if kind.upper() == "BODY":
                kind = PointKind.BODY
            else:
                try:
                    kind = POINT_KIND_WORDS[kind.upper()]
                except KeyError:
                    words = sorted(w.lower() for w in POINT_KIND_WORDS)
                    raise ModelError(f"unknown point kind {kind!r}; expected one of {words} or body") from None
        self.points.append(Point(PointKind(kind), r, float(m), float(V), float(CdA), float(Ca), F_ext, body))
        return Attachment("point", len(self.points) - 1)

    def add_line(self, line_type: str, end_a: Attachment, end_b: Attachment, *, L: float, N: int,
                 outputs: str = "") -> Line:
        """Add a line from ``end_a`` (node 0) to ``end_b`` (node N)."""
        line = Line(line_type, end_a, end_b, float(L), int(N), outputs)
        self.lines.append(line)
        return line

    def add_failure(self, attachment: Attachment, lines, *, time: float = math.inf,
                    tension: float = math.inf) -> Failure:
        """Let ``lines`` (0-based indices) go of ``attachment`` at ``time`` [s] or once the load
        they carry there reaches ``tension`` [N] (see :class:`Failure`)."""
        f = Failure(attachment, [int(i) for i in np.atleast_1d(lines)], float(time), float(tension))
        self.failures.append(f)
        return f

    def add_hydro(self, bodies, coefficients, **options) -> HydroBodies:
        """Make deck bodies ``bodies`` (0-based indices, in the order of the coefficient set's
        bodies) float with the potential-flow ``coefficients`` (a Dataset, a WAMIT stem or a
        Capytaine NetCDF file); see :class:`~moorline.model.floating.HydroBodies` for the options.
        Bodies without a :class:`~moorline.model.floating.FloatingBody` entry get a default one."""
        h = HydroBodies(list(np.atleast_1d(bodies)), coefficients, **options)
        self.hydro.append(h)
        for b in h.bodies:
            if self.floating_body(b) is None:
                self.floating.append(FloatingBody(b))
        return h

    def add_floating(self, body: int, **settings) -> FloatingBody:
        """Set (or replace) the extra loads of floating body ``body`` (see
        :class:`~moorline.model.floating.FloatingBody`)."""
        fb = FloatingBody(body, **settings)
        self.floating = [f for f in self.floating if f.body != fb.body] + [fb]
        return fb

    def add_joint(self, child: int, parent: int | None = None, **options) -> Joint:
        """A prismatic joint (see :class:`~moorline.model.floating.Joint`)."""
        j = Joint(child, parent, **options)
        self.joints.append(j)
        return j

    def floating_body(self, body: int) -> FloatingBody | None:
        """The floating-body settings of deck body ``body``, or None if it does not float."""
        return next((f for f in self.floating if f.body == body), None)

    # ------------------------------------------------------------------ queries
    def end_position(self, att: Attachment) -> np.ndarray:
        """Initial (deck-pose) global position of an attachment [m]."""
        if att.kind == "point":
            return self.point_position(att.index)
        rA, rB = self.rod_ends(att.index)
        return rA if att.end == "A" else rB

    def point_position(self, i: int) -> np.ndarray:
        """Deck-pose global position of point ``i`` [m]."""
        p = self.points[i]
        if p.kind == PointKind.BODY:
            return self.bodies[p.body].to_global(p.r)
        return p.r.copy()

    def rod_ends(self, k: int) -> tuple[np.ndarray, np.ndarray]:
        """Deck-pose global positions of the ends A and B of rod ``k`` [m]."""
        rod = self.rods[k]
        rB = rod.rB if rod.N > 0 else rod.rA  # a zero-length rod has both ends at end A
        if rod.kind in (RodKind.BODY, RodKind.BODY_PINNED):
            b = self.bodies[rod.body]
            return b.to_global(rod.rA), b.to_global(rB)
        return rod.rA.copy(), np.array(rB, dtype=float)

    @property
    def coupled_points(self) -> list[int]:
        """Indices of coupled points, in point order."""
        return [i for i, p in enumerate(self.points) if p.kind == PointKind.COUPLED]

    @property
    def coupled_bodies(self) -> list[int]:
        return [i for i, b in enumerate(self.bodies) if b.kind in (BodyKind.COUPLED, BodyKind.COUPLED_PINNED)]

    @property
    def coupled_rods(self) -> list[int]:
        return [i for i, r in enumerate(self.rods) if r.kind in (RodKind.COUPLED, RodKind.COUPLED_PINNED)]

    @property
    def n_coupled_dof(self) -> int:
        """Coupled bodies and rods take 6 DOF (x, y, z, roll, pitch, yaw), their pinned variants
        3 (x, y, z), coupled points 3; in the order bodies, rods, points (MoorDyn's order)."""
        n = sum(6 if self.bodies[i].kind == BodyKind.COUPLED else 3 for i in self.coupled_bodies)
        n += sum(6 if self.rods[i].kind == RodKind.COUPLED else 3 for i in self.coupled_rods)
        return n + 3 * len(self.coupled_points)

    # ------------------------------------------------------------------ checks
    def validate(self) -> None:
        """Raise :class:`ModelError` naming the first inconsistency found."""
        if not (self.lines or self.rods or self.bodies):
            raise ModelError("the model has no lines, rods or bodies")
        for name, lt in self.line_types.items():
            if lt.d <= 0:
                raise ModelError(f"line type {name!r}: diameter must be > 0, got {lt.d}")
            if lt.w <= 0:
                raise ModelError(f"line type {name!r}: mass per length must be > 0, got {lt.w}")
            if lt.EA_ref <= 0:
                raise ModelError(f"line type {name!r}: EA must be > 0")
            for c in ("Cd", "Ca", "CdAx", "CaAx", "Cl", "dF", "cF"):
                if getattr(lt, c) < 0:
                    raise ModelError(f"line type {name!r}: {c} must be >= 0, got {getattr(lt, c)}")
            _check_axial_model(name, lt)
        for k, ln in enumerate(self.lines, 1):
            if ln.line_type not in self.line_types:
                raise ModelError(f"line {k}: unknown line type {ln.line_type!r}")
            if ln.N < 1:
                raise ModelError(f"line {k}: needs at least one segment, got {ln.N}")
            if ln.L == 0:
                raise ModelError(f"line {k}: unstretched length must not be zero")
            for end, att in (("A", ln.end_a), ("B", ln.end_b)):
                if att.kind == "point" and not 0 <= att.index < len(self.points):
                    raise ModelError(f"line {k} end {end}: no point {att.index + 1}")
                if att.kind == "rod" and (not 0 <= att.index < len(self.rods) or att.end not in ("A", "B")):
                    raise ModelError(f"line {k} end {end}: no rod end {att}")
                if att.kind not in ("point", "rod"):
                    raise ModelError(f"line {k} end {end}: unknown attachment {att}")
            if ln.end_a == ln.end_b:
                raise ModelError(f"line {k}: both ends attached to {ln.end_a}")
            lt = self.line_types[ln.line_type]
            if lt.elastic == SYROPE:
                if ln.syrope_ic is None:
                    raise ModelError(f"line {k}: line type {ln.line_type!r} uses the Syrope model, so the line needs "
                                     "its initial Tmax0 and Tmean0 (a SYROPE IC row)")
                tmax, tmean = ln.syrope_ic
                owc = lt.syrope.owc
                if not owc.y[0] <= tmax <= owc.y[-1]:
                    raise ModelError(f"line {k}: Syrope Tmax0 = {tmax:g} N is outside the original working curve's "
                                     f"tension range [{owc.y[0]:g}, {owc.y[-1]:g}] N")
                if not 0.0 <= tmean <= tmax:
                    raise ModelError(f"line {k}: Syrope Tmean0 = {tmean:g} N must lie in [0, Tmax0 = {tmax:g}] N")
        for k, rod in enumerate(self.rods, 1):
            if rod.rod_type not in self.rod_types:
                raise ModelError(f"rod {k}: unknown rod type {rod.rod_type!r}")
            on_body = rod.kind in (RodKind.BODY, RodKind.BODY_PINNED)
            if on_body and (rod.body is None or not 0 <= rod.body < len(self.bodies)):
                raise ModelError(f"rod {k}: attached to body {None if rod.body is None else rod.body + 1}, "
                                 f"which does not exist ({len(self.bodies)} bodies)")
            if rod.N < 0:
                raise ModelError(f"rod {k}: number of segments must be >= 0, got {rod.N}")
            if rod.N > 0 and rod.length == 0:
                raise ModelError(f"rod {k}: ends A and B coincide but NumSegs = {rod.N}")
        for name, rt in self.rod_types.items():
            if rt.d <= 0 or rt.w < 0:
                raise ModelError(f"rod type {name!r}: diameter must be > 0 and mass per length >= 0")
        attached = {a.index for ln in self.lines for a in (ln.end_a, ln.end_b) if a.kind == "point"}
        for i, p in enumerate(self.points):
            if p.kind == PointKind.BODY and (p.body is None or not 0 <= p.body < len(self.bodies)):
                raise ModelError(f"point {i + 1}: attached to body {None if p.body is None else p.body + 1}, "
                                 f"which does not exist ({len(self.bodies)} bodies)")
            if p.kind == PointKind.FREE and i not in attached and p.m + self.env.rho * p.Ca * p.V <= 0:
                raise ModelError(f"point {i + 1}: a free point with no mass and no lines cannot move")
            if p.m < 0 or p.V < 0 or p.CdA < 0 or p.Ca < 0:
                raise ModelError(f"point {i + 1}: mass, volume, CdA and Ca must be >= 0")
        for i, b in enumerate(self.bodies, 1):
            if b.m < 0 or b.V < 0 or np.any(b.I < 0) or np.any(b.CdA < 0) or np.any(b.Ca < 0):
                raise ModelError(f"body {i}: mass, inertia, volume, CdA and Ca must be >= 0")
        self._check_free_rigid()
        self._check_floating()
        for k, f in enumerate(self.failures, 1):
            check_failure(self, f, f"failure {k}")
        if not (self.env.rho >= 0 and self.env.g >= 0):  # also refuses NaN
            raise ModelError(f"rho and g must be >= 0 (0: vacuum, weightless), got rho = {self.env.rho}, "
                             f"g = {self.env.g}")
        if self.env.waves is not None and self.env.g <= 0:
            raise ModelError("waves need gravity: g must be > 0 when waves are given")
        if self.env.depth < 0:
            raise ModelError(f"water depth must be >= 0, got {self.env.depth}")
        from .types import CONTACT_MODES, FRICTION_MODELS

        if self.env.contact not in CONTACT_MODES:
            raise ModelError(f"seabed contact must be one of {CONTACT_MODES}, got {self.env.contact!r}")
        if self.env.friction not in FRICTION_MODELS:
            raise ModelError(f"seabed friction model must be one of {FRICTION_MODELS}, got {self.env.friction!r}")
        e = self.env
        for name in ("kBot", "cBot", "mu", "fric_damp", "mu_kT", "mu_kA", "cv"):
            if getattr(e, name) < 0:
                raise ModelError(f"{name} must be >= 0, got {getattr(e, name)}")
        for name in ("stat_dyn", "mc"):
            if getattr(e, name) <= 0:
                raise ModelError(f"{name} must be > 0, got {getattr(e, name)}")
        if e.kShear is not None and e.kShear <= 0:
            raise ModelError(f"kShear must be > 0, got {e.kShear}")

    def _check_floating(self) -> None:
        """Floating bodies are free deck bodies, each in exactly one coefficient set, whose deck
        volume and added mass are zero (the potential-flow model carries buoyancy and added mass);
        joints link floating bodies, one joint per child, children not parents."""
        nb = len(self.bodies)
        in_set: dict[int, int] = {}
        for k, h in enumerate(self.hydro):
            for b in h.bodies:
                if not 0 <= b < nb:
                    raise ModelError(f"hydrodynamic body set {k + 1}: no body {b + 1} ({nb} bodies)")
                if b in in_set:
                    raise ModelError(f"body {b + 1} is in two hydrodynamic body sets ({in_set[b] + 1} and {k + 1})")
                in_set[b] = k
        seen = set()
        for fb in self.floating:
            b = fb.body
            if not 0 <= b < nb:
                raise ModelError(f"floating body: no body {b + 1} ({nb} bodies)")
            if b in seen:
                raise ModelError(f"body {b + 1} has two floating-body entries")
            seen.add(b)
            if b not in in_set:
                raise ModelError(f"body {b + 1} floats but no hydrodynamic coefficients name it (add_hydro)")
            body = self.bodies[b]
            if body.kind != BodyKind.FREE:
                raise ModelError(f"body {b + 1} floats, so it must be a free body, not {body.kind.name.lower()}")
            if body.V != 0.0 or np.any(body.Ca != 0.0):
                raise ModelError(f"body {b + 1} floats: its deck volume and added-mass coefficients must be 0 "
                                 f"(got V = {body.V}, Ca = {body.Ca.tolist()}); the potential-flow model gives "
                                 "buoyancy and added mass, they would count twice")
            for k, s in enumerate(fb.morison):
                if not isinstance(s, MorisonStrip):
                    raise ModelError(f"body {b + 1} Morison strip {k + 1}: expected a MorisonStrip")
        missing = sorted(set(in_set) - seen)
        if missing:
            raise ModelError(f"bodies {[b + 1 for b in missing]} have coefficients but no floating-body entry")
        children = {}
        for j in self.joints:
            for role, b in (("child", j.child), ("parent", j.parent)):
                if b is not None and b not in seen:
                    raise ModelError(f"joint {role} body {b + 1} must be a floating body")
            if j.child in children:
                raise ModelError(f"body {j.child + 1} is the child of two joints")
            children[j.child] = j
        for j in self.joints:
            if j.parent is not None and j.parent in children:
                raise ModelError(f"body {j.parent + 1} is both a joint's child and a parent: chains of joints are "
                                 "not supported")

    def _check_free_rigid(self) -> None:
        """A free body or rod must have some mass to move."""
        rho = self.env.rho
        floating = {f.body for f in self.floating}
        for i, b in enumerate(self.bodies):
            if b.kind != BodyKind.FREE or i in floating:  # a floating body has its added mass
                continue
            has = b.m + rho * float(np.max(b.Ca)) * b.V > 0 or np.min(b.I) > 0
            kids = any(p.kind == PointKind.BODY and p.body == i for p in self.points) or \
                any(r.body == i and r.kind in (RodKind.BODY, RodKind.BODY_PINNED) for r in self.rods)
            if not has and not kids:
                raise ModelError(f"body {i + 1}: a free body with no mass, inertia, added mass or attached "
                                 "rods and points cannot move")
        for k, rod in enumerate(self.rods, 1):
            if rod.kind == RodKind.FREE and rod.N > 0 and self.rod_types[rod.rod_type].w <= 0 and \
                    self.rod_types[rod.rod_type].Ca <= 0:
                raise ModelError(f"rod {k}: a free rod with no mass and no added mass cannot move")


def _check_axial_model(name: str, lt: LineType) -> None:
    """The viscoelastic and Syrope parameters of line type ``name`` (spec 3.4)."""
    if lt.elastic not in (ELASTIC, VISCO_CONSTANT, VISCO_MEAN, SYROPE):
        raise ModelError(f"line type {name!r}: unknown axial model {lt.elastic} (expected 1 to 4)")
    if lt.elastic == ELASTIC:
        return
    what = {VISCO_CONSTANT: "viscoelastic (EA_s|EA_d)", VISCO_MEAN: "viscoelastic (EA_s|EA_Dc|EA_D_Lm)",
            SYROPE: "Syrope"}[lt.elastic]
    if isinstance(lt.BA, Curve):
        raise ModelError(f"line type {name!r}: the {what} model needs BA_s as a number (or -zeta), not a curve")
    if not lt.BA_D >= 0:
        raise ModelError(f"line type {name!r}: BA_d must be >= 0 (the dynamic damper takes no ratio), got {lt.BA_D}")
    if lt.BA == 0.0 and lt.BA_D == 0.0:
        raise ModelError(f"line type {name!r}: the {what} model needs BA_s + BA_d > 0 (its static-branch stretch "
                         "rate divides by it)")
    if lt.elastic == VISCO_CONSTANT:
        if not lt.EA_D > 0 or lt.EA_D == lt.EA_ref:
            raise ModelError(f"line type {name!r}: the dynamic stiffness EA_d must be > 0 and differ from the static "
                             f"EA_s = {lt.EA_ref:g} N, got {lt.EA_D:g} N")
        return
    if not lt.EA_D > 0:
        raise ModelError(f"line type {name!r}: the {what} model needs EA_Dc > 0, got {lt.EA_D:g} N")
    if lt.elastic == VISCO_MEAN:
        if lt.EA_D_Lm < 0:
            raise ModelError(f"line type {name!r}: EA_D_Lm must be >= 0, got {lt.EA_D_Lm}")
        return
    if lt.syrope is None:
        raise ModelError(f"line type {name!r}: the Syrope model needs its settings (SYROPE:<file>)")
    if not lt.EA_D_Lm > 0:
        raise ModelError(f"line type {name!r}: the Syrope model needs EA_D_Lm (beta) > 0, got {lt.EA_D_Lm}")
    lt.syrope.check()
    owc = lt.syrope.owc
    z = owc.x - np.log1p(lt.EA_D_Lm * owc.y / lt.EA_D) / lt.EA_D_Lm
    if np.any(np.diff(z) <= 0) or np.any(np.diff(owc.y) <= 0):
        raise ModelError(f"line type {name!r}: the Syrope original working curve must have increasing tensions and "
                         "increasing slow strains x - ln(1 + beta y / alpha) / beta (MoorDyn refuses it too)")


def _num_or_curve(v):
    if isinstance(v, Curve):
        return v
    if isinstance(v, tuple) and len(v) == 2:
        return Curve(*v)
    return float(v)


def check_failure(model: Model, f: Failure, what: str) -> None:
    """Raise :class:`ModelError` unless every line of failure ``f`` has an end on its attachment."""
    att = f.attachment
    if att.kind == "point" and not 0 <= att.index < len(model.points):
        raise ModelError(f"{what}: there is no point {att.index + 1} ({len(model.points)} points)")
    if att.kind == "rod" and not 0 <= att.index < len(model.rods):
        raise ModelError(f"{what}: there is no rod {att.index + 1} ({len(model.rods)} rods)")
    if not f.lines:
        raise ModelError(f"{what}: no lines listed")
    for li in f.lines:
        if not 0 <= li < len(model.lines):
            raise ModelError(f"{what}: there is no line {li + 1} ({len(model.lines)} lines)")
        ln = model.lines[li]
        if att not in (ln.end_a, ln.end_b):
            raise ModelError(f"{what}: line {li + 1} is not attached to {att} (its ends: {ln.end_a}, {ln.end_b})")
    if not (f.time > 0 and f.tension > 0):  # also refuses NaN
        raise ModelError(f"{what}: time and tension must be > 0 (inf for none), got {f.time} and {f.tension}")
