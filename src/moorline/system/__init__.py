"""The runtime of a mooring system: :class:`System` (init / step / advance_to, MoorDyn's coupling
API), the views of its lines, points, rods and bodies, and its initial-condition strategies."""

from .runtime import System
from .views import BodyView, LineView, PointView, RodView

__all__ = ["BodyView", "LineView", "PointView", "RodView", "System"]
