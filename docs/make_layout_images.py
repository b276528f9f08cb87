"""Regenerate the pictures of the layout pages (docs/layouts/index.md and one page per type): a plan
of every layout type, for the two-family ones their 3D FE mesh made by gmsh
(meshes.gridshell_fe_gmsh.build_layout_fe, level 0, whole surface, coloured by body), and the shape
of a uniform bottom drive on every type the bar-and-hinge model builds (FE-calibrated set; the 5 x 5
and rhombic ones as tests/solvers/test_gridshell_layouts_bh.py).

    .venv/bin/python docs/make_layout_images.py [--no-shapes] [--no-fe] [--only NAME]
    # docs/images/layout_*.png (--only: one layout's pictures)
"""

from __future__ import annotations

import pathlib
import sys

from lcefem.meshes.gridshell_layout import NAMED_LAYOUTS
from lcefem.validation.studies.gridshell.gridshell_plots import layout_plan_figure, render_gridshell

IMAGES = pathlib.Path(__file__).resolve().parent / "images"
PLANS = {
    "published": "orthogonal 3 x 3 (published, seed 001 Fig. 4)",
    "5x5": "orthogonal 5 x 5 (refined)",
    "rhombic60": "rhombic, 60 deg, 3 x 3",
    "triangular": "triangular, 5 ribbons per family (19 hexagonal junctions)",
    "hexagonal": "hexagonal, the 3 cells round the centre junction (13 junctions, 15 pieces)",
}
#: Layout -> (support, drive): a uniform bottom drive. The triangular grid has no rollers (the
#: published rollers sit at the ends of an orthogonal grid's ribbons): the clamp of its centre
#: hexagon. The honeycomb: its top strips (a bowl; its bottom strips alone give a shallow dome).
SHAPES = {
    "5x5": ("rollers", {"B": 1.37}),
    "rhombic60": ("clamp", {"B": 1.395}),
    "triangular": ("clamp", {"B": 1.37}),
    "hexagonal": ("clamp", {"T": 1.3}),
}
#: Layouts whose FE mesh is pictured, and the height exaggeration of the picture [-] (the arch is
#: 1.1 mm on a 150-220 mm surface).
FE_MESHES = ("published", "5x5", "rhombic60")
Z_SCALE = 2.0


def fe_mesh_figure(name: str) -> pathlib.Path:
    """docs/images/layout_<name>_fe_mesh.png: the layout's FE mesh (level 0, whole surface) in
    three colours (Kapton; bottom layer: strips and pads; top layer: strips, crown pads, glue)."""
    from mpi4py import MPI

    import numpy as np
    import pyvista as pv

    import dolfinx.plot

    from lcefem.meshes.composite_beam import CompositeBeamGeometry
    from lcefem.meshes.gridshell_fe import GridshellFEMesh
    from lcefem.meshes.gridshell_fe_gmsh import build_layout_fe
    from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N

    tm = build_layout_fe(
        NAMED_LAYOUTS[name],
        CompositeBeamGeometry(),
        PUBLISHED_LAMBDA_N,
        GridshellFEMesh(level=0),
        MPI.COMM_SELF,
        symmetry="full",
    )
    topology, cell_types, x = dolfinx.plot.vtk_mesh(tm.mesh)
    grid = pv.UnstructuredGrid(topology, cell_types, x * np.array([1.0, 1.0, Z_SCALE]))
    body = np.zeros(tm.mesh.topology.index_map(3).size_local, dtype=int)
    groups = tm.info["cell_groups"]
    for value, members in (
        (1, ("bottom_strips", "bottom_pads")),
        (2, ("top_strips", "top_pads", "glue")),
    ):
        tags = [t for g in members if g in groups for t in groups[g]]
        body[tm.cell_tags.indices[np.isin(tm.cell_tags.values, tags)]] = value
    grid.cell_data["body"] = body
    path = IMAGES / f"layout_{name}_fe_mesh.png"
    tmp = path.with_name(path.stem + ".part.png")
    plotter = pv.Plotter(off_screen=True, window_size=[1200, 800])
    try:
        plotter.set_background("white")
        plotter.add_mesh(
            grid,
            scalars="body",
            cmap=["#d9a441", "#3b6fb6", "#c0392b"],
            show_edges=True,
            edge_color="#333333",
            line_width=0.5,
            show_scalar_bar=False,
        )
        plotter.add_text(
            f"{name}: 3D FE mesh made by gmsh, level 0 ({grid.n_cells} hexahedra; z x "
            f"{Z_SCALE:g}); Kapton, bottom layer, top layer",
            position="upper_left",
            font_size=10,
            color="black",
        )
        plotter.view_isometric()
        plotter.reset_camera()
        plotter.camera.zoom(1.6)
        plotter.screenshot(str(tmp))
    finally:
        plotter.close()
    tmp.replace(path)
    return path


def main(shapes: bool = True, fe: bool = True, only: str | None = None) -> None:
    for name, title in PLANS.items():
        if only not in (None, name):
            continue
        print(
            layout_plan_figure(
                IMAGES / f"layout_{name}_plan.png", NAMED_LAYOUTS[name].plan(), title
            )
        )
    for name in FE_MESHES if fe else ():
        if only in (None, name):
            print(fe_mesh_figure(name))
    if not shapes:
        return
    from lcefem.solvers.problems.gridshell_bh import GridshellBH, GridshellBHConfig
    from lcefem.validation.studies.gridshell import calibrate

    ms = calibrate.model_set("fe-calibrated")
    for name, (support, drive) in SHAPES.items():
        if only not in (None, name):
            continue
        layout = NAMED_LAYOUTS[name]
        p = GridshellBH(
            ms.structure(layout),
            GridshellBHConfig(materials=ms.materials_for(layout), support=support),
        )
        p.set_drives(drive)
        p.advance()
        label = ", ".join(f"lambda_{k} = {v}" for k, v in drive.items())
        print(
            render_gridshell(
                IMAGES / f"layout_{name}_shape.png",
                p.structure,
                p.x,
                f"{name}: {label} ({support}; FE-calibrated bar-and-hinge)",
            )
        )


if __name__ == "__main__":
    only = sys.argv[sys.argv.index("--only") + 1] if "--only" in sys.argv else None
    main(shapes="--no-shapes" not in sys.argv, fe="--no-fe" not in sys.argv, only=only)
