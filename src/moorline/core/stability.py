"""Time-step choice and the stability estimate (spec 5.4).

MoorDyn picks ``dtM`` from the deck, or ``CFL`` times the smallest segment period
``2 pi l sqrt(w/EA)``. It checks nothing else. moorline also estimates the fastest modes an
explicit scheme must resolve (axial segment modes with the stiffest tangent EA, seabed contact
damping, over-damped internal damping, light points between stiff lines) and reports the one that
governs, with the largest stable ``dtM`` for the chosen scheme.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..model import ELASTIC, SYROPE, VISCO_CONSTANT, Model
from .integrate import STABLE_OMEGA_DT, Scheme
from .layout import P_FREE, Layout

#: largest stable omega*dt for an UNDAMPED oscillation: RK4 is stable to 2.83; RK2 amplifies it by
#: about (omega dt)^4 / 8 per step (spec 5.4), kept below 1e-6 per step; Euler always amplifies it
UNDAMPED_OMEGA_DT = {Scheme.EULER: 0.0, Scheme.RK2: (8e-6) ** 0.25, Scheme.RK4: 2.8, Scheme.IMPLICIT: 1.0,
                     Scheme.GENALPHA: math.inf, Scheme.HEUN: (8e-6) ** 0.25, Scheme.AB: 0.0, Scheme.LEULER: 0.0,
                     Scheme.NEWMARK: 1.0, Scheme.WILSON: 1.0}


@dataclass
class Mode:
    """A fast mode: where it is, what it is, its rate [rad/s] (or decay rate [1/s]), and whether
    anything damps it (bending modes have no damping in the lumped-mass formulation)."""

    where: str
    kind: str
    rate: float
    damped: bool = True

    def dt_limit(self, scheme: Scheme) -> float:
        limit = STABLE_OMEGA_DT[scheme] if self.damped else UNDAMPED_OMEGA_DT[scheme]
        if self.rate <= 0:
            return math.inf
        return limit / self.rate if limit > 0 else 0.0


def segment_period(model: Model, layout: Layout, li: int) -> float:
    """MoorDyn's segment period 2 pi l sqrt(w / EA_ref) of line ``li`` [s]."""
    lt = model.line_types[model.lines[li].line_type]
    l0 = layout.line_L[li] / layout.line_N[li]
    return 2.0 * math.pi * l0 * math.sqrt(lt.w / lt.EA_ref)


def choose_dtM(model: Model, layout: Layout) -> float:
    """``dtM`` from the options, or CFL times the smallest segment period (MoorDyn's rule)."""
    if model.options.dtM is not None and model.options.dtM > 0:
        return float(model.options.dtM)
    if not model.lines:
        return 1e-3  # rods and bodies only: no segment period to scale; MoorDyn's default dtM
    tmin = min(segment_period(model, layout, li) for li in range(len(model.lines)))
    return float(model.options.CFL) * tmin


def fast_modes(model: Model, layout: Layout, on_seabed: np.ndarray | None = None) -> list[Mode]:
    """Every fast mode the explicit schemes must resolve.

    Parameters
    ----------
    on_seabed : bool array (n_lines,), optional
        Lines with at least one node in seabed contact (seabed modes are included for these;
        all lines with an end at or below the seabed when not given).
    """
    modes: list[Mode] = []
    E = layout.env
    L = layout.lines
    for li, ln in enumerate(model.lines):
        lt = model.line_types[ln.line_type]
        l0 = layout.line_L[li] / layout.line_N[li]
        name = f"line {li + 1}"
        EA = lt.EA_max
        BA = float(L.seg_BA[L.seg_ptr[li]])
        if lt.elastic != ELASTIC:
            EA, BA, relax = _viscoelastic_rates(model, ln, lt, BA)
            modes.append(Mode(name, "viscoelastic stretch relaxation", relax))
        modes.append(Mode(name, "axial segment mode", 2.0 / l0 * math.sqrt(EA / lt.w)))
        if lt.has_bending:
            modes.append(Mode(name, "highest bending mode (undamped)", 4.0 / l0**2 * math.sqrt(lt.EI_max / lt.w),
                              damped=False))
        if BA > 0:
            zeta = BA / (l0 * math.sqrt(EA * lt.w))
            if zeta > 1.0:
                modes.append(Mode(name, f"over-damped internal damping (zeta {zeta:.3g})",
                                  4.0 * BA / (lt.w * l0 * l0)))
        touches = bool(on_seabed[li]) if on_seabed is not None else None
        if touches is None:
            ends = [model.end_position(ln.end_a), model.end_position(ln.end_b)]
            touches = any(r[2] <= _seabed_height(model, E.depth, r) * (1.0 - 1e-5)
                          for r in ends)
        if touches:
            modes.append(Mode(name, "seabed contact damping", E.cBot * lt.d / lt.w))
            modes.append(Mode(name, "seabed contact stiffness", math.sqrt(E.kBot * lt.d / lt.w)))
            if model.env.friction == "stickslip":
                modes.append(Mode(name, "stick-slip friction spring", math.sqrt(E.kshear * lt.d / lt.w)))
            elif max(E.muT, E.muA) > 0:
                # the creep branch of the saturated models is a damper mu cv on the node mass w l
                modes.append(Mode(name, "seabed friction creep damping", max(E.muT, E.muA) * E.cv / (lt.w * l0)))
    # points between stiff lines: axial stiffness of the attached end segments on the point mass
    P = layout.points
    for p, pt in enumerate(model.points):
        if P.kind[p] != P_FREE:
            continue
        k, m_ends = _attached_ends(model, layout, "point", p)
        m = pt.m + E.rho * pt.Ca * pt.V + m_ends
        if k > 0 and m > 0:
            modes.append(Mode(f"point {p + 1}", "point on its lines", math.sqrt(k / m)))
    modes += _rigid_modes(model, layout)
    return modes


