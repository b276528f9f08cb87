"""The robotic surface of seed 001 (Fig. 4) in 3D finite strain: the FE gridshell problem (issue 14,
"Physics and routes"): the prescribed-lambda route (:class:`GridshellFE`, the paper's simulation
route). The heated route (coil currents per strip through the Joule-heated heat equation) is
:class:`lcefem.solvers.problems.gridshell_heated.HeatedGridshellFE`; the mesh-to-mesh transfer of
:meth:`GridshellFE.prolong_from` is :func:`lcefem.solvers.transfer.prolong_by_tag`.

Mesh: :func:`lcefem.meshes.gridshell_fe.build_gridshell_fe` (per-strip cell tags, groups, channels).
Physics: the FE composite beam's (:mod:`lcefem.solvers.problems.composite_beam`), generalised from
two strips to 48 and from one strip direction to two:

* Kapton ribbons: compressible neo-Hookean, datasheet E and nu (``FEMaterials.kapton``).
* LCE strips: W(F U(a)^-1) of :mod:`lcefem.models.hyperelastic` with
  U(a) = a n(x)n + a^-1/2 (I - n(x)n) (:func:`lcefem.models.lce.isochoric_uniaxial`),
  a = lambda/lambda_N the strip's length relative to the as-built (nematic) state and n its own
  ribbon direction (e_x for x strips, e_y for y strips). lambda is a cell-wise (DG0) field, so every
  strip tag is its own drive and the forms are compiled once.
* Bond pads (LCE under the tabs, junctions and crowns): the same law with a = 1 (passive, as the
  beam's); glue squares where the top strips cross: a stiff neo-Hookean block (the published
  model's glue bars, E = 1e4 MPa).
* Strip-ribbon frictionless penalty contact:
  :func:`lcefem.solvers.problems.composite_beam.make_contacts`.
* Supports (:class:`GridshellSupports`): mirror planes of the reduced model (u_n = 0) plus either
  the published perimeter rollers (dome, cylinder, table: u_z = 0 at the outer ribbons' end corners,
  8 in the full surface) or the published saddle clamp (the centre junction's corners held);
  in-plane rigid-body motion removed as the published script does when a mirror plane does not; or
  the experiment's table ('table': the surface's weight and frictionless unilateral penalty contact
  of its lowest faces, the bottom strips and pads, with a rigid plane,
  :class:`lcefem.solvers.contact.RigidPlaneContact`; only the in-plane rigid-body motion removed).
  Optional gravity (always on the table): the surface's 33 g (seed 001) spread uniformly over its
  volume.

The ramp from the current to the target lambdas uses the project's path follower (secant or
tangent predictor, step cutting, damped relaxation across folds).

Observables (:meth:`GridshellFE.observables`), keys "name [unit]": the paper's two centre-curvature
measures through :func:`lcefem.solvers.analysis.curvature.gridshell_curvatures` (circle through the
apex and the two ends of the middle ribbon in x and y; quadratic surface through the junction
centres), on the same stations as the bar-and-hinge gridshell: ribbon mid-surface points at the
junction corners and at the ribbons' ends (x or y = 0 and 141 mm, the published ribbon ends; the FE
mesh's flat end tabs lie beyond them). Points outside a reduced model are the mirror images of
points inside it. Sign: positive for a bowl, negative for a dome (seed 001, Fig. 4).

Units: mm, N, MPa, mJ (README).

Materials, contact construction, Newton options and the lambda check are the composite beam's
(:mod:`lcefem.solvers.problems.composite_beam`, :mod:`lcefem.models.bar_hinge_materials`).
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import pathlib
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from types import SimpleNamespace

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from mpi4py import MPI
from petsc4py import PETSc

import numpy as np
import ufl

import dolfinx
import dolfinx.fem.petsc
import dolfinx.io

from lcefem.meshes.composite_beam import CompositeBeamGeometry
from lcefem.meshes.gridshell_fe import (
    GridshellFEMesh,
    build_gridshell_fe,
    cell_group,
    strip_catalogue,
)
from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N, GlueBars
from lcefem.models.errors import InputError
from lcefem.models.hyperelastic import NeoHookeanSolid, lce_strain_energy, neo_hookean_strain_energy
from lcefem.models.lce import isochoric_uniaxial
from lcefem.models.loads import SurfaceWeight
from lcefem.models.parameters import check, param
from lcefem.solvers.analysis.curvature import gridshell_curvatures
from lcefem.solvers.contact import (
    NodalDamping,
    NodalLoad,
    PenaltyContact,
    RigidPlaneContact,
    attach,
    plane_face_nodes,
)
from lcefem.solvers.continuation import PathControl, PathFollower
from lcefem.solvers.exports import write_snapshot
from lcefem.solvers.mechanics import (
    QUADRATURE_DEGREE,
    HyperelasticProblem,
    assemble_global,
    deformation_gradient,
    displacement_space,
    volume_measure,
)
from lcefem.solvers.problems.composite_beam import (
    BEAM_NEWTON,
    FEMaterials,
    check_lambda,
    make_contacts,
)
from lcefem.solvers.problems.protocol import (
    LOAD,
    StepRecord,
    check_quasi_static_step,
    copy_arrays,
    put_arrays,
)
from lcefem.solvers.transfer import prolong_by_tag

PUBLISHED = (
    "published reduced-order model (Daraio-lab/RoboticSurface_SciRob_LiuK, Examples2D.m; "
    "shared/reference/published_reduced_model.md)"
)
_prefix = itertools.count()
#: Standard gravity [mm/s^2] (m/s^2 x 1e3: lengths in mm).
STANDARD_GRAVITY = 9.80665e3
#: First trial step of :meth:`GridshellFE.settle`'s residual homotopy [-] (chosen: a tenth of the
#: start's residual per step; the whole offset at once is full Newton from the start state, which
#: at level 1 of the dome went 55 -> 919 -> 27 -> 1e4 N to an inverted element).
SETTLE_FIRST_STEP = 0.1
#: Fill-reducing ordering of the gridshell's LDL^T: MUMPS's PORD (ICNTL(7) = 4) instead of its
#: automatic choice (METIS here). The factorisations are ~60 % of a ramp's time (Jacobian assembly
#: ~30 %; the symbolic analysis runs once per model, MUMPS reuses it at every Newton iteration):
#: one dome tangent at level 0 (26,904 DOFs, t = 0.05) 1.75e9 -> 1.27e9 flops (RINFOG(3)),
#: numeric factorisation 0.216 -> 0.177 s CPU; QAMD/AMD 1.57e9, AMF 1.61e9, SCOTCH 1.88e9
#: (level 1: 1.53e10 -> 1.27e10 flops, 1.54 -> 1.34 s CPU); level-0 dome ramp 46.3 -> 40.5 s CPU
#: (benchmarks/gridshell_fe_speed.py, docs/performance.md). The answer moves by the
#: round-off of another elimination order only: the dome's circle curvature by 3e-13 1/mm.
GRIDSHELL_ORDERING = {"mat_mumps_icntl_7": 4}
#: Support kinds of :class:`GridshellSupports`.
SUPPORT_KINDS = ("rollers", "centre_clamp", "table")


@dataclass(frozen=True)
class GridshellMaterials(FEMaterials):
    """The FE beam's materials (Kapton, LCE) plus the glue squares where the top strips cross."""

    # E of the published glue bars (models.bar_hinge_materials.GlueBars, 1e4 MPa); nu = 0.34 chosen
    # as Kapton's. 2e4 times stiffer than the LCE: the raised square is effectively rigid.
    glue: NeoHookeanSolid = field(
        default_factory=lambda: NeoHookeanSolid(youngs_modulus=GlueBars().youngs_modulus)
    )


