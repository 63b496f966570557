"""Frequency-domain hydrodynamics of floating bodies (linear potential flow)."""
