"""Off-screen pictures (PNG) of a deformed dolfinx body coloured by a scalar field (pyvista).

Typical use at the end of an FE case::

    from lcefem.validation.app import render
    png = render.render_deformed(ctx.path("strip_0p2A_t20s.png"), u, T,
                                 scalar_label="temperature [C]", title="0.2 A, t = 20 s")
    ctx.add_figure(png, plots.caption("Deformed strip at t = 20 s coloured by temperature.",
                                      sources))

Serial only (the body is drawn from the local mesh); for parallel runs write VTX/XDMF files and open
them in ParaView. Without an X display, VTK's EGL window is selected so no X server is needed.
"""

from __future__ import annotations

import os
import pathlib
import sys

import dolfinx_solver  # noqa: F401  (must be imported before dolfinx)

import numpy as np

import dolfinx.fem
import dolfinx.plot

if sys.platform.startswith("linux") and not os.environ.get("DISPLAY"):
    # headless: VTK's default X window fails ("bad X server connection") before falling back
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

VIEWS = ("iso", "xy", "xz", "yz")


def _node_values(
    displacement: dolfinx.fem.Function, scalar
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(topology, cell types, node coordinates, displacement (n, 3), scalar (n,)) on the nodes of
    the displacement's space (P1 or P2 Lagrange): the scalar is interpolated there."""
    V = displacement.function_space
    bs = V.dofmap.index_map_bs
    if V.num_sub_spaces == 0 or bs not in (2, 3):
        raise ValueError("displacement must be a vector Lagrange Function (2 or 3 components)")
    topology, cell_types, geometry = dolfinx.plot.vtk_mesh(V)
    n = geometry.shape[0]
    disp = np.zeros((n, 3))
    disp[:, :bs] = displacement.x.array.real.reshape(n, bs)
    carrier = dolfinx.fem.Function(V)  # its first component carries the scalar on V's nodes
    if isinstance(scalar, dolfinx.fem.Function):
        carrier.sub(0).interpolate(scalar)
    elif callable(scalar) and not hasattr(scalar, "ufl_shape"):
        carrier.sub(0).interpolate(scalar)  # a function of x (numpy)
    else:  # a UFL expression, e.g. spontaneous_stretch(T, transition)
        degree = V.ufl_element().embedded_superdegree
        Q = dolfinx.fem.functionspace(V.mesh, ("Lagrange", degree))
        q = dolfinx.fem.Function(Q)
        q.interpolate(dolfinx.fem.Expression(scalar, Q.element.interpolation_points))
        carrier.sub(0).interpolate(q)
    values = carrier.x.array.real.reshape(n, bs)[:, 0].copy()
    return topology, cell_types, geometry, disp, values


def render_deformed(
    path: pathlib.Path,
    displacement: dolfinx.fem.Function,
    scalar,
    *,
    scalar_label: str = "temperature [C]",
    size: tuple[int, int] = (1200, 700),
    warp: float = 1.0,
    view: str = "iso",
    clim: tuple[float, float] | None = None,
    cmap: str = "coolwarm",
    show_undeformed: bool = True,
    title: str = "",
    zoom: float = 1.0,
    mirror: tuple[tuple[int, float], ...] = (),
    crop: tuple[int, float, float] | None = None,
) -> pathlib.Path:
    """Render the body displaced by ``warp * displacement`` [mm], coloured by ``scalar``, to a PNG.

    Args:
        displacement: vector Lagrange Function (P1 or P2) [mm].
        scalar: a dolfinx Function (any element; interpolated onto the displacement's nodes), a UFL
            expression, or a function of the coordinates x (numpy, shape (3, n)).
        scalar_label: colour-bar title with its unit, e.g. "spontaneous stretch [-]".
        size: image width and height [pixels].
        view: "iso" or a coordinate plane "xy", "xz", "yz".
        clim: colour range; the data range when None.
        show_undeformed: draw the undeformed body's edges in grey.
        mirror: symmetry planes (axis, coordinate [mm]) to reflect a symmetric model about, so that
            a quarter model is drawn whole (the planes must carry no normal displacement).
        crop: (axis, lower, upper) [mm]: draw only the cells whose reference coordinate along
            ``axis`` lies in [lower, upper] (e.g. the free end of a long strip).
    Returns:
        ``path`` (written atomically via a ``*.part.png`` name).
    """
    if displacement.function_space.mesh.comm.size > 1:
        raise NotImplementedError(
            "render_deformed runs in serial; open the VTX/XDMF files in ParaView"
        )
    if view not in VIEWS:
        raise ValueError(f"view {view!r}: allowed: {', '.join(VIEWS)}")
    if not (scalar_label.rstrip().endswith("]") and "[" in scalar_label):
        raise ValueError(f"scalar_label {scalar_label!r} needs a unit in brackets")
    import pyvista as pv

    topology, cell_types, geometry, disp, values = _node_values(displacement, scalar)
    grid = pv.UnstructuredGrid(topology, cell_types, geometry)
    grid.point_data["displacement [mm]"] = disp
    grid.point_data[scalar_label] = values
    if crop is not None:
        axis, lower, upper = crop
        centres = grid.cell_centers().points[:, axis]
        grid = grid.extract_cells(np.nonzero((centres >= lower) & (centres <= upper))[0])
    for axis, position in mirror:
        normal = np.zeros(3)
        normal[axis] = 1.0
        origin = np.zeros(3)
        origin[axis] = position
        reflected = grid.reflect(normal, point=origin)
        reflected.point_data["displacement [mm]"][:, axis] *= -1.0
        grid = grid.merge(reflected)
    warped = grid.warp_by_vector("displacement [mm]", factor=warp)

    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.stem + ".part.png")
    plotter = pv.Plotter(off_screen=True, window_size=list(size))
    try:
        plotter.set_background("white")
        if show_undeformed:
            plotter.add_mesh(
                grid.extract_surface(algorithm="dataset_surface").extract_feature_edges(),
                color="grey",
                opacity=0.5,
                line_width=1,
            )
        plotter.add_mesh(
            warped,
            scalars=scalar_label,
            cmap=cmap,
            clim=clim,
            show_edges=False,
            scalar_bar_args={
                "title": scalar_label,
                "color": "black",
                "vertical": True,
                "position_x": 0.80,
                "position_y": 0.12,
                "width": 0.06,
                "height": 0.72,
                "title_font_size": 14,
                "label_font_size": 12,
            },
        )
        if title or warp != 1.0:
            note = title + (f"   (displacement x {warp:g})" if warp != 1.0 else "")
            plotter.add_text(note, position="upper_left", font_size=11, color="black")
        plotter.add_axes(color="black")
        {
            "iso": plotter.view_isometric,
            "xy": plotter.view_xy,
            "xz": plotter.view_xz,
            "yz": plotter.view_yz,
        }[view]()
        plotter.reset_camera()
        if zoom != 1.0:
            plotter.camera.zoom(zoom)
        plotter.screenshot(str(tmp), window_size=list(size))
    finally:
        plotter.close()
    tmp.replace(path)
    return path