@dataclass(frozen=True)
class GridshellSupports:
    """How the surface is held."""

    kind: str = param(
        "rollers",
        "-",
        PUBLISHED + ": 'rollers' (dome, cylinder, table: u_z = 0 at "
        "the outer ribbons' end corners, 8 in all) or 'centre_clamp' (saddle: the "
        "centre junction's four corners clamped); seed 001's experiment: 'table' "
        "(the surface lies on a rigid table: its weight, frictionless unilateral "
        "contact of its lowest faces with the plane, in-plane rigid-body motion "
        "removed as by the rollers, nothing else held)",
    )
    gravity: bool = param(
        False,
        "-",
        "chosen: the published simulations have no gravity; True "
        "loads the surface with its weight (always on for kind = 'table')",
    )
    table_stiffness: float = param(
        50.0,
        "N/mm^3",
        "chosen: the strip-ribbon contact's penalty "
        "(solvers.contact.PenaltyContact.stiffness): the 33 g rest on "
        "the table with ~1e-5 mm penetration",
        positive=True,
    )
    mass: float = param(
        SurfaceWeight().total_mass,
        "t",
        "seed 001: 33 g (models.loads.SurfaceWeight), spread uniformly over the gridshell's volume",
        positive=True,
    )

    def checked(self) -> "GridshellSupports":
        check(self, "supports")
        if self.kind not in SUPPORT_KINDS:
            raise InputError(
                f"supports.kind = {self.kind!r}: allowed "
                + ", ".join(repr(k) for k in SUPPORT_KINDS)
            )
        return self

    @property
    def weight(self) -> bool:
        """Whether the surface carries its weight."""
        return self.gravity or self.kind == "table"


@dataclass(frozen=True)
class GridshellConfig:
    """Everything a :class:`GridshellFE` is built from (units in each dataclass)."""

    geometry: CompositeBeamGeometry = field(default_factory=CompositeBeamGeometry)
    mesh: GridshellFEMesh = field(default_factory=GridshellFEMesh)
    cells: int = param(3, "-", "seed 001: the 3 x 3 grid (ribbons per direction)", minimum=1)
    symmetry: str = param(
        "quarter",
        "-",
        "reduced model (meshes.gridshell_fe.RECIPE_SYMMETRY): "
        "'quarter', 'half_x', 'half_y' or 'full'",
    )
    lambda_N: float = param(
        PUBLISHED_LAMBDA_N,
        "-",
        PUBLISHED + ": as-built (nematic) stretch relative to the isotropic length",
        minimum=1.0,
    )
    materials: GridshellMaterials = field(default_factory=GridshellMaterials)
    supports: GridshellSupports = field(default_factory=GridshellSupports)
    contact: PenaltyContact = field(default_factory=PenaltyContact)
    control: PathControl = field(default_factory=PathControl)


def lce_strip_energy(F, a, director, law):
    """W(F U(a)^-1) [mJ/mm^3] of an LCE strip at relative length a = lambda/lambda_N along its unit
    director (UFL; U^-1 = U(1/a) in closed form), as the FE beam's strips."""
    return lce_strain_energy(F * isochoric_uniaxial(1.0 / a, director), law)


