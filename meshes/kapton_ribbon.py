"""The passive Kapton ribbon specimen of the buckling test (seed 001, Fig. 2G, fig. S4 and Materials
and Methods: 36 mm x 7 mm x 127 um, fixed-fixed, end shortening up to 50 %).

Coordinates [mm]: x along the ribbon, the free length spanning 0 <= x <= length; y across
(0 <= y <= width); z out of plane. :class:`KaptonSpecimenGeometry` holds what a continuum (FE)
builder can use too; :class:`KaptonBarHingeMesh` the bar-and-hinge choices. In the bar-and-hinge
model each clamp is one extra rigid panel outside the free length (all its nodes held), so the fold
hinge on the clamp's edge makes the end a built-in one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lcefem.meshes.bar_hinge_structure import BarHingeStructure, n5b8_structure
from lcefem.meshes.communicator import resolve_comm
from lcefem.models.errors import InputError
from lcefem.models.parameters import check, param

SEED_SPECIMEN = "seed 001 Materials and Methods: nine samples 36 mm long, 7 mm wide, 127 um Kapton"


@dataclass(frozen=True)
class KaptonSpecimenGeometry:
    """The buckling specimen (seed 001)."""

    length: float = param(
        36.0, "mm", SEED_SPECIMEN + " (taken as the free length between clamps)", positive=True
    )
    width: float = param(7.0, "mm", SEED_SPECIMEN, positive=True)
    thickness: float = param(0.127, "mm", SEED_SPECIMEN, positive=True)
    supports: str = param("fixed-fixed", "-", "seed 001 Fig. 2G: fixed-fixed support")

    @property
    def second_moment(self) -> float:
        """I = w t^3/12 [mm^4] for bending out of the ribbon's plane."""
        return self.width * self.thickness**3 / 12.0

    def checked(self) -> "KaptonSpecimenGeometry":
        check(self, "specimen")
        if self.supports != "fixed-fixed":
            raise InputError(f"specimen.supports = {self.supports!r}: allowed 'fixed-fixed'")
        return self


@dataclass(frozen=True)
class KaptonBarHingeMesh:
    """Bar-and-hinge discretisation of the specimen."""

    panels: int = param(
        11,
        "-",
        "chosen: 36/11 = 3.27 mm panels, close to the hinge spacing "
        "(Lx + d)/Nx = 3.36 mm for which the published hinge stiffness "
        "k = 5.5 E t^3/(12 (Lx + d)/Nx) is written; k is per unit hinge length, so "
        "the chain's bending stiffness grows with the panel length (16 panels of "
        "2.25 mm, like the beam's flank panels, buckle at 36 % less)",
        minimum=2,
        maximum=2000,
    )
    clamp_length: float = param(
        2.3,
        "mm",
        "chosen: length of the rigid clamp panel at each end "
        "(outside the free length; its value does not matter)",
        positive=True,
    )
    imperfection: float = param(
        1.0e-3,
        "-",
        "chosen: amplitude/length of the first fixed-fixed mode "
        "z = a (1 - cos(2 pi x/L))/2 seeding the buckling path",
        minimum=0.0,
        maximum=0.1,
    )

    def checked(self) -> "KaptonBarHingeMesh":
        check(self, "mesh")
        if not isinstance(self.panels, int):
            raise InputError(f"mesh.panels = {self.panels!r}: must be an integer >= 2")
        return self


def build_ribbon_bar_hinge(
    specimen: KaptonSpecimenGeometry = KaptonSpecimenGeometry(),
    mesh: KaptonBarHingeMesh = KaptonBarHingeMesh(),
) -> BarHingeStructure:
    """N5B8 bar-and-hinge structure of the specimen with rigid clamp panels at both ends.

    Node sets: "left_clamp" / "right_clamp" (all nodes of each clamp panel, to be held; the right
    one moves by the prescribed end shortening), "left_end" / "right_end" (the two nodes at x = 0
    and x = length), "mid_span" (the two nodes nearest x = length/2).
    """
    s = specimen.checked()
    m = mesh.checked()
    x = np.concatenate(
        [[-m.clamp_length], np.linspace(0.0, s.length, m.panels + 1), [s.length + m.clamp_length]]
    )
    z = np.where(
        (x >= 0) & (x <= s.length),
        0.5 * m.imperfection * s.length * (1.0 - np.cos(2.0 * np.pi * x / s.length)),
        0.0,
    )
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
    structure.info.update(
        panels=m.panels,
        panel_length=s.length / m.panels,
        free_length=s.length,
        imperfection=m.imperfection,
    )
    structure.validate()
    return structure


