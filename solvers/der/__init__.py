"""Discrete Elastic Rods with implicit contact and friction (seed 000; Bergou et al. 2008, 2010).

Modules:

- :mod:`~lcefem.solvers.der.model`: ``DiscreteRod`` (section, rest shape, masses, gravity, damping,
  ground/contact/friction, prescribed dofs, external forces), ``RodState`` (nodes, edge angles,
  velocities, reference directors, reference twist), ``RestShape``, ``Ground``, ``lumped_masses``.
- :mod:`~lcefem.solvers.der.frames`: parallel transport, reference twist, material frames.
- :mod:`~lcefem.solvers.der.assembly`: vectorised energy/gradient/banded-Hessian assembly, contact
  sampling (section corners, frame angle interpolated between sections), friction lag.
- :mod:`~lcefem.solvers.der.newton`: Newton with banded Cholesky, Levenberg shift, line search.
- :mod:`~lcefem.solvers.der.integrator`: implicit Euler / implicit midpoint ``Integrator`` with
  step halving and ``ConvergenceError``.
- :mod:`~lcefem.solvers.der.static`: ``solve_static`` (load stepping, rest-shape continuation).
- :mod:`~lcefem.solvers.der.heat`: section heat model of a ribbon (cells, contact and air exchange).
- :mod:`~lcefem.solvers.der.ribbon`: the LCE ribbon (``RibbonSimulation``) and
  ``ribbon_static_response`` (static shape of a free ribbon at given temperatures, for FE
  comparisons).
- compiled (numba) loops: :mod:`~lcefem.solvers.der.kernels` (stretching, bending, twisting,
  transport source), :mod:`~lcefem.solvers.der.contact_kernels` (sample points, contact, friction,
  boxes), :mod:`~lcefem.solvers.der.heat_kernels` (section heat step),
  :mod:`~lcefem.solvers.der.frame_kernels` (frame transport), :mod:`~lcefem.solvers.der.banded`
  (banded Cholesky), :mod:`~lcefem.solvers.der.kernel_ops` (dense helpers), and
  :mod:`~lcefem.solvers.der.compiled_newton` (the Newton loop around them).
- :mod:`~lcefem.solvers.der.output`: VTK PolyData time series (.vtp + .pvd) and CSV, written
  atomically.
"""

from lcefem.solvers.der.integrator import Integrator, StepOptions
from lcefem.solvers.der.model import DiscreteRod, Ground, RestShape, RodState, lumped_masses
from lcefem.solvers.der.newton import NewtonOptions
from lcefem.solvers.der.ribbon import (
    RibbonNumerics,
    RibbonSetup,
    RibbonSimulation,
    StaticResponse,
    ribbon_static_response,
)
from lcefem.solvers.der.static import solve_static, statically_determinate_support

__all__ = [
    "DiscreteRod",
    "Ground",
    "Integrator",
    "NewtonOptions",
    "RestShape",
    "RibbonNumerics",
    "RibbonSetup",
    "RibbonSimulation",
    "RodState",
    "StaticResponse",
    "StepOptions",
    "lumped_masses",
    "ribbon_static_response",
    "solve_static",
    "statically_determinate_support",
]
