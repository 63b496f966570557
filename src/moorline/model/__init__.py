"""Plain descriptions of a mooring system (no numba, no file formats)."""

from .system import Model
from .types import (
    BODY_KIND_WORDS,
    CONTACT_MODES,
    FRICTION_MODELS,
    POINT_KIND_WORDS,
    Attachment,
    Bathymetry,
    Body,
    BodyKind,
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
    angles_xyz,
    rotation_xyz,
)

__all__ = ["BODY_KIND_WORDS", "CONTACT_MODES", "FRICTION_MODELS", "POINT_KIND_WORDS", "Attachment", "Bathymetry",
           "Body", "BodyKind", "Curve", "Environment", "Line", "LineType", "Model", "ModelError", "Options", "Point",
           "PointKind", "Rod", "RodKind", "RodType", "angles_xyz", "rotation_xyz"]