def _viscoelastic_rates(model: Model, line, lt, BAs: float) -> tuple[float, float, float]:
    """(axial stiffness [N] and damping [N s] the nodes of a viscoelastic segment feel at once,
    relaxation rate of its stretch state [1/s]).

    The tension EA_1 s / l acts through the state s, but its damper passes the instant part
    BA_s (EA_d dl + BA_d ldot) / ((BA_s + BA_d) l): a stiffness EA_d BA_s / (BA_s + BA_d) and the
    two dampers in series. The state relaxes at the rate (EA_d + EA_1) / (BA_s + BA_d).
    EA_d is estimated at the Syrope line's Tmax0, or at 1 % strain for the mean-load model."""
    if lt.elastic == VISCO_CONSTANT:
        ea_d = lt.EA_D
    elif lt.elastic == SYROPE:
        ea_d = lt.EA_D + lt.EA_D_Lm * (line.syrope_ic[0] if line.syrope_ic else 0.0)
    else:
        ea_d = lt.EA_D + lt.EA_D_Lm * 0.01 * lt.EA_ref
    BAd = lt.BA_D
    den = BAs + BAd
    ea_s = lt.EA_ref
    ea_1 = ea_d * ea_s / (ea_d - ea_s) if ea_d != ea_s else math.inf
    EA = max(lt.EA_max, ea_d * BAs / den) if den > 0 else lt.EA_max
    BA = BAs * BAd / den if den > 0 else 0.0
    relax = abs(ea_d + ea_1) / den if den > 0 else math.inf
    return EA, BA, relax


def _seabed_height(model: Model, depth: float, r) -> float:
    """Seabed height [m] below the horizontal position of ``r``."""
    bathy = model.env.bathymetry
    return bathy.height(r[0], r[1]) if bathy is not None else -depth


def _attached_ends(model: Model, layout: Layout, kind: str, index: int) -> tuple[float, float]:
    """Axial stiffness EA_max / l [N/m] and half-segment mass [kg] of the line end segments
    attached to the point or rod ``index`` (``kind`` 'point' or 'rod')."""
    stiff = mass = 0.0
    for li, ln in enumerate(model.lines):
        lt = model.line_types[ln.line_type]
        l0 = layout.line_L[li] / layout.line_N[li]
        for att in (ln.end_a, ln.end_b):
            if att.kind == kind and att.index == index:
                stiff += lt.EA_max / l0
                mass += 0.5 * lt.w * l0
    return stiff, mass


def _rigid_modes(model: Model, layout: Layout) -> list[Mode]:
    """Free rods (translation on the axial stiffness of their lines' end segments, and seabed
    contact of their nodes)."""
    from ..model import RodKind

    E = layout.env
    modes = []
    for k, rod in enumerate(model.rods):
        if rod.kind != RodKind.FREE:
            continue
        rt = model.rod_types[rod.rod_type]
        stiff, m_ends = _attached_ends(model, layout, "rod", k)
        m = rt.w * rod.length + E.rho * rt.Ca * 0.25 * math.pi * rt.d**2 * rod.length + m_ends
        if stiff > 0 and m > 0:
            modes.append(Mode(f"rod {k + 1}", "rod on its lines", math.sqrt(stiff / m)))
        rA, rB = model.rod_ends(k)
        zb = max(_seabed_height(model, E.depth, r) for r in (rA, rB))
        near_seabed = min(rA[2], rB[2]) - zb <= rod.length + rt.d  # within reach of the seabed
        if rod.N > 0 and rt.w > 0 and near_seabed:
            modes.append(Mode(f"rod {k + 1}", "rod seabed contact stiffness", math.sqrt(E.kBot * rt.d / rt.w)))
            modes.append(Mode(f"rod {k + 1}", "rod seabed contact damping", E.cBot * rt.d / rt.w))
    return modes


def stability_report(model: Model, layout: Layout, dtM: float, scheme: Scheme,
                     on_seabed: np.ndarray | None = None, label: str | None = None) -> tuple[Mode, float, str]:
    """The governing mode, the largest stable dtM [s] for ``scheme``, and a one-line report."""
    modes = fast_modes(model, layout, on_seabed) or [Mode("system", "no fast mode", 0.0)]
    gov = min(modes, key=lambda m: m.dt_limit(scheme))
    limit = gov.dt_limit(scheme)
    ratio = gov.rate * dtM
    bound = STABLE_OMEGA_DT[scheme] if gov.damped else UNDAMPED_OMEGA_DT[scheme]
    name = label or scheme.name
    if math.isinf(limit):
        text = (f"dtM = {dtM:.4g} s ({name}, unconditionally stable); fastest mode: {gov.where}, {gov.kind}, "
                f"rate {gov.rate:.4g} 1/s, rate*dtM = {ratio:.3g}: modes faster than about 1/dtM are damped "
                f"numerically, not resolved")
    elif limit > 0:
        text = (f"dtM = {dtM:.4g} s ({name}); governing mode: {gov.where}, {gov.kind}, "
                f"rate {gov.rate:.4g} 1/s, rate*dtM = {ratio:.3g} (stable up to about {bound:.3g}, i.e. "
                f"dtM <= {limit:.3g} s)")
    else:
        text = (f"dtM = {dtM:.4g} s ({name}); governing mode: {gov.where}, {gov.kind}, rate "
                f"{gov.rate:.4g} 1/s: {name} amplifies undamped modes at any dtM; use RK4")
    return gov, limit, text
