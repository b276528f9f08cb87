"""Write a built-in mesh with its named tags for another tool (gmsh, ParaView, a FEniCSx script).

``lcefem mesh NAME --format msh|xdmf|vtu --out DIR [--model fe|bar-hinge] [--mesh-level L]
[--layout NAME|FILE] [--overwrite]``

NAME is a body (``strip``, ``beam``, ``gridshell``, ``ribbon``, ``specimen``) or ``all``. Each mesh
is the one its body builds from its default configuration (the same builder, dimensions and level as
``lcefem run``), in mm:

========= ====================================================== ===============================
NAME      ``--model fe`` (default)                               ``--model bar-hinge``
========= ====================================================== ===============================
strip     the heated LCE strip, quarter (seed 001, Fig. 2)       --
beam      the composite beam, quarter (Fig. 3)                   N5B8 panels, strip and glue bars
gridshell the 3 x 3 robotic surface, quarter (Fig. 4)            N5B8 panels, strip bars
ribbon    the twisted ribbon (60 mm, 3 turns; seed 000)          --
specimen  the Kapton buckling specimen, half (Fig. 2G)           N5B8 panels
========= ====================================================== ===============================

``--layout`` (gridshell only): the gridshell of a layout (:mod:`lcefem.meshes.gridshell_layout`, a
name such as ``5x5`` or ``rhombic60`` or a TOML file with a ``[layout]`` section;
docs/layouts/index.md): the FE mesh made by gmsh from it
(:func:`lcefem.meshes.gridshell_fe_gmsh.build_layout_fe`: quarter on an orthogonal grid, whole on a
rhombic one) or its bar-and-hinge structure; the stem gains the
layout's name (``gridshell_5x5``).

Writes ``DIR/<stem>.<format>`` (stem: NAME, ``<NAME>_bar_hinge`` for the bar-and-hinge model), with
``<stem>.tags.json`` (the name of every tag) for xdmf/vtu and ``<stem>.h5`` for xdmf
(:mod:`lcefem.meshes.io`), then ``summary.json`` (per mesh: files, cells per tag, the builder's
facts). ``all`` writes every mesh of every model into DIR.

Under mpiexec the FE meshes are built shared over the ranks, as ``lcefem run`` builds them, and
gathered to rank 0, which writes them (the files hold the same cells, tags and geometry as a serial
run's; the nodes are numbered in dolfinx's global order).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time

from lcefem.models.errors import InputError
from lcefem.solvers.runtime.files import json_safe, write_json
from lcefem.solvers.runtime.outdir import add_out_arguments

BODIES = ("strip", "beam", "gridshell", "ribbon", "specimen")
MODELS = ("fe", "bar-hinge")
#: the bodies that have a bar-and-hinge structure
BAR_HINGE = ("beam", "gridshell", "specimen")


def add_arguments(p: argparse.ArgumentParser) -> None:
    from lcefem.meshes.io import FORMATS

    p.add_argument(
        "name",
        metavar="NAME",
        choices=BODIES + ("all",),
        help="the body whose mesh to write: " + ", ".join(BODIES) + ", or all",
    )
    p.add_argument(
        "--format",
        required=True,
        choices=tuple(FORMATS),
        help="msh (gmsh, physical names), xdmf or vtu (ParaView; names in <stem>.tags.json)",
    )
    p.add_argument(
        "--model",
        choices=MODELS,
        default="fe",
        help="the 3D FE mesh (default) or the bar-and-hinge structure (beam, gridshell, specimen)",
    )
    p.add_argument(
        "--mesh-level",
        type=int,
        default=None,
        help="FE refinement level l: element size = level-0 size / (l + 1) (default: the body's)",
    )
    p.add_argument(
        "--layout",
        default=None,
        help="gridshell only: a layout name (published, 5x5, 7x7, rhombic60, rhombic60_5x5) or "
        "a TOML file with a [layout] section (docs/layouts/index.md)",
    )
    add_out_arguments(p, "results/mesh")


@dataclasses.dataclass(frozen=True)
class MeshRequest:
    """One mesh to write: body, model, level (None: the body's default) and format."""

    body: str
    model: str
    level: int | None
    format: str
    layout: object = None  # gridshell: a checked Layout (None: the body's default)
    layout_name: str = ""

    @property
    def stem(self) -> str:
        body = f"{self.body}_{self.layout_name}" if self.layout_name else self.body
        return body if self.model == "fe" else f"{body}_bar_hinge"


def _fe_config(body: str):
    """The body's default configuration and the name of its mesh section."""
    if body == "strip":
        from lcefem.solvers.problems.strip import StripConfig

        return StripConfig()
    if body == "beam":
        from lcefem.solvers.problems.composite_beam_run import BeamFEConfig

        return BeamFEConfig()
    if body == "gridshell":
        from lcefem.solvers.problems.gridshell import GridshellConfig

        return GridshellConfig()
    if body == "specimen":
        from lcefem.solvers.problems.kapton_specimen import KaptonSpecimenFEConfig

        return KaptonSpecimenFEConfig()
    return None


def _ribbon_resolution():
    from lcefem.meshes.twisted_ribbon import TwistedRibbonMesh

    return TwistedRibbonMesh()


def _fe_mesh_section(body: str):
    """The FE mesh resolution dataclass the body builds with (its ``level`` field bounded)."""
    return _ribbon_resolution() if body == "ribbon" else _fe_config(body).mesh


def _level_bounds(resolution) -> tuple[int, int]:
    meta = {f.name: f.metadata for f in dataclasses.fields(resolution)}["level"]
    return int(meta.get("minimum", 0)), int(meta.get("maximum", 8))


def requests(args: argparse.Namespace) -> list[MeshRequest]:
    """The meshes NAME/--model/--mesh-level ask for, checked (one-line InputError naming the
    flag)."""
    if args.name == "all":
        pairs = [(b, "fe") for b in BODIES] + [(b, "bar-hinge") for b in BAR_HINGE]
    else:
        if args.model == "bar-hinge" and args.name not in BAR_HINGE:
            raise InputError(
                f"--model bar-hinge: {args.name} has only the FE mesh; bar-and-hinge "
                f"structures: {', '.join(BAR_HINGE)}"
            )
        pairs = [(args.name, args.model)]
    level = args.mesh_level
    if level is not None:
        if all(model == "bar-hinge" for _, model in pairs):
            raise InputError(
                f"--mesh-level = {level}: a bar-and-hinge structure has no refinement "
                "level (its panels are the published model's)"
            )
        for body, model in pairs:
            if model != "fe":
                continue
            lo, hi = _level_bounds(_fe_mesh_section(body))
            if not lo <= level <= hi:
                raise InputError(f"--mesh-level = {level}: the {body} mesh takes {lo} to {hi}")
    layout, layout_name = None, ""
    if getattr(args, "layout", None):
        import pathlib

        from lcefem.meshes.gridshell_layout import NAMED_LAYOUTS
        from lcefem.validation.app.layouts import load_layout

        if args.name != "gridshell":
            raise InputError(f"--layout: only with NAME gridshell (given {args.name})")
        layout = load_layout(args.layout)
        layout_name = (
            args.layout if args.layout in NAMED_LAYOUTS else pathlib.Path(args.layout).stem
        )
        if args.model == "fe":  # refused here, before the output folder is touched
            _layout_fe_checks(layout)
    return [
        MeshRequest(b, m, level if m == "fe" else None, args.format, layout, layout_name)
        for b, m in pairs
    ]


def _layout_fe_checks(layout) -> None:
    """The one-line refusals of :func:`lcefem.meshes.gridshell_fe_gmsh.build_layout_fe` (kind,
    glued)."""
    from lcefem.meshes.gridshell_layout import FE_KINDS

    if layout.kind not in FE_KINDS:
        raise InputError(
            f"--layout: kind {layout.kind!r}: the FE mesh is built for "
            f"{', '.join(FE_KINDS)} (two families of ribbons, two strips a junction)"
        )
    if layout.glued != "all":
        raise InputError(
            f"--layout: glued = {layout.glued!r}: the FE mesh bonds every junction; allowed 'all'"
        )


def prepare(args: argparse.Namespace) -> list[MeshRequest]:
    """The checked requests (before the output folder is touched)."""
    return requests(args)


def build_tagged(request: MeshRequest, comm=None):
    """The body's own mesh: a :class:`~lcefem.meshes._gmsh.TaggedMesh` (FE, on ``comm``, default
    :func:`~lcefem.meshes.communicator.default_comm`) or a
    :class:`~lcefem.meshes.bar_hinge_structure.BarHingeStructure` (bar-and-hinge, on every rank)."""
    body = request.body
    if request.model == "bar-hinge":
        return _bar_hinge(body, request.layout)
    resolution = _fe_mesh_section(body)
    if request.level is not None:
        resolution = dataclasses.replace(resolution, level=request.level)
    if body == "strip":
        from lcefem.meshes.strip import build_strip_mesh

        cfg = _fe_config(body)
        return build_strip_mesh(cfg.geometry, cfg.transition.lambda_N, resolution, comm)
    if body == "beam":
        from lcefem.meshes.composite_beam_fe import build_beam_fe

        cfg = _fe_config(body)
        return build_beam_fe(cfg.geometry, cfg.actuation.lambda_N, resolution, comm)
    if body == "gridshell":
        from lcefem.meshes.gridshell_fe import build_gridshell_fe

        cfg = _fe_config(body)
        if request.layout is not None:
            from lcefem.meshes.gridshell_fe_gmsh import build_layout_fe

            return build_layout_fe(request.layout, cfg.geometry, cfg.lambda_N, resolution, comm)
        return build_gridshell_fe(
            cfg.geometry, cfg.lambda_N, resolution, comm, cells=cfg.cells, symmetry=cfg.symmetry
        )
    if body == "ribbon":
        from lcefem.meshes.twisted_ribbon import build_twisted_ribbon
        from lcefem.solvers.problems.twisted_ribbon_der import RibbonConfig

        g = (
            RibbonConfig().geometry
        )  # the rolling ribbon's as-built section and twist (lcefem run ribbon)
        return build_twisted_ribbon(g.length, g.width, g.thickness, g.twist_rate, resolution, comm)
    from lcefem.meshes.kapton_ribbon import build_ribbon_fe

    return build_ribbon_fe(_fe_config(body).specimen, resolution, comm)


def build(request: MeshRequest, comm=None):
    """(meshio.Mesh, the builder's facts) of one request (:func:`build_tagged`); under MPI the mesh
    is rank 0's (None on the other ranks)."""
    from lcefem.meshes.io import structure_to_meshio, to_meshio

    built = build_tagged(request, comm)
    if request.model == "bar-hinge":
        return structure_to_meshio(built), built.info
    names = {"cells": built.cells, "facets": built.facets}
    return to_meshio(built.mesh, built.cell_tags, built.facet_tags, names), built.info


def _bar_hinge(body: str, layout=None):
    if body == "beam":
        from lcefem.meshes.composite_beam import build_beam_bar_hinge
        from lcefem.solvers.problems.composite_beam_bh import BeamConfig

        cfg = BeamConfig()
        return build_beam_bar_hinge(cfg.geometry, cfg.mesh)
    if body == "gridshell":
        from lcefem.meshes.gridshell import build_gridshell_bar_hinge
        from lcefem.solvers.problems.gridshell_bh_run import GridshellBHRunConfig

        cfg = GridshellBHRunConfig()
        return build_gridshell_bar_hinge(cfg.geometry, layout or cfg.layout, cfg.mesh)
    from lcefem.meshes.kapton_ribbon import build_ribbon_bar_hinge
    from lcefem.solvers.problems.kapton_specimen_bh import KaptonSpecimenConfig

    cfg = KaptonSpecimenConfig()
    return build_ribbon_bar_hinge(cfg.specimen, cfg.mesh)


def _plain(info: dict) -> dict:
    """The builder's facts that are plain JSON values (numbers, names, arrays); objects are left
    out."""
    out = {}
    for key, value in info.items():
        try:
            json.dumps(json_safe(value), allow_nan=False)
        except (TypeError, ValueError):
            continue
        out[str(key)] = json_safe(value)
    return out


def main(args: argparse.Namespace) -> int:
    from lcefem.meshes.communicator import default_comm
    from lcefem.meshes.io import name_map, tag_counts, write_mesh

    comm = default_comm()
    t0 = time.perf_counter()
    written = {}
    for request in args.prepared:
        m, info = build(request, comm)
        if comm.rank != 0:  # rank 0 holds the gathered mesh and writes it
            continue
        meta = {"body": request.body, "model": request.model}
        files = write_mesh(m, args.out, request.stem, request.format, meta)
        written[request.stem] = {
            "body": request.body,
            "model": request.model,
            "format": request.format,
            "files": [p.name for p in files],
            "points": int(m.points.shape[0]),
            "cells per tag": tag_counts(m),
            "tags": name_map(m),
            "info": _plain(info),
        }
        line = (
            f"lcefem: {request.stem}: {m.points.shape[0]} nodes, "
            f"{sum(len(c.data) for c in m.cells)} "
            f"cells in {len(m.field_data)} named tags -> {args.out / files[-1].name}"
        )
        if len(args.prepared) == 1:
            print(line)  # the command's one line
        elif not args.quiet:
            print(line)  # progress of `all`
    wall = time.perf_counter() - t0
    write_json(
        args.out / "summary.json",
        {
            "command": "mesh",
            "units": {"length": "mm"},
            "processes": comm.size,
            "meshes": written,
            "wall_time [s]": wall,
        },
        comm,
    )
    if len(args.prepared) > 1 and comm.rank == 0:
        print(
            f"lcefem: {len(written)} meshes as {args.format} in {wall:.1f} s; results in {args.out}"
        )
    return 0
