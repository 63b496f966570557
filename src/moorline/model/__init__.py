"""Plain descriptions of a mooring system (no numba, no file formats)."""

from .floating import BemRun, FloatingBody, Hull, HydroBodies, Joint, MorisonStrip
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
           "BemRun", "Body", "BodyKind", "Curve", "Environment", "FloatingBody", "Hull", "HydroBodies", "Joint", "Line",
           "LineType",
           "Model", "ModelError", "MorisonStrip", "Options", "Point", "PointKind", "Rod", "RodKind", "RodType",
           "angles_xyz", "rotation_xyz"]
