"""moorline: lumped-mass mooring line and dynamic power cable simulation.

Package layout and the direction of its dependencies (keep it):

    model/       plain descriptions (Model, LineType, Point, Line, Environment, Options)
    io/          MoorDyn v2 decks and output tables              -> model
    core/        numba kernels, arrays in and out                 -> numpy, numba (core.layout -> model)
    simulate.py  output-interval loop, progress, instability checks -> core, model
    coupling.py  System: the outer-program interface               -> core, model, io
    results.py   xarray Datasets and MoorDyn-style writers         -> numpy, xarray
    cli.py       the ``moorline`` command                          -> everything above

Nothing below imports from a layer above it.
"""

__version__ = "0.1.0"

from .coupling import System  # noqa: E402
from .errors import DeckError, SimulationError  # noqa: E402
from .model import Model  # noqa: E402
from .motion import Trajectory  # noqa: E402
from .simulate import simulate  # noqa: E402  (the function shadows its module's name on purpose)

__all__ = ["DeckError", "Model", "SimulationError", "System", "Trajectory", "__version__", "simulate"]
