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

from .errors import DeckError, SimulationError
from .model import Model

__version__ = "0.1.0"

__all__ = ["DeckError", "Model", "SimulationError", "__version__"]
