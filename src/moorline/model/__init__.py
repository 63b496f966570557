"""Plain descriptions of a mooring system (no numba, no file formats)."""

from .floating import BemRun, FloatingBody, Hull, HydroBodies, Joint, MorisonStrip
from .system import Model
from .types import (
    BODY_KIND_WORDS,
    CONTACT_MODES,
    ELASTIC,
    FRICTION_MODELS,
    POINT_KIND_WORDS,
    SYROPE,
    SYROPE_WC_TYPES,
    VISCO_CONSTANT,
    VISCO_MEAN,
    Attachment,
    Bathymetry,
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
    angles_xyz,
    rotation_xyz,
)

__all__ = ["BODY_KIND_WORDS", "CONTACT_MODES", "ELASTIC", "FRICTION_MODELS", "SYROPE", "SYROPE_WC_TYPES",
           "VISCO_CONSTANT", "VISCO_MEAN", "SyropeCurve", "POINT_KIND_WORDS", "Attachment", "Bathymetry",
           "BemRun", "Body", "BodyKind", "Curve", "Environment", "Failure", "FloatingBody", "Hull", "HydroBodies",
           "Joint", "Line",
           "LineType",
           "Model", "ModelError", "MorisonStrip", "Options", "Point", "PointKind", "Rod", "RodKind", "RodType",
           "angles_xyz", "rotation_xyz"]
