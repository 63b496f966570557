"""The quasi-static mooring model.

* :mod:`.catenary`: the frictionless elastic catenary, the start guess of the dynamic model's
  initial conditions (kept as it is for that use).
* :mod:`.line2d`: the line of the quasi-static model (seabed contact, slope, MAP++ friction, slack
  and grounded lines) with the analytic derivatives of its end forces.
* :mod:`.network`: the compiled network solve (free points and bodies by Newton) and the condensed
  stiffness (implicit-function theorem).
* :mod:`.hydrostatics`: :class:`BodyHydrostatics`, the buoyancy of a floating body.
* :mod:`.solver`: :class:`QuasiStaticModel`, built once from a Model, and its ``solve``.
"""

from .catenary import CatenaryResult, CatenaryStatus, catenary, catenary_nodes, catenary_profile, catenary_solve
from .hydrostatics import BodyHydrostatics
from .solver import QuasiStaticError, QuasiStaticModel, QuasiStaticSolution, line_end_forces

__all__ = ["BodyHydrostatics", "CatenaryResult", "CatenaryStatus", "QuasiStaticError", "QuasiStaticModel",
           "QuasiStaticSolution", "catenary", "catenary_nodes", "catenary_profile", "catenary_solve",
           "line_end_forces"]
