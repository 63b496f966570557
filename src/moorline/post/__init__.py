"""Post-processing for fatigue and design checks of cables and mooring lines.

    sections   = section_loads(ds, model=model)                 # tension, curvature vector, My, Mz
    stress     = cross_section_stress(sections, TubeSection(0.040, 0.020), tensile_only=True)
    damage     = fatigue_damage(stress, SNCurve.one_slope(6.098e19, 6.238, unit=1e6))
    where      = critical_location(damage)                      # arc length s [m], theta [deg]

Modules: :mod:`.sections` (section loads and the local frame), :mod:`.stress` (tube stress),
:mod:`.fatigue` (rainflow, S-N/T-N curves, Miner's sum, life), :mod:`.seastate` (scatter diagrams,
the buoy motion of a sea state, lifetime weighting), :mod:`.envelopes` (curvature, bend radius,
tension and compression checks). This layer depends on numpy, xarray and ``rainflow`` only; a
Model passed in is only read (its line types, lines and rods).
"""

from .envelopes import envelopes
from .fatigue import (
    SECONDS_PER_YEAR,
    SNCurve,
    api_chain_tn_curve,
    critical_location,
    dnv_chain_sn_curve,
    fatigue_damage,
    life_years,
    miner_sum,
    rainflow_cycles,
)
from .seastate import (
    ScatterDiagram,
    SeaState,
    buoy_motion,
    jonswap_spectrum,
    lifetime_damage,
    to_scatter_grid,
    tp_from_tz,
    wave_components,
    wavenumber,
)
from .sections import clamp_tangents, line_nodes, section_loads
from .stress import TubeSection, cross_section_stress, theta_points

__all__ = ["SECONDS_PER_YEAR", "SNCurve", "ScatterDiagram", "SeaState", "TubeSection", "api_chain_tn_curve",
           "buoy_motion", "clamp_tangents", "critical_location", "cross_section_stress", "dnv_chain_sn_curve",
           "envelopes", "fatigue_damage", "jonswap_spectrum", "life_years", "lifetime_damage", "line_nodes",
           "miner_sum", "rainflow_cycles", "section_loads", "theta_points", "to_scatter_grid", "tp_from_tz",
           "wave_components", "wavenumber"]
