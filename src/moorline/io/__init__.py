"""MoorDyn v1/v2 input decks (:func:`read_deck`, :func:`write_deck`), EA/BA/EI curve files, seabed
bathymetry files and VTK output for ParaView (:func:`write_vtk`)."""

from .bathymetry import find_seafloor_file, read_depth_grid, read_seafloor_grid, write_seafloor_grid
from .deck import read_curve, read_deck, read_deck_text, write_deck
from .vtk import write_vtk

__all__ = ["find_seafloor_file", "read_curve", "read_deck", "read_deck_text", "read_depth_grid",
           "read_seafloor_grid", "write_deck", "write_seafloor_grid", "write_vtk"]
