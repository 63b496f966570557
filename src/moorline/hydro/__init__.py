"""Frequency-domain hydrodynamics of floating bodies (linear potential flow): coefficient Datasets, WAMIT and
Capytaine input/output, Capytaine runs with a cache, radiation impulse responses and state-space fits, excitation
interpolation and RAOs.

Modules and the direction of their dependencies (keep it; nothing here imports moordyn or moorpy, and Capytaine
only inside the functions of ``bem`` that need it):

    dataset      schema, builder, checks, change of reference point     -> numpy, xarray
    wamit        .1/.3/.hst/.out reader and writer                      -> dataset (irf for a missing A_inf)
    bem          Capytaine NetCDF/Datasets, meshes, cached computation  -> dataset (irf for a missing A_inf)
    irf          impulse response, Ogilvie's relations, convolution     -> dataset
    statespace   Hankel-SVD realisations, passivity, packing            -> dataset, irf
    excitation   interpolation in frequency and heading                 -> numpy, xarray
    rao          mass matrix, impedance, RAOs, constrained two-body PTO -> dataset, excitation
"""

from .bem import (
    compute_coefficients,
    from_capytaine,
    load_mesh,
    mesh_axisymmetric,
    mesh_cylinder,
    mesh_hemisphere,
    read_capytaine,
    read_gdf,
    write_netcdf,
)
from .dataset import (
    HydroFileError,
    build_dataset,
    check_coefficients,
    dof_labels,
    matrix,
    reference_transform,
    transform_reference,
)
from .excitation import excitation_transfer
from .irf import coefficients_from_irf, impulse_response, passive_damping, radiation_convolution_force
from .rao import LinearPTO, impedance, mass_matrix, rao
from .statespace import PackedStateSpace, StateSpaceFit, fit_state_space
from .wamit import read_wamit, read_wamit_out, write_wamit

__all__ = [
    "HydroFileError", "LinearPTO", "PackedStateSpace", "StateSpaceFit", "build_dataset", "check_coefficients",
    "coefficients_from_irf", "compute_coefficients", "dof_labels", "excitation_transfer", "fit_state_space",
    "from_capytaine", "impedance", "impulse_response", "load_mesh", "mass_matrix", "matrix", "mesh_axisymmetric",
    "mesh_cylinder", "mesh_hemisphere", "passive_damping", "radiation_convolution_force", "rao", "read_capytaine",
    "read_gdf", "read_wamit", "read_wamit_out", "reference_transform", "transform_reference", "write_netcdf",
    "write_wamit",
]
