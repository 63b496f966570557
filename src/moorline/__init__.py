"""moorline: lumped-mass mooring line and dynamic power cable simulation.

Package layout and the direction of its dependencies (keep it; ``tests/unit/test_house.py``
checks it):

    errors.py      the exceptions every layer raises                   -> nothing
    model/         plain descriptions (Model, LineType, Point, Line, Rod, Body, Environment,
                   Options, waves and currents)                         -> numpy
    io/            MoorDyn v1/v2 decks (lexer, column tables, builder, writer), output tables,
                   bathymetry and wave/current files, VTK files        -> model, errors
    core/          numba kernels, arrays in and out: layout, lines, seabed, rigid bodies,
                   water kinematics, rhs, time schemes, implicit solver and its Jacobian, the
                   dynamic model's static kernels                       -> numpy, numba (and model,
                                                                           where it builds arrays)
    hydro/         potential-flow coefficients as xarray Datasets: WAMIT and Capytaine readers,
                   cached Capytaine runs, impulse responses, state-space fits, RAOs
                                                                        -> numpy, scipy, xarray (capytaine)
    quasistatic/   the quasi-static model: elastic catenaries with seabed friction, line
                   networks with free points and bodies, stiffness, offset curves
                                                                        -> model, core
    system/        the runtime: System (init / step / advance_to), object views, initial
                   conditions, floating-body arrays, checkpoints (save / load), input limits
                                                                        -> core, quasistatic, hydro,
                                                                           model, io
    motion.py      prescribed coupled motions                           -> core
    results.py     xarray Datasets, the NetCDF writer and its stream    -> numpy, xarray
    progress.py    the compile notice and its timing (stderr)           -> numba, tqdm
    simulate.py    output-interval loop, progress, streamed outputs, checkpoints
                                                                        -> system, results, progress
    post/          fatigue: section loads, stress, rainflow, S-N, Miner -> numpy, xarray
    studies/       parametric sweeps: spec, parameters, case runner, executors
                                                                        -> simulate, post, system, io
    plot.py        figures                                              -> post
    cli.py         the ``moorline`` command                             -> everything above
    coupling.py, batch.py   old import paths of system/ and studies/ (re-exports only)

Nothing imports from a layer above it, and no two modules import each other.
"""

__version__ = "0.1.0"

from .errors import DeckError, SimulationError  # noqa: E402
from .io import read_deck, write_deck, write_vtk  # noqa: E402
from .model import Model  # noqa: E402
from .motion import Trajectory  # noqa: E402
from .simulate import simulate  # noqa: E402  (the function shadows its module's name on purpose)
from .system import System  # noqa: E402

__all__ = ["DeckError", "Model", "SimulationError", "System", "Trajectory", "__version__", "read_deck", "simulate",
           "write_deck", "write_vtk"]
