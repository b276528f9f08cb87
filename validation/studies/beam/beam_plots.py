"""Figures of the beam runs that :mod:`lcefem.validation.app.plots` does not cover: the side view of
a deformed composite beam (bar-and-hinge and FE), the curvature-along-the-ramp + side-view figure of
``lcefem run beam``, and the 3D render of the FE beam (matplotlib, Agg; units on the axes)."""

from __future__ import annotations

import pathlib

import numpy as np
from matplotlib.figure import Figure

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.validation.app.plots import save_figure


def draw_side_view(ax, structure: BarHingeStructure, x: np.ndarray, *, label: bool = True) -> None:
    """x-z view of the ribbon edge y = 0 (black), bottom strips (red), top strips (blue),
    stations."""
    x = np.asarray(x).reshape(-1, 3)
    edge = structure.nodes[:, 1] < 0.5 * structure.nodes[:, 1].max()
    for p in structure.panels:
        q = x[[p[0], p[1]]]
        ax.plot(q[:, 0], q[:, 2], "k-", lw=1.2)
    styles = {
        "bottom_strips": ("tab:red", "bottom strip"),
        "top_strips": ("tab:blue", "top strip"),
        "glue": ("tab:green", "glue"),
    }
    for group, (colour, name) in styles.items():
        for k, (i, j) in enumerate(structure.bars.get(group, [])):
            if not edge[i]:
                continue
            q = x[[i, j]]
            ax.plot(
                q[:, 0],
                q[:, 2],
                "-",
                color=colour,
                lw=1.0,
                label=name if label and k == 0 else None,
            )
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("z [mm]")


def plot_beam_run(
    path, structure, x_final, load_factor, curvature, eq2, title: str
) -> pathlib.Path:
    """Curvature vs load factor along the ramp (bar-and-hinge and Eq. 2) and the final side view."""
    fig = Figure(figsize=(11, 4.4), layout="constrained")
    a, b = fig.subplots(1, 2)
    a.plot(load_factor, curvature, "k.-", label="bar-and-hinge (circle fit, middle stations)")
    a.plot(load_factor, eq2, "r--", label="Eq. 2 (seed 001, eta = 0.57)")
    a.set_xlabel("load factor t [-] (rest lengths ramped from nematic to target)")
    a.set_ylabel("curvature kappa [1/mm]")
    a.legend()
    a.grid(alpha=0.3)
    draw_side_view(b, structure, x_final)
    b.legend(loc="best", fontsize=8)
    b.set_title("final state (ribbon edge y = 0)")
    fig.suptitle(title)
    return save_figure(fig, path, 130)


def plot_fe_side_view(path, model, u, title: str, extra=None) -> pathlib.Path | None:
    """x-z view [mm] of the FE beam's nodes on the ribbon's outer edge plane (y = 0), by body;
    ``extra(ax)`` draws the left panel (e.g. curvature along the ramp). On several ranks each rank's
    owned nodes are gathered to rank 0, which draws and writes the figure (collective; the other
    ranks return None)."""
    import dolfinx

    V = u.function_space
    comm = V.mesh.comm
    X = V.tabulate_dof_coordinates()  # model: BeamFE or heated model
    x = X + u.x.array.reshape(-1, 3)
    owned = V.dofmap.index_map.size_local  # a ghost node is drawn by the rank that owns it
    tm = model.tmesh
    edge = np.abs(X[:, 1] - tm.info["strip_y_range"][0]) < 1e-9
    colours = {
        "kapton": ("k", "Kapton ribbon"),
        "bottom_strips": ("tab:red", "bottom strips"),
        "bottom_pads": ("salmon", "bottom bond pads"),
        "top_strips": ("tab:blue", "top strips"),
        "top_pads": ("lightblue", "top bond pads"),
    }
    nodes = {}
    for name in colours:
        dofs = dolfinx.fem.locate_dofs_topological(V, 3, tm.cell_tags.find(tm.cell_tag(name)))
        dofs = dofs[(dofs < owned) & edge[dofs]]
        xz = np.column_stack([x[dofs, 0], x[dofs, 2], X[dofs, 0], X[dofs, 2]])
        if comm.size > 1:
            parts = comm.gather(xz, root=0)
            xz = np.concatenate(parts) if comm.rank == 0 else xz
        nodes[name] = xz
    if comm.rank != 0:
        return None
    fig = Figure(figsize=(11, 4.4), layout="constrained")
    axes = fig.subplots(1, 2)
    if extra is not None:
        extra(axes[0])
    ax = axes[1]
    for name, (colour, label) in colours.items():
        xz = nodes[name]
        ax.plot(xz[:, 0], xz[:, 1], ".", ms=2, color=colour, label=label)
        ax.plot(xz[:, 2], xz[:, 3], ".", ms=1, color="0.8")
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("z [mm]")
    ax.set_title("side view at the strips' edge (grey: as built)", fontsize=9)
    ax.legend(fontsize=7, markerscale=4)
    fig.suptitle(title, fontsize=10)
    return save_figure(fig, path, 130)


def render_fe_beam(path, model, title: str) -> pathlib.Path:
    """3D render of the deformed FE beam, mirrored to the whole beam, coloured by height z [mm]."""
    from lcefem.validation.app import render

    info = model.tmesh.info
    mirror = [(1, 0.5 * info["ribbon_width"])]
    if info["symmetry"] == "quarter":
        mirror.append((0, info["x_mid"]))
    u = model.u
    return render.render_deformed(
        path,
        u,
        lambda x: x[2],
        scalar_label="height z (as built) [mm]",
        title=title,
        mirror=tuple(mirror),
        view="xz",
        show_undeformed=False,
    )
