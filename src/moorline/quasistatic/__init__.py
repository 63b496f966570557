"""The quasi-static mooring model: elastic catenary lines (with seabed contact), used today as the
start guess of the dynamic model's initial conditions."""

from .catenary import CatenaryResult, CatenaryStatus, catenary, catenary_nodes, catenary_profile, catenary_solve

__all__ = ["CatenaryResult", "CatenaryStatus", "catenary", "catenary_nodes", "catenary_profile", "catenary_solve"]
