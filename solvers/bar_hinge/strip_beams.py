"""The bar-and-hinge model with the LCE strips' own bending stiffness (``mesh.strip_element`` =
'bending' or 'beam'): :class:`StripBeamModel` adds one
:func:`lcefem.models.bar_hinge.strip_beam_element` per strip piece and rail (rows
``structure.info["strip_beams"]``, written by
:func:`lcefem.meshes.composite_beam.apply_strip_element`) to
:class:`lcefem.solvers.bar_hinge.BarHingeModel`'s energy, gradient and Hessian (its COO pattern
extended by the elements' 18 x 18 blocks). :func:`bar_hinge_model` builds it when the structure has
such rows and the plain model otherwise, so that 'bar' and 'offset' structures run exactly as
before.

E I per rail = lce.bending_modulus (3 mu_0 = 0.543 MPa) x lce.bending_factor x
sections["strip_beams"]["second_moment"] (half the as-built strip section's w_s h_s^3/12); the
element's stiffness 2 E I/L with L the piece's as-built chord length (the section and the length are
taken as built: the strips' thinning and shortening with actuation are not followed).

Units: mm, N, mJ.
"""

from __future__ import annotations

import numpy as np

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.models import bar_hinge as law
from lcefem.models import bar_hinge_materials as bhm
from lcefem.solvers.bar_hinge import BarHingeModel
from lcefem.solvers.bar_hinge.kernels import BEAM_SLOT_TABLE, strip_beam_forces


class StripBeamModel(BarHingeModel):
    """:class:`BarHingeModel` plus the strips' bending elements (see the module docstring)."""

    def __init__(self, structure: BarHingeStructure, *args, **kwargs):
        rows = np.asarray(structure.info.get("strip_beams", np.zeros((0, 6))), dtype=np.int64)
        self._beam_rows = rows.reshape(-1, 6)
        x0 = structure.nodes
        xs = [x0[self._beam_rows[:, c]] for c in range(6)]
        self._beam_length = np.linalg.norm(xs[3] - xs[0], axis=1)
        self._beam_rest_a = law.dihedral_angle(xs[0], xs[1], xs[2], xs[3], derivatives=0)
        self._beam_rest_b = law.dihedral_angle(xs[3], xs[4], xs[5], xs[0], derivatives=0)
        super().__init__(structure, *args, **kwargs)
        second_moment = float(structure.sections["strip_beams"]["second_moment"])
        self.strip_bending_stiffness = (
            self.lce.bending_modulus * self.lce.bending_factor * second_moment
        )
        self._beam_c = (
            np.full(self._beam_rows.shape[0], 2.0 * self.strip_bending_stiffness)
            / self._beam_length
        )

    def _build_pattern(self) -> None:
        super()._build_pattern()
        dofs = (3 * self._beam_rows[:, :, None] + np.arange(3)).reshape(
            self._beam_rows.shape[0], -1
        )
        start = self._coo_rows.size
        self._beam_dofs = dofs
        self._beam_coo = slice(start, start + dofs.size * dofs.shape[1])
        self._coo_rows = np.concatenate(
            [self._coo_rows, np.repeat(dofs, dofs.shape[1], axis=1).ravel()]
        )
        self._coo_cols = np.concatenate([self._coo_cols, np.tile(dofs, (1, dofs.shape[1])).ravel()])

    def strip_beam_energy(self, x) -> np.ndarray:
        """Bending energy [mJ] of every strip element."""
        x = np.asarray(x, dtype=float).reshape(-1, 3)
        return law.strip_beam_element(
            *(x[self._beam_rows[:, c]] for c in range(6)),
            self._beam_c,
            self._beam_rest_a,
            self._beam_rest_b,
            derivatives=0,
        )

    def evaluate(self, x: np.ndarray, derivatives: int = 2):
        """:meth:`BarHingeModel.evaluate` plus the strip elements: the energy as
        :func:`law.strip_beam_element`, its derivatives from the compiled kernel
        (:func:`strip_beam_forces`; the numpy version's (n, 18, 18) temporaries were 14 % of the
        5 x 5 gridshell's assembly), the Hessian written straight into its COO slice."""
        out = super().evaluate(x, derivatives)
        x = np.asarray(x, dtype=float).reshape(-1, 3)
        xs = [x[self._beam_rows[:, c]] for c in range(6)]
        th_a = law.dihedral_angle(xs[0], xs[1], xs[2], xs[3], derivatives=0)
        th_b = law.dihedral_angle(xs[3], xs[4], xs[5], xs[0], derivatives=0)
        d_a = np.mod(th_a - self._beam_rest_a + np.pi, 2.0 * np.pi) - np.pi
        d_b = np.mod(th_b - self._beam_rest_b + np.pi, 2.0 * np.pi) - np.pi
        c = self._beam_c
        beam_energy = float(np.sum(c * (d_a * d_a + d_a * d_b + d_b * d_b)))
        if derivatives == 0:
            return out + beam_energy
        n = d_a.shape[0]
        grad_e = np.empty((n, 18))
        if derivatives == 2:
            hess = out[2][self._beam_coo].reshape(n, 18, 18)
        else:
            hess = np.empty((1, 18, 18))  # not written
        m_a, m_b = c * (2.0 * d_a + d_b), c * (d_a + 2.0 * d_b)
        strip_beam_forces(
            np.stack(xs), c, m_a, m_b, BEAM_SLOT_TABLE, grad_e, hess, derivatives == 2
        )
        energy = out[0] + beam_energy
        grad = out[1] + np.bincount(
            self._beam_dofs.ravel(), weights=grad_e.ravel(), minlength=self.ndof
        )
        if derivatives == 1:
            return energy, grad
        return energy, grad, out[2]


def bar_hinge_model(
    structure: BarHingeStructure, materials: bhm.BarHingeMaterials = bhm.BarHingeMaterials()
) -> BarHingeModel:
    """The model of ``structure``: :class:`StripBeamModel` when it has strip bending elements
    (``mesh.strip_element`` 'bending' or 'beam'), :class:`BarHingeModel` otherwise."""
    if len(structure.info.get("strip_beams", ())):
        m = materials
        return StripBeamModel(
            structure, m.kapton, m.lce, m.glue, m.strip_contact, m.ogden, m.contact
        )
    return BarHingeModel.from_materials(structure, materials)
