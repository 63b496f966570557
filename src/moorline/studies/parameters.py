"""The registry of the parameters a study can vary (:data:`PARAMETERS`, :func:`register_parameter`)
and how a case's values are applied to a model."""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..errors import StudyError
from ..model.water import Current

log = logging.getLogger("moorline")


# ---------------------------------------------------------------------------------------------- registry
@dataclass(frozen=True)
class Parameter:
    """A parameter a study can vary.

    ``kind`` is 'model' (``setter(model, value, target)`` changes the Model), 'sea_state' (the
    value goes to the :class:`~moorline.post.SeaState` field ``field``) or 'current' (``field``
    'speed' or 'heading' of a uniform current, set together once all parameters of a case are
    read, so their order does not matter).
    """

    name: str
    kind: str
    setter: Callable | None = None
    field: str | None = None
    units: str = ""
    doc: str = ""


#: name -> Parameter. A parameter may be written ``name[target]`` in a study; the target (a line
#: type name for line-type parameters, a line number for line parameters) is passed to the
#: setter, which applies the value to every line type / line when it is None.
PARAMETERS: dict[str, Parameter] = {}


def register_parameter(name: str, setter: Callable, *, units: str = "", doc: str = "") -> None:
    """Register (or replace) a model parameter.

    Parameters
    ----------
    name : str
        Name used in study files.
    setter : callable
        ``setter(model, value, target)``: change the :class:`~moorline.Model` in place; ``target``
        is the text in ``name[target]`` or None.
    units, doc : str
        For reports and error messages.
    """
    PARAMETERS[name] = Parameter(name, "model", setter, None, units, doc)


def _line_types(model, target):
    if target is None:
        return list(model.line_types.values())
    if target not in model.line_types:
        raise StudyError(f"no line type {target!r} in the deck (types: {sorted(model.line_types)})")
    return [model.line_types[target]]


def _lines(model, target):
    if target is None:
        return list(model.lines)
    try:
        k = int(target)
        return [model.lines[k - 1]] if 1 <= k <= len(model.lines) else []
    except ValueError:
        return []


def _line_type_setter(attr: str):
    def setter(model, value, target=None):
        for lt in _line_types(model, target):
            setattr(lt, attr, float(value))
    return setter


def _line_setter(attr: str, cast):
    def setter(model, value, target=None):
        lines = _lines(model, target)
        if not lines:
            raise StudyError(f"no line {target!r} in the deck ({len(model.lines)} lines)")
        for ln in lines:
            setattr(ln, attr, cast(value))
    return setter


def _set_dtM(model, value, target=None):
    model.options.dtM = float(value)


def _set_depth(model, value, target=None):
    model.env.depth = float(value)


for _name, _attr, _units, _doc in (("mass", "w", "kg/m", "mass per unit length in air"),
                                   ("EI", "EI", "N m^2", "bending stiffness"),
                                   ("EA", "EA", "N", "axial stiffness"),
                                   ("diameter", "d", "m", "volume-equivalent diameter"),
                                   ("Cd", "Cd", "-", "transverse drag coefficient"),
                                   ("Ca", "Ca", "-", "transverse added-mass coefficient"),
                                   ("CdAx", "CdAx", "-", "tangential drag coefficient"),
                                   ("CaAx", "CaAx", "-", "tangential added-mass coefficient")):
    register_parameter(_name, _line_type_setter(_attr), units=_units, doc=f"line type {_doc}")
register_parameter("length", _line_setter("L", float), units="m", doc="unstretched line length")
register_parameter("segments", _line_setter("N", int), units="-", doc="number of segments of a line")
register_parameter("dtM", _set_dtM, units="s", doc="internal time step")
register_parameter("depth", _set_depth, units="m", doc="water depth (flat seabed)")
for _name, _field, _units in (("Hs", "Hs", "m"), ("Tz", "Tz", "s"), ("wave_heading", "heading", "deg"),
                              ("gamma", "gamma", "-"), ("seed", "seed", "-")):
    PARAMETERS[_name] = Parameter(_name, "sea_state", None, _field, _units, f"sea state {_field}")
for _name, _field, _units in (("current_speed", "speed", "m/s"), ("current_heading", "heading", "deg")):
    PARAMETERS[_name] = Parameter(_name, "current", None, _field, _units, f"uniform current {_field} "
                                  "(heading: the direction the water flows toward, from +x toward +y)")


def _split_name(key: str) -> tuple[str, str | None]:
    """'mass[cable]' -> ('mass', 'cable')."""
    if key.endswith("]") and "[" in key:
        name, target = key[:-1].split("[", 1)
        return name.strip(), target.strip()
    return key.strip(), None


def _parameter(key: str) -> tuple[Parameter, str | None]:
    name, target = _split_name(key)
    p = PARAMETERS.get(name)
    if p is None:
        raise StudyError(f"unknown parameter {name!r}; known parameters: {', '.join(sorted(PARAMETERS))}")
    return p, target




def _apply_parameters(model, params: dict) -> dict:
    """Apply the model parameters in order, then the current; return the sea-state fields set."""
    sea, current = {}, {}
    for key, value in params.items():
        p, target = _parameter(key)
        if p.kind == "sea_state":
            sea[p.field] = value
        elif p.kind == "current":
            if target is not None:
                raise StudyError(f"parameter {key!r}: current parameters take no [target]")
            current[p.field] = value
        else:
            try:
                p.setter(model, value, target)
            except StudyError:
                raise
            except (TypeError, ValueError) as e:
                raise StudyError(f"parameter {key!r} = {value!r}: {e}") from None
    if current:
        _set_current(model, **current)
    return sea


def _set_current(model, speed=None, heading=None) -> None:
    """A uniform current of ``speed`` [m/s] toward ``heading`` [deg]; what is not given is kept
    from the deck's current (which must then be uniform)."""
    v = np.zeros(3)
    old = model.env.current
    if old is not None:
        vel = np.asarray(old.velocity, dtype=float)
        if vel.size != 3:
            raise StudyError("current_speed and current_heading make a uniform current; the deck's current "
                             "varies in space or time")
        v = vel.reshape(3)
    s = float(speed) if speed is not None else math.hypot(v[0], v[1])
    h = float(heading) if heading is not None else math.degrees(math.atan2(v[1], v[0]))
    try:
        model.env.current = Current.uniform(s, h, vertical=v[2])
    except ValueError as e:
        raise StudyError(f"current: {e}") from None
