"""Plain descriptions of a mooring system (no numba, no file formats)."""

from .system import Model
from .types import (
    CONTACT_MODES,
    FRICTION_MODELS,
    POINT_KIND_WORDS,
    Attachment,
    Bathymetry,
    Curve,
    Environment,
    Line,
    LineType,
    ModelError,
    Options,
    Point,
    PointKind,
    Rod,
    RodKind,
    RodType,
)

__all__ = ["CONTACT_MODES", "FRICTION_MODELS", "POINT_KIND_WORDS", "Attachment", "Bathymetry", "Curve",
           "Environment", "Line", "LineType", "Model", "ModelError", "Options", "Point", "PointKind", "Rod", "RodKind",
           "RodType"]
