"""Numba kernels of moorline: arrays in, arrays out."""
