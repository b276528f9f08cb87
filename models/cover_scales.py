"""Cover scales of the robotic surface (seed 001, Fig. 1B and 5): Kapton disks attached at their
centres over each junction, overlapping their neighbours and free to slide on them.

Physics only: the disks' plate bending stiffness, their overlap (lens) areas and mass. How the layer
enters the bar-and-hinge energy is :mod:`lcefem.solvers.bar_hinge.cover_scales`.

The approximation (an equivalent elastic layer): where two disks overlap they are pressed onto each
other and, being free to slide (frictionless, no shear transfer between layers), each bends as a
separate plate with the surface's curvature; the stack's bending stiffness is the sum of the layers'
(no composite action). Disk material outside every overlap is a free flap and stores no energy. The
layer's energy for curvatures (kx, ky, kxy) [1/mm] is

    U = D A_b (kx^2 + ky^2 + 2 nu kx ky + 2 (1 - nu) kxy^2) / 2,   D = E t^3 / (12 (1 - nu^2)),

with A_b the disk material that lies in an overlap: 2 x (lens area) per overlapping pair
(:meth:`CoverScales.bent_area`). ``bent = "disks"`` takes every disk's whole area instead (the upper
bound: each disk fully conforming to the surface).

Units: mm, N, t.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from lcefem.models import units
from lcefem.models.errors import InputError
from lcefem.models.hyperelastic import KAPTON_DATASHEET_MODULUS, KAPTON_POISSON_RATIO
from lcefem.models.parameters import param

SEED = (
    "seed 001, Materials and Methods: 'The cover scales were circular disks with 50 mm diameter', "
    "cut "
    "from the '127-um-thick Kapton films'"
)
BENT = ("overlaps", "disks")


@dataclass(frozen=True)
class CoverScales:
    """The Kapton cover scales (one disk per junction, centred on it)."""

    diameter: float = param(50.0, "mm", SEED, positive=True)
    thickness: float = param(0.127, "mm", SEED, positive=True)
    youngs_modulus: float = param(
        KAPTON_DATASHEET_MODULUS,
        "MPa",
        "DuPont Kapton HN datasheet, 23 C (shared/reference/materials.md: 2.5 GPa)",
        positive=True,
    )
    poisson_ratio: float = param(
        KAPTON_POISSON_RATIO, "-", "DuPont Kapton HN datasheet: 0.34", minimum=0.0, maximum=0.5
    )
    density: float = param(
        1.42 * units.G_PER_CM3, "t/mm^3", "DuPont Kapton HN datasheet: 1.42 g/cm^3", positive=True
    )
    bent: str = param(
        "overlaps",
        "-",
        "which disk material bends with the surface: 'overlaps' (the "
        "material in overlap lenses, pressed by a neighbour: the model) or 'disks' (all "
        "of it: upper bound); assumed, module docstring",
    )

    def checked(self) -> "CoverScales":
        if self.bent not in BENT:
            raise InputError(f"scales.bent = {self.bent!r}: allowed {', '.join(BENT)}")
        return self

    @property
    def bending_stiffness(self) -> float:
        """Plate bending stiffness D = E t^3 / (12 (1 - nu^2)) [N mm]."""
        nu = self.poisson_ratio
        return self.youngs_modulus * self.thickness**3 / (12.0 * (1.0 - nu * nu))

    @property
    def disk_area(self) -> float:
        """[mm^2]"""
        return math.pi * self.diameter**2 / 4.0

    @property
    def disk_mass(self) -> float:
        """[t]"""
        return self.density * self.disk_area * self.thickness

    def lens_area(self, distance: float) -> float:
        """Overlap area [mm^2] of two disks whose centres are ``distance`` [mm] apart (0 if
        apart)."""
        r = 0.5 * self.diameter
        d = float(distance)
        if d >= 2.0 * r:
            return 0.0
        return 2.0 * r * r * math.acos(d / (2.0 * r)) - 0.5 * d * math.sqrt(4.0 * r * r - d * d)

    def bent_area(self, pitch: float, ribbons: int) -> float:
        """A_b [mm^2] of an n x n grid of disks on a square pitch [mm] (module docstring): nearest
        and diagonal neighbours' lenses, each counted for both disks ('overlaps'), or n^2 disk
        areas."""
        n = int(ribbons)
        if self.bent == "disks":
            return n * n * self.disk_area
        near = 2 * n * (n - 1)
        diagonal = 2 * (n - 1) ** 2
        return 2.0 * (
            near * self.lens_area(pitch) + diagonal * self.lens_area(math.sqrt(2.0) * pitch)
        )