def von_mises(P, F):
    """Von Mises equivalent [MPa] of the Cauchy stress sigma = P F^T / det F (UFL)."""
    sigma = P * F.T / ufl.det(F)
    s = ufl.dev(sigma)
    return ufl.sqrt(1.5 * ufl.inner(s, s))


@dataclass
class GridshellState:
    """One converged state of a ramp."""

    load_factor: float  # [-] path parameter t of the ramp
    iterations: int  # Newton iterations of the step
    observables: dict  # "name [unit]" -> value


class GridshellFE:
    """The FE gridshell (module docstring): forms compiled once; drives are the strips' lambda.

    Build: ``GridshellFE(GridshellConfig(...))``. Drive: :meth:`set_drives` with a strip tag
    (``bottom_x_r1_s2``), a group (``XD1``..``YU3``, ``top_x_r1_j1``) or a channel (Tx, Ty, Bx, By).
    Solve: :meth:`advance` (to the targets set) or :meth:`ramp` (set and advance). Observe:
    :meth:`observables`, :meth:`junction_centres`. Output: :meth:`write_fields`.
    """

    def __init__(
        self,
        config: GridshellConfig = GridshellConfig(),
        comm: MPI.Comm | None = None,
        petsc_options: dict | None = None,
    ):
        self.config = cfg = config
        supports = cfg.supports.checked()
        self.lambda_N = lam_n = float(cfg.lambda_N)
        self.tmesh = tm = build_gridshell_fe(
            cfg.geometry, lam_n, cfg.mesh, comm, cells=cfg.cells, symmetry=cfg.symmetry
        )
        self.info = tm.info
        msh = tm.mesh
        self.comm = msh.comm  # the runner claims and writes a run's folder on every rank together
        self.V = V = displacement_space(msh, 2)
        self.u = u = dolfinx.fem.Function(V, name="displacement")
        # cell-wise drive and director (DG0): one value per cell, set per strip tag
        self.V0 = V0 = dolfinx.fem.functionspace(msh, ("DG", 0))
        self.lam = dolfinx.fem.Function(V0, name="lambda")
        self.director = dolfinx.fem.Function(
            dolfinx.fem.functionspace(msh, ("DG", 0, (3,))), name="director"
        )
        ncells = msh.topology.index_map(3).size_local + msh.topology.index_map(3).num_ghosts
        cell_values = np.zeros(ncells, dtype=np.int32)
        cell_values[tm.cell_tags.indices] = tm.cell_tags.values
        self._cell_dof = V0.dofmap.list[:, 0]  # DG0 dof of each cell
        self._dof_tag = np.zeros(self.lam.x.array.size, dtype=np.int32)
        self._dof_tag[self._cell_dof] = cell_values
        self.lam.x.array[:] = lam_n
        dirs = self.director.x.array.reshape(-1, 3)
        # the two ribbon families' unit vectors in the plane (a rhombic mesh: e2 = (cos a, sin a))
        families = np.asarray(tm.info.get("directions", ((1.0, 0.0), (0.0, 1.0))))
        for channel, axis in (("Bx", 0), ("Tx", 0), ("By", 1), ("Ty", 1)):
            if channel in tm.info["cell_groups"]:
                dirs[np.isin(self._dof_tag, cell_group(tm, channel)), :2] = families[axis]
        self.target = self.lam.x.array.copy()
        self.strip_tags = {name: tm.cell_tag(name) for name in tm.info["strips"]}
        self._all_strips = strip_catalogue(cfg.geometry, cfg.cells, tm.info["strip_width"])

        # energy: every term compiled once; only lam (and the gravity Constant) change
        mats = cfg.materials
        F = deformation_gradient(u)
        dx = volume_measure(tm, QUADRATURE_DEGREE)
        strips = cell_group(tm, "bottom_strips") + cell_group(tm, "top_strips")
        pads = tuple(
            t
            for g in ("bottom_pads", "top_pads")
            if g in tm.info["cell_groups"]
            for t in cell_group(tm, g)
        )
        glue = cell_group(tm, "glue") if "glue" in tm.info["cell_groups"] else ()
        a = self._strip_stretch_ratio(u)
        densities = {
            "kapton": (neo_hookean_strain_energy, mats.kapton, cell_group(tm, "kapton")),
            "lce": (lambda G, law: lce_strip_energy(G, a, self.director, law), mats.lce, strips),
            "pads": (lce_strain_energy, mats.lce, pads),  # passive: a = 1, the beam's
            "glue": (neo_hookean_strain_energy, mats.glue, glue),
        }
        energy = sum(w(F, law) * dx(tags) for w, law, tags in densities.values() if tags)
        self.volume = assemble_global(dolfinx.fem.form(1.0 * dx), msh.comm)  # [mm^3], model
        self.gravity = dolfinx.fem.Constant(msh, np.zeros(3, dtype=PETSc.ScalarType))  # [N/mm^3]
        self._weight_density = (
            supports.mass * STANDARD_GRAVITY / (self.volume * tm.info["symmetry_factor"])
        )
        if supports.weight:
            energy = energy - ufl.dot(self.gravity, u) * dx
        self.gravity_on = 0.0  # fraction of the weight applied

        self._X = V.tabulate_dof_coordinates()  # reference node positions [mm] (owned, then ghosts)
        self._owned_nodes = V.dofmap.index_map.size_local  # nodes (blocks) this rank owns
        self.bcs = self._supports(supports)
        # the FE beam's Newton settings; no divergence test: from u = 0 the first full step may
        # push strips through the ribbon (contact closes only at the next iterate), raising the
        # residual far above its small initial value before Newton converges
        # Direct LDL^T at every size unless the options name a pc_type: the automatic iterative path
        # above ITERATIVE_PATH_DOFS was measured on the strip only, never with contact and the thin
        # Kapton; the finest dome level used so far (3, 369k DOFs) factorised in 3.2 GB.
        options = {**BEAM_NEWTON, "pc_type": "cholesky"}
        options.update(petsc_options or {})
        if (
            options["pc_type"] == "cholesky"
            and options.get("pc_factor_mat_solver_type", "mumps") == "mumps"
        ):
            options = {**GRIDSHELL_ORDERING, **options}  # the caller's own ordering wins
        self.problem = HyperelasticProblem(
            u,
            energy,
            self.bcs,
            prefix=f"lcefem_gridshell{next(_prefix)}_",
            petsc_options=options,
            user_options=tuple(petsc_options or ()),
        )
        self.problem.snes.setDivergenceTolerance(1e30)
        self.contacts = make_contacts(tm, u, cfg.contact)
        self.table = None
        if supports.kind == "table":  # the lowest faces (bottom strips and pads) rest on it
            z0 = float(msh.comm.allreduce(self._X[:, 2].min(), op=MPI.MIN))
            nodes, areas = plane_face_nodes(V, z0)
            self.table = RigidPlaneContact(u, nodes, areas, z0, supports.table_stiffness)
        self.damping = NodalDamping(u)  # proximal term of the path follower's relaxation at folds
        self.offset = NodalLoad(u)  # the residual homotopy's offset (settle); off otherwise
        attach(
            self.problem,
            [*self.contacts, *([self.table] if self.table else []), self.damping, self.offset],
        )

        # stress measure for output: von Mises of the Cauchy stress, cell-wise (DG0), per material
        Fv = ufl.variable(F)
        self.stress = dolfinx.fem.Function(V0, name="von_mises_stress")
        self._stress_exprs = []
        points = V0.element.interpolation_points
        for w, law, tags in densities.values():
            if not tags:
                continue
            W = w(Fv, law)
            expr = dolfinx.fem.Expression(von_mises(ufl.diff(W, Fv), Fv), points)
            cells = np.flatnonzero(np.isin(cell_values, tags)).astype(np.int32)
            self._stress_exprs.append((expr, cells))

        self._stations = self._make_stations()
        self.ndofs = V.dofmap.index_map.size_global * V.dofmap.index_map_bs
        self.last_follower = None
        self.wall_time = 0.0  # [s] spent in ramps

    def _strip_stretch_ratio(self, u):
        """a = lambda/lambda_N of the strips (UFL): the prescribed cell-wise lambda (this route)."""
        return self.lam / self.lambda_N

    # ------------------------------------------------------------------ supports
    def _nodes_at(self, xy, tol: float = 1e-6) -> np.ndarray:
        """Ribbon nodes (block indices) through the thickness at in-plane point ``xy`` [mm] (the
        ribbon is flat there: junctions, segment ends, tabs); ``xy`` in the mesh builder's
        coordinates, mapped x e1 + y e2 on a rhombic mesh (info["directions"])."""
        X = self._X
        if "directions" in self.info:
            xy = np.asarray(xy[:2], dtype=float) @ np.asarray(self.info["directions"])
        half = 0.5 * self.info["ribbon_thickness"] + tol
        hit = np.flatnonzero(
            (np.abs(X[:, 0] - xy[0]) < tol)
            & (np.abs(X[:, 1] - xy[1]) < tol)
            & (np.abs(X[:, 2]) <= half)
        )
        return hit

    def _supports(self, supports: GridshellSupports) -> list:
        tm, V, info = self.tmesh, self.V, self.info
        fdim = tm.mesh.topology.dim - 1
        tm.mesh.topology.create_connectivity(fdim, tm.mesh.topology.dim)
        zero = PETSc.ScalarType(0.0)
        bcs = []
        mirrors = [(name, comp) for name, comp in (("sym_x", 0), ("sym_y", 1)) if name in tm.facets]
        for name, comp in mirrors:
            facets = tm.facet_tags.find(tm.facet_tag(name))
            dofs = dolfinx.fem.locate_dofs_topological(V.sub(comp), fdim, facets)
            bcs.append(dolfinx.fem.dirichletbc(zero, dofs, V.sub(comp)))
        mirrored = {comp for _, comp in mirrors}
        held: dict[int, list[int]] = {0: [], 1: [], 2: []}
        if supports.kind in ("rollers", "table"):
            vertical = [2] if supports.kind == "rollers" else []  # the table carries it by contact
            for xy, comps in self._roller_points():
                nodes = self._nodes_at(xy)
                if nodes.size == 0:
                    continue  # outside this reduced model: its mirror image holds
                for comp in vertical + [k for k in comps if k not in mirrored]:
                    held[comp] += list(nodes)
        else:
            for corner in info["centre_junction_corners"]:
                nodes = self._nodes_at(corner[:2])
                for comp in range(3):
                    held[comp] += list(nodes)
        self.support_nodes = {
            comp: np.unique(np.asarray(v, dtype=np.int32)) for comp, v in held.items()
        }
        held_z = tm.mesh.comm.allreduce(
            int(self.support_nodes[2].size), op=MPI.SUM
        )  # over the ranks
        if held_z == 0 and supports.kind != "table":
            raise InputError(
                f"supports.kind = {supports.kind!r}: no support point in the "
                f"{info['symmetry']} model"
            )
        for comp, nodes in self.support_nodes.items():
            # on every rank if on any: collapse() is collective (a rank without such a node
            # skipped it and deadlocked the others under mpiexec)
            if tm.mesh.comm.allreduce(int(nodes.size), op=MPI.SUM):
                dofs = self._component_dofs(comp, nodes)
                bcs.append(dolfinx.fem.dirichletbc(zero, dofs, V.sub(comp)))
        return bcs

    def _component_dofs(self, comp: int, nodes: np.ndarray) -> np.ndarray:
        """DOFs of component ``comp`` (of V.sub(comp)) at the given nodes (block indices)."""
        Vc, _ = self.V.sub(comp).collapse()
        pts = self._X[nodes]

        def marker(x):
            if pts.size == 0:  # none on this rank
                return np.zeros(x.shape[1], dtype=bool)
            d = np.min(np.linalg.norm(x.T[:, None, :] - pts[None, :, :], axis=2), axis=1)
            return d < 1e-6

        return dolfinx.fem.locate_dofs_geometrical((self.V.sub(comp), Vc), marker)[0]

    def _roller_points(self) -> list[tuple[tuple[float, float], tuple[int, ...]]]:
        """The published 8 rollers (full-model (x, y) [mm], extra in-plane components held): the
        outer ribbons' end corners on the perimeter side, at the FE ribbon ends (beyond the tabs).
        In-plane rigid-body motion as the published script: the first u_x, u_y, the second u_x,
        the third u_y (dropped where a mirror plane holds that component)."""
        info = self.info
        n, W = info["cells_per_direction"], info["ribbon_width"]
        c = info["junction_centres"]
        lo, hi = -info["end_tab"], info["ribbon_length"] + info["end_tab"]
        edge_lo, edge_hi = c[0] - 0.5 * W, c[n - 1] + 0.5 * W  # outer edges of the outer ribbons
        pts = [
            ((edge_lo, lo), (0, 1)),
            ((edge_lo, hi), (0,)),
            ((edge_hi, lo), (1,)),
            ((edge_hi, hi), ()),  # y ribbons' ends
            ((hi, edge_lo), ()),
            ((hi, edge_hi), ()),
            ((lo, edge_lo), ()),
            ((lo, edge_hi), ()),
        ]
        return pts

    # ------------------------------------------------------------------ drives
    def _tags_of(self, selector: str) -> tuple[int, ...]:
        """Strip cell tags of a strip tag, group or channel name."""
        groups = self.info["cell_groups"]
        if selector in self.strip_tags:
            return (self.strip_tags[selector],)
        if selector in groups:
            tags = groups[selector]
            if not set(tags) <= set(self.strip_tags.values()):
                raise InputError(f"drive {selector!r}: not a group of LCE strips (a material)")
            return tags
        if selector in self._all_strips or _is_full_group(selector, self.config.cells):
            raise InputError(
                f"drive {selector!r}: lies outside the {self.info['symmetry']} model "
                "(its mirror image carries the same drive); drive a channel or a "
                "piece inside the model"
            )
        raise InputError(
            f"drive {selector!r}: not a strip tag, group (XD1..YU3) or channel (Tx, Ty, Bx, By)"
        )

    def _set_lambda(self, drives: Mapping[str, float]) -> None:
        """Target spontaneous stretches lambda [-] (relative to the isotropic length; as built:
        lambda_N) per strip tag, group or channel, applied in the mapping's order (a later key
        overrides an earlier one on shared strips); reached by :meth:`advance`."""
        for selector, value in drives.items():
            lam = check_lambda(f"lambda[{selector}]", value, self.lambda_N)
            self.target[np.isin(self._dof_tag, self._tags_of(selector))] = lam

    def lambda_of(self, selector: str, target: bool = False) -> np.ndarray:
        """Distinct lambda values [-] (current, or the targets) on the cells of a selector."""
        arr = self.target if target else self.lam.x.array
        return np.unique(arr[np.isin(self._dof_tag, self._tags_of(selector))])

    def advance(
        self, dt: float = 1.0, *, on_step: Callable[[GridshellState], None] | None = None
    ) -> StepRecord:
        """Take every strip linearly from its current lambda to its target (path parameter
        t: 0 -> 1; ``dt`` < 1 stops at that fraction of the way; with gravity on, its weight rises
        with t on the first ramp) with the path follower. Raises ConvergenceError (the model keeps
        the last converged state). The record's ``detail``: one :class:`GridshellState` per
        accepted step."""
        dt = check_quasi_static_step(dt)
        lam0 = self.lam.x.array.copy()
        dlam = dt * (self.target - lam0)
        g0 = self.gravity_on
        g1 = g0 + dt * (self._full_weight() - g0)

        def set_load(t: float) -> None:
            self.lam.x.array[:] = lam0 + t * dlam
            self._set_weight(g0 + t * (g1 - g0))

        states = self._follow(set_load, self.config.control, "gridshell ramp", on_step)
        self.lam.x.array[:] = (
            self.target if dt == 1.0 else lam0 + dlam
        )  # exactly, not lam0 + 1.0 * dlam
        follower = self.last_follower
        return StepRecord(
            dt,
            states[-1].observables if states else self.observables(),
            follower.iterations,
            follower.cuts,
            clock=LOAD,
            detail=states,
        )

    def ramp(self, drives: Mapping[str, float], **kw) -> list[GridshellState]:
        """:meth:`set_drives` then :meth:`advance`; the states of the ramp."""
        self._set_lambda(drives)
        return self.advance(**kw).detail

    def settle(
        self,
        first_step: float = SETTLE_FIRST_STEP,
        on_step: Callable[[GridshellState], None] | None = None,
    ) -> list[GridshellState]:
        """Equilibrium at the target lambdas (and the full weight, if any) from the current
        displacement u_0, e.g. one prolonged from a coarser mesh (:meth:`prolong_from`) or the
        equilibrium of other materials, which is no equilibrium here: the residual homotopy

            R(u) - (1 - s) R(u_0) = 0,   s: 0 -> 1,

        (R the nodal force residual [N]; u_0 solves it at s = 0 exactly, an equilibrium solves it
        at s = 1) followed by the path follower of the ramps (predictor, step cuts; first trial
        step ``first_step``, growing to the whole remainder), the offset a :class:`NodalLoad`.
        Each step moves the offset by a fraction of R(u_0), so the path stays on the branch u_0
        lies near, where full Newton steps from u_0 at the full load can jump to another (README,
        "The full-ramp study with --prolong"). Raises ConvergenceError as :meth:`advance`;
        InputError when u_0 is not finite or inverts an element."""
        if not 0.0 < first_step <= 1.0:
            raise InputError(f"settle: first_step = {first_step}: must lie in (0, 1]")
        self.lam.x.array[:] = self.target
        self._set_weight(self._full_weight())
        for bc in self.bcs:  # the supports hold exactly (u_0 may carry round-off there)
            bc.set(self.u.x.array)
        self.u.x.scatter_forward()
        if not self.problem.admissible():
            raise InputError("settle: the start state is not finite or inverts an element")
        self.offset.force[:] = self.residual()

        def set_load(s: float) -> None:
            self.offset.factor = 1.0 - s

        control = dataclasses.replace(self.config.control, first_step=first_step, max_step=1.0)
        try:
            return self._follow(set_load, control, "gridshell settle (residual homotopy)", on_step)
        finally:
            self.offset.factor = 0.0

    def residual(self) -> np.ndarray:
        """The nodal force residual R(u) [N] at the current state and load (every term: volume,
        contact, table; zero on the supported DOFs when u meets the supports)."""
        b = self.problem.snes.getFunction()[0]
        x, r = b.duplicate(), b.duplicate()
        try:
            dolfinx.fem.petsc.assign(self.u, x)
            self.problem.snes.computeFunction(x, r)
            return r.array.copy()
        finally:
            x.destroy()
            r.destroy()

    def _full_weight(self) -> float:
        """Weight fraction at the end of a ramp [-]."""
        return 1.0 if self.config.supports.weight else 0.0

    def _set_weight(self, fraction: float) -> None:
        self.gravity_on = fraction
        self.gravity.value = fraction * np.array([0.0, 0.0, -self._weight_density])

    def _follow(
        self,
        set_load: Callable[[float], None],
        control: PathControl,
        where: str,
        on_step: Callable[[GridshellState], None] | None,
    ) -> list[GridshellState]:
        """The path follower from t = 0 (the current state) to 1 at ``set_load(t)``; one
        :class:`GridshellState` per accepted step (``on_step`` called with it)."""
        follower = PathFollower(self.problem, set_load, control, self.damping)
        states: list[GridshellState] = []

        def record(t: float, its: int) -> None:
            states.append(GridshellState(t, its, self.observables()))
            if on_step is not None:
                on_step(states[-1])

        started = time.perf_counter()
        try:
            follower.follow(1.0, where=where, on_step=record)
        finally:
            self.wall_time += time.perf_counter() - started
            self.last_follower = follower
        return states

    # ------------------------------------------------------------------ mesh transfer
    def save_state(self, path=None) -> pathlib.Path | dict:
        """The converged state (displacement, lambda per strip tag, weight fraction) and the mesh
        it lives on (level, layers, symmetry; DOF coordinates to check the rebuild) as ``.npz``,
        written atomically; read back by :meth:`prolong_from` on a finer mesh (serial). Without a
        path: an in-memory copy for :meth:`restore_state` (the Problem protocol)."""
        if path is None:
            return self.memory_state()
        path = pathlib.Path(path)
        m = self.config.mesh
        tags = np.asarray(sorted(self.strip_tags.values()), dtype=np.int32)
        lam = np.array([self._tag_value(self.lam.x.array, t) for t in tags])
        tmp = path.with_name(path.name + ".part.npz")
        np.savez(
            tmp,
            u=self.u.x.array,
            dof_coordinates=self._X,
            strip_tags=tags,
            strip_lambda=lam,
            gravity_on=self.gravity_on,
            level=m.level,
            ribbon_layers=m.ribbon_layers,
            strip_layers=m.strip_layers,
            symmetry=self.config.symmetry,
            cells=self.config.cells,
        )
        tmp.replace(path)
        return path

    def _tag_value(self, array: np.ndarray, tag: int) -> float:
        values = np.unique(array[self._dof_tag == tag])
        if values.size != 1:
            raise RuntimeError(f"strip tag {tag}: {values.size} lambda values, expected one")
        return float(values[0])

    def prolong_from(self, path) -> None:
        """Take the state saved by :meth:`save_state` (a coarser mesh of the same surface, model and
        layers) as this model's current state: the displacement interpolated material by
        material (:func:`prolong_by_tag`), each strip tag's lambda (current and target) and the
        weight fraction. Then :meth:`settle` finds the equilibrium on this mesh."""
        with np.load(path) as data:
            saved = {k: data[k] for k in data.files}
        mine = {
            "ribbon_layers": self.config.mesh.ribbon_layers,
            "strip_layers": self.config.mesh.strip_layers,
            "symmetry": self.config.symmetry,
            "cells": self.config.cells,
        }
        for key, value in mine.items():
            if saved[key].item() != value:
                raise InputError(
                    f"prolong_from {path}: {key} = {saved[key].item()!r}, this model has {value!r}"
                )
        if self.tmesh.mesh.comm.size > 1:
            raise InputError("prolong_from: serial only (the saved DOF order is one process's)")
        cfg = self.config
        mesh0 = dataclasses.replace(cfg.mesh, level=int(saved["level"]))
        tm0 = build_gridshell_fe(
            cfg.geometry,
            self.lambda_N,
            mesh0,
            MPI.COMM_SELF,
            cells=cfg.cells,
            symmetry=cfg.symmetry,
        )
        u0 = dolfinx.fem.Function(displacement_space(tm0.mesh, 2))
        X0 = u0.function_space.tabulate_dof_coordinates()
        if X0.shape != saved["dof_coordinates"].shape or not np.allclose(
            X0, saved["dof_coordinates"], rtol=0.0, atol=1e-9
        ):
            raise InputError(
                f"prolong_from {path}: the rebuilt level-{mesh0.level} mesh does not "
                "match the saved DOF coordinates"
            )
        u0.x.array[:] = saved["u"]
        self.u.x.array[:] = prolong_by_tag(u0, tm0.cell_tags, self.V, self.tmesh.cell_tags).ravel()
        self.u.x.scatter_forward()
        for tag, lam in zip(saved["strip_tags"], saved["strip_lambda"]):
            self.lam.x.array[self._dof_tag == tag] = lam
        self.target = self.lam.x.array.copy()
        self._set_weight(float(saved["gravity_on"]))

    # ------------------------------------------------------------------ observables
    def _make_stations(self) -> SimpleNamespace:
        """Reference stations (full-model (x, y) [mm]) of the curvature measures, laid out as the
        bar-and-hinge structure's node sets so that :func:`gridshell_curvatures` applies."""
        info = self.info
        n, W = info["cells_per_direction"], info["ribbon_width"]
        c = np.asarray(info["junction_centres"])
        h = 0.5 * W
        length = info["ribbon_length"]
        xy, index = [], {}

        def station(p) -> int:
            key = (round(float(p[0]), 9), round(float(p[1]), 9))
            if key not in index:
                index[key] = len(xy)
                xy.append(key)
            return index[key]

        corners = ((-h, -h), (h, -h), (h, h), (-h, h))  # order of the centre frame (x edge first)
        jc = np.array(
            [
                [[station((c[i] + a, c[j] + b)) for a, b in corners] for j in range(n)]
                for i in range(n)
            ]
        )
        ends_x = np.array(
            [[[station((e, c[r] + s)) for s in (-h, h)] for e in (0.0, length)] for r in range(n)]
        )
        ends_y = np.array(
            [[[station((c[r] + s, e)) for s in (-h, h)] for e in (0.0, length)] for r in range(n)]
        )
        mid = n // 2
        structure = SimpleNamespace(
            nodes=None,
            info={"ribbons": n},
            node_sets={
                "junction_corners": jc,
                "centre_junction": jc[mid, mid],
                "ribbon_ends_x": ends_x,
                "ribbon_ends_y": ends_y,
            },
        )
        # each station: model nodes of its mirror image inside the model, and the reflection
        centre = info["centre"]
        cut_x, cut_y = "sym_x" in self.tmesh.facets, "sym_y" in self.tmesh.facets
        nodes, flips = [], []
        for x, y in xy:
            fx, fy = cut_x and x < centre - 1e-9, cut_y and y < centre - 1e-9
            p = (2 * centre - x if fx else x, 2 * centre - y if fy else y)
            # the nodes this rank owns (a ghost is another rank's: counted once over the ranks)
            found = self._nodes_at(p)
            found = found[found < self._owned_nodes]
            if self.tmesh.mesh.comm.allreduce(int(found.size), op=MPI.SUM) == 0:
                raise RuntimeError(f"no ribbon node at station {p}")
            nodes.append(found)
            flips.append((fx, fy))
        return SimpleNamespace(structure=structure, nodes=nodes, flips=flips, centre=centre)

    def station_positions(self) -> np.ndarray:
        """Deformed stations (m, 3) [mm]: ribbon mid-surface (mean through the thickness), mirror
        images for stations outside a reduced model."""
        s = self._stations
        x = self._X + self.u.x.array.reshape(-1, 3)
        # sums and counts of the owned nodes of each station, added over the ranks (serial: the
        # mean)
        sums = np.array([np.append(x[nodes].sum(axis=0), nodes.size) for nodes in s.nodes]).reshape(
            -1, 4
        )
        sums = self.tmesh.mesh.comm.allreduce(sums, op=MPI.SUM)
        out = np.empty((len(s.nodes), 3))
        for k, (fx, fy) in enumerate(s.flips):
            p = sums[k, :3] / sums[k, 3]
            if fx:
                p[0] = 2 * s.centre - p[0]
            if fy:
                p[1] = 2 * s.centre - p[1]
            out[k] = p
        return out

    def junction_centres(self) -> np.ndarray:
        """Deformed junction centres (n, n, 3) [mm] (mean of each junction's mid-surface corners;
        index [i, j]: i along x, j along y)."""
        x = self.station_positions()
        return x[self._stations.structure.node_sets["junction_corners"]].mean(axis=2)

    def observables(self) -> dict[str, float]:
        """Named observables, keys "name [unit]" (module docstring; curvature sign: + bowl, -
        dome)."""
        x = self.station_positions()
        k = gridshell_curvatures(self._stations.structure, x)
        z = (self._X + self.u.x.array.reshape(-1, 3))[:, 2]
        comm = self.tmesh.mesh.comm
        zmin, zmax = (
            comm.allreduce(float(z.min()), op=MPI.MIN),
            comm.allreduce(float(z.max()), op=MPI.MAX),
        )
        jc = self.junction_centres()
        n = jc.shape[0]
        out = {
            "kappa_circle_x [1/mm]": k["circle_x"],
            "kappa_circle_y [1/mm]": k["circle_y"],
            "kappa_quad_x [1/mm]": k.get("quad_kx", math.nan),
            "kappa_quad_y [1/mm]": k.get("quad_ky", math.nan),
            "kappa_quad_1 [1/mm]": k.get("quad_k1", math.nan),
            "kappa_quad_2 [1/mm]": k.get("quad_k2", math.nan),
            "gaussian_quad [1/mm^2]": k.get("gaussian", math.nan),
            "quad_rms_residual [mm]": k.get("rms_residual", math.nan),
            "z_range [mm]": zmax - zmin,  # of the whole deformed body
            "surface_z_range [mm]": float(np.ptp(jc[:, :, 2])),  # of the junction centres
            "apex_z [mm]": float(jc[n // 2, n // 2, 2]),
            "contact_force [N]": self.info["symmetry_factor"]
            * sum(c.normal_force() for c in self.contacts),
        }
        if self.table is not None:  # whole surface: the model's reaction x the symmetry factor
            out["table_force [N]"] = self.info["symmetry_factor"] * self.table.normal_force()
            out["apex_height_above_table [mm]"] = out["apex_z [mm]"] - self.table.height
            out["table_contact_nodes [-]"] = int(np.sum(self.table.active()))
        for i in range(n):
            for j in range(n):
                for axis, name in enumerate("xyz"):
                    out[f"junction_{i}{j}_{name} [mm]"] = float(jc[i, j, axis])
        return out

    # ------------------------------------------------------------------ fields
    def update_stress(self) -> None:
        """Cell-wise von Mises stress [MPa] of the current state into ``self.stress``."""
        for expr, cells in self._stress_exprs:
            self.stress.interpolate(expr, cells0=cells)
        self.stress.x.scatter_forward()

    def _cell_fields(self) -> list[dolfinx.fem.Function]:
        """The DG0 fields of cells.xdmf: lambda [-], von Mises stress [MPa], director."""
        self.update_stress()
        return [self.lam, self.stress, self.director]

    def write_fields(self, folder, t: float = 0.0) -> list[pathlib.Path]:
        """ParaView files of the current state in ``folder``: displacement.bp (Q2, VTX, written as
        .part and renamed) and cells.xdmf (lambda [-], von Mises stress [MPa], director, one value
        per cell)."""
        folder = pathlib.Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        disp = write_snapshot(folder, "displacement.bp", [self.u], t)
        cells = folder / "cells.xdmf"
        with dolfinx.io.XDMFFile(self.tmesh.mesh.comm, cells, "w") as f:
            f.write_mesh(self.tmesh.mesh)
            for fn in self._cell_fields():
                f.write_function(fn, t)
        return [disp, cells]

    # -- the Problem protocol (lcefem.solvers.problems.protocol) --------------------------------
    drive = "lambda [-]"

    def drive_tags(self) -> tuple[str, ...]:
        """Strip tags, then the groups and channels made of strips (:meth:`set_drives`)."""
        strips = set(self.strip_tags.values())
        groups = [g for g, tags in self.info["cell_groups"].items() if tags and set(tags) <= strips]
        return (*self.strip_tags, *groups)

    def set_drives(self, drives: Mapping[str, float]) -> None:
        self._set_lambda(drives)

    def fields(self) -> dict:
        lam, stress, director = GridshellFE._cell_fields(self)
        return {
            "displacement [mm]": self.u,
            "lambda [-]": lam,
            "von Mises stress [MPa]": stress,
            "director [-]": director,
        }

    def memory_state(self) -> dict:
        """What :meth:`advance` changes: displacement, lambda and its targets, weight fraction."""
        return {
            "arrays": copy_arrays([self.u, self.lam]),
            "target": self.target.copy(),
            "gravity_on": self.gravity_on,
        }

    def restore_state(self, state: dict) -> None:
        put_arrays([self.u, self.lam], state["arrays"])
        self.target = state["target"].copy()
        self._set_weight(state["gravity_on"])


def _is_full_group(name: str, n: int) -> bool:
    """A published group (XD1..YU{n}) or channel name of the full model."""
    if name in ("Tx", "Ty", "Bx", "By"):
        return True
    return (
        len(name) >= 3
        and name[0] in "XY"
        and name[1] in "DU"
        and name[2:].isdigit()
        and 1 <= int(name[2:]) <= n
    )


__all__ = [
    "GRIDSHELL_ORDERING",
    "GridshellConfig",
    "GridshellFE",
    "GridshellMaterials",
    "GridshellState",
    "GridshellSupports",
    "SUPPORT_KINDS",
    "lce_strip_energy",
    "von_mises",
]
