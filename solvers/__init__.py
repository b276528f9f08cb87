"""Numerics: heat, mechanics, coupled stepping, continuation, and the reduced-order integrators.

Solvers take model objects and meshes; they know nothing of experiments.

Importing this package orders MPI ahead of dolfinx/petsc4py (``dolfinx_solver``), so a script that
imports anything from ``lcefem.solvers`` first may then ``import dolfinx`` itself (without it,
``import dolfinx`` on its own fails to load libmpi). See docs/library.md.
"""

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py; cheap: no dolfinx import)
