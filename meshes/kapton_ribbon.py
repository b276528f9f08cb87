"""The passive Kapton ribbon specimen of the buckling test (seed 001, Fig. 2G, fig. S4 and Materials
and Methods: 36 mm x 7 mm x 127 um, fixed-fixed, end shortening up to 50 %).

Coordinates [mm]: x along the ribbon, the free length spanning 0 <= x <= length; y across
(0 <= y <= width); z out of plane. :class:`RibbonSpecimen` holds what a continuum (FE) builder can use
too; :class:`RibbonBarHingeMesh` the bar-and-hinge choices. In the bar-and-hinge model each clamp is
one extra rigid panel outside the free length (all its nodes held), so the fold hinge on the clamp's
edge makes the end a built-in one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lcefem.meshes.bar_hinge_structure import BarHingeStructure, n5b8_structure
from lcefem.models.errors import InputError
from lcefem.models.parameters import check, param

SEED_SPECIMEN = "seed 001 Materials and Methods: nine samples 36 mm long, 7 mm wide, 127 um Kapton"


@dataclass(frozen=True)
class RibbonSpecimen:
    """The buckling specimen (seed 001)."""

    length: float = param(36.0, "mm", SEED_SPECIMEN + " (taken as the free length between clamps)",
                          positive=True)
    width: float = param(7.0, "mm", SEED_SPECIMEN, positive=True)
    thickness: float = param(0.127, "mm", SEED_SPECIMEN, positive=True)
    supports: str = param("fixed-fixed", "-", "seed 001 Fig. 2G: fixed-fixed support")

    @property
    def second_moment(self) -> float:
        """I = w t^3/12 [mm^4] for bending out of the ribbon's plane."""
        return self.width * self.thickness ** 3 / 12.0

    def checked(self) -> "RibbonSpecimen":
        check(self, "specimen")
        if self.supports != "fixed-fixed":
            raise InputError(f"specimen.supports = {self.supports!r}: allowed 'fixed-fixed'")
        return self


@dataclass(frozen=True)
class RibbonBarHingeMesh:
    """Bar-and-hinge discretisation of the specimen."""

    panels: int = param(11, "-", "chosen: 36/11 = 3.27 mm panels, close to the hinge spacing "
                        "(Lx + d)/Nx = 3.36 mm for which the published hinge stiffness "
                        "k = 5.5 E t^3/(12 (Lx + d)/Nx) is written; k is per unit hinge length, so "
                        "the chain's bending stiffness grows with the panel length (16 panels of "
                        "2.25 mm, like the beam's flank panels, buckle at 36 % less)", minimum=2,
                        maximum=2000)
    clamp_length: float = param(2.3, "mm", "chosen: length of the rigid clamp panel at each end "
                                "(outside the free length; its value does not matter)", positive=True)
    imperfection: float = param(1.0e-3, "-", "chosen: amplitude/length of the first fixed-fixed mode "
                                "z = a (1 - cos(2 pi x/L))/2 seeding the buckling path", minimum=0.0,
                                maximum=0.1)

    def checked(self) -> "RibbonBarHingeMesh":
        check(self, "mesh")
        if not isinstance(self.panels, int):
            raise InputError(f"mesh.panels = {self.panels!r}: must be an integer >= 2")
        return self


def build_ribbon_bar_hinge(specimen: RibbonSpecimen = RibbonSpecimen(),
                           mesh: RibbonBarHingeMesh = RibbonBarHingeMesh()) -> BarHingeStructure:
    """N5B8 bar-and-hinge structure of the specimen with rigid clamp panels at both ends.

    Node sets: "left_clamp" / "right_clamp" (all nodes of each clamp panel, to be held; the right one
    moves by the prescribed end shortening), "left_end" / "right_end" (the two nodes at x = 0 and
    x = length), "mid_span" (the two nodes nearest x = length/2).
    """
    s = specimen.checked()
    m = mesh.checked()
    x = np.concatenate([[-m.clamp_length], np.linspace(0.0, s.length, m.panels + 1),
                        [s.length + m.clamp_length]])
    z = np.where((x >= 0) & (x <= s.length),
                 0.5 * m.imperfection * s.length * (1.0 - np.cos(2.0 * np.pi * x / s.length)), 0.0)
    coords = np.array([(xi, yi, zi) for xi, zi in zip(x, z) for yi in (0.0, s.width)])
    n_st = x.size
    panels = np.array([(2 * a, 2 * a + 2, 2 * a + 3, 2 * a + 1) for a in range(n_st - 1)])
    structure = n5b8_structure(coords, panels, s.thickness)
    centres = structure.panel_centres
    structure.node_sets["left_clamp"] = np.array([0, 1, 2, 3, centres[0]])
    last = 2 * (n_st - 1)
    structure.node_sets["right_clamp"] = np.array([last - 2, last - 1, last, last + 1, centres[-1]])
    structure.node_sets["left_end"] = np.array([2, 3])
    structure.node_sets["right_end"] = np.array([last - 2, last - 1])
    mid = 1 + int(np.argmin(np.abs(x[1:-1] - 0.5 * s.length)))
    structure.node_sets["mid_span"] = np.array([2 * mid, 2 * mid + 1])
    structure.info.update(panels=m.panels, panel_length=s.length / m.panels,
                          free_length=s.length, imperfection=m.imperfection)
    structure.validate()
    return structure
