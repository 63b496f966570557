"""Old home of :class:`moorline.System` and its views, kept so that ``from moorline.coupling import
System`` goes on working; the runtime now lives in :mod:`moorline.system`."""

from .system import BodyView, LineView, PointView, RodView, System

__all__ = ["BodyView", "LineView", "PointView", "RodView", "System"]