# --------------------------------------------------------------------------- continuum (FE) mesh
@dataclass(frozen=True)
class KaptonFEMesh:
    """Structured hexahedral mesh of the specimen for quadratic (Q2) elements.

    One Q2 element through the 0.127 mm thickness represents a linear strain distribution through
    it, i.e. pure membrane plus bending, without the shear locking of linear elements; in-plane the
    elements are ``size / (level + 1)`` long (the element aspect ratio size/thickness is then 4-16,
    harmless for Q2; tests/meshes/test_kapton_ribbon_fe.py and the case ribbon_buckling_fe show the
    critical load converged). Level l multiplies the level-0 in-plane counts by l + 1.
    """

    size: float = param(1.0, "mm", "chosen: level-0 in-plane element size", positive=True)
    level: int = param(
        1, "-", "refinement level: in-plane element size = size / (level + 1)", minimum=0, maximum=8
    )
    thickness_elements: int = param(
        1,
        "-",
        "chosen: Q2 elements through the thickness (one represents bending exactly)",
        minimum=1,
        maximum=8,
    )
    symmetry: str = param(
        "half",
        "-",
        "'half' (the plane y = width/2 as a symmetry plane: the "
        "first buckling modes are symmetric across the width) or 'full'",
    )

    def element_size(self) -> float:
        return self.size / (self.level + 1)

    def checked(self) -> "KaptonFEMesh":
        check(self, "mesh")
        if self.symmetry not in ("half", "full"):
            raise InputError(f"mesh.symmetry = {self.symmetry!r}: allowed 'half' or 'full'")
        for name in ("level", "thickness_elements"):
            if not isinstance(getattr(self, name), int):
                raise InputError(f"mesh.{name} = {getattr(self, name)!r}: must be an integer")
        return self


def build_ribbon_fe(
    specimen: KaptonSpecimenGeometry = KaptonSpecimenGeometry(),
    mesh: KaptonFEMesh = KaptonFEMesh(),
    comm=None,
):
    """gmsh hexahedral mesh of the specimen's free length [0, L] x [0, W (or W/2)] x [0, t].

    Tags (by name): cells "kapton"; facets "clamp_left" (x = 0), "clamp_right" (x = L), and with
    ``symmetry="half"`` "sym_y" (y = W/2). Returns a :class:`~lcefem.meshes._gmsh.TaggedMesh`
    whose ``info`` holds the dimensions, element size and ``symmetry_factor`` (2 for a half model:
    forces on the whole specimen are twice those of the mesh).
    """
    from lcefem.meshes._gmsh import TaggedMesh, gmsh_session, to_dolfinx

    comm = resolve_comm(comm)
    s = specimen.checked()
    m = mesh.checked()
    half = m.symmetry == "half"
    L, t = s.length, s.thickness
    W = 0.5 * s.width if half else s.width
    mult = m.level + 1
    nx = mult * max(1, int(np.ceil(L / m.size - 1e-9)))
    ny = mult * max(1, int(np.ceil(W / m.size - 1e-9)))
    nz = m.thickness_elements
    with gmsh_session("kapton_ribbon") as model:
        if comm.rank == 0:
            model.occ.addBox(0.0, 0.0, 0.0, L, W, t)
            model.occ.synchronize()
            tol = 1e-3 * t
            for _, curve in model.getEntities(1):
                xmin, ymin, zmin, xmax, ymax, zmax = model.getBoundingBox(1, curve)
                n = nx if xmax - xmin > tol else (ny if ymax - ymin > tol else nz)
                model.mesh.setTransfiniteCurve(curve, n + 1)
            faces = {"clamp_left": [], "clamp_right": [], "sym_y": []}
            for _, surf in model.getEntities(2):
                model.mesh.setTransfiniteSurface(surf)
                model.mesh.setRecombine(2, surf)
                xmin, ymin, zmin, xmax, ymax, zmax = model.getBoundingBox(2, surf)
                if xmax - xmin < tol:
                    faces["clamp_left" if xmax < 0.5 * L else "clamp_right"].append(surf)
                elif half and ymax - ymin < tol and ymin > 0.5 * W:
                    faces["sym_y"].append(surf)
            ((_, vol),) = model.getEntities(3)
            model.mesh.setTransfiniteVolume(vol)
            model.mesh.setRecombine(3, vol)
            model.addPhysicalGroup(3, [vol], 1, "kapton")
            names = ["clamp_left", "clamp_right"] + (["sym_y"] if half else [])
            for tag, name in enumerate(names, start=1):
                model.addPhysicalGroup(2, faces[name], tag, name)
            model.mesh.generate(3)
        data, cells, facets = to_dolfinx(model, comm)
    info = {
        "length": L,
        "width": s.width,
        "thickness": t,
        "element_size": L / nx,
        "divisions": (nx, ny, nz),
        "level": m.level,
        "symmetry": m.symmetry,
        "symmetry_factor": 2 if half else 1,
    }
    return TaggedMesh(data.mesh, data.cell_tags, data.facet_tags, cells, facets, info)
