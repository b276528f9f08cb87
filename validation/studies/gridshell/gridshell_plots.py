"""Figures of the gridshell: an off-screen 3D render of a shape (pyvista) with the junction centres
marked, and the bar chart of centre curvatures (ours by the lambda and current routes vs the paper's
simulation and experiment)."""

from __future__ import annotations

import os
import pathlib
import sys
from collections.abc import Sequence

import numpy as np

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.solvers.analysis.curvature import junction_centre_points
from lcefem.solvers.exports import ribbon_triangles

if sys.platform.startswith("linux") and not os.environ.get("DISPLAY"):
    # headless: as validation/app/render.py, VTK's EGL window (no X server)
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")


def render_gridshell(
    path: pathlib.Path, structure: BarHingeStructure, x: np.ndarray, title: str
) -> pathlib.Path:
    """PNG of the deformed ribbons (coloured by height z [mm]), strips as lines (bottom red, top
    blue) and the junction centres as black spheres."""
    import pyvista as pv

    x = np.asarray(x, dtype=float).reshape(-1, 3)
    tri = ribbon_triangles(structure)
    faces = np.hstack([np.full((tri.shape[0], 1), 3), tri]).ravel()
    ribbons = pv.PolyData(x, faces=faces)
    ribbons.point_data["height z [mm]"] = x[:, 2]
    plotter = pv.Plotter(off_screen=True, window_size=(1000, 750))
    plotter.add_mesh(ribbons, scalars="height z [mm]", cmap="viridis", show_edges=False)
    for group, colour in (("bottom_strips", "red"), ("top_strips", "royalblue"), ("glue", "grey")):
        if group in structure.bars:
            pairs = structure.bars[group]
            lines = np.hstack([np.full((pairs.shape[0], 1), 2), pairs]).ravel()
            plotter.add_mesh(pv.PolyData(x, lines=lines), color=colour, line_width=3)
    centres = junction_centre_points(structure, x).reshape(-1, 3)
    plotter.add_mesh(
        pv.PolyData(centres).glyph(geom=pv.Sphere(radius=2.0), scale=False, orient=False),
        color="black",
    )
    plotter.add_text(title, font_size=10)
    plotter.view_isometric()
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.stem + ".part.png")
    plotter.screenshot(str(tmp))
    plotter.close()
    tmp.replace(path)
    return path


def curvature_bar_chart(
    path: pathlib.Path, shapes: Sequence[str], series: dict[str, dict], sources: Sequence[str]
) -> pathlib.Path:
    """Grouped bars of kappa_x and kappa_y [1/mm] per shape; ``series`` maps a label to
    {shape: (kappa_x, kappa_y)} (None for a missing value)."""
    from matplotlib.figure import Figure

    from lcefem.validation.app.plots import save_figure, sources_footer

    def drawn(values: dict) -> bool:
        return any(
            v is not None and np.isfinite(v) for s in shapes for v in values.get(s, (None, None))
        )

    # a series without a single value (e.g. the current route, not run at the quick level) gets no
    # legend entry, which would name bars that are not there; the footer says it was left out
    empty = [label for label, values in series.items() if not drawn(values)]
    series = {label: values for label, values in series.items() if drawn(values)}
    if empty:
        sources = [*sources, f"no values, not drawn: {', '.join(empty)}"]
    fig = Figure(figsize=(11, 4.5), layout="constrained")
    axes = fig.subplots(1, 2, sharey=True)
    width = 0.8 / max(len(series), 1)
    pos = np.arange(len(shapes))
    for k, (ax, comp) in enumerate(zip(axes, ("kappa_x", "kappa_y"))):
        for i, (label, values) in enumerate(series.items()):
            vals = [values.get(s, (None, None))[k] for s in shapes]
            vals = [np.nan if v is None else v for v in vals]
            ax.bar(pos + (i - 0.5 * (len(series) - 1)) * width, vals, width, label=label)
        ax.set_xticks(pos, shapes)
        ax.axhline(0.0, color="k", lw=0.8)
        ax.set_title(f"{comp} at the centre junction (dome negative)", fontsize=9)
        ax.grid(alpha=0.3, axis="y")
    axes[0].set_ylabel("curvature [1/mm]")
    if series:
        axes[1].legend(fontsize=7)
    sources_footer(fig, sources)
    return save_figure(fig, pathlib.Path(path), 150)


def reachable_set_figure(
    path: pathlib.Path, kappa: np.ndarray, points: dict[str, tuple[float, float]], title: str
) -> pathlib.Path:
    """Scatter of reachable centre curvatures (kappa_x, kappa_y) [1/mm] (rows of ``kappa``) with
    their convex hull, and labelled target points."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from scipy.spatial import ConvexHull

    kappa = np.asarray(kappa, dtype=float)
    fig, ax = plt.subplots(figsize=(6.0, 5.5))
    ax.scatter(
        kappa[:, 0], kappa[:, 1], s=8, color="tab:blue", label="equilibria on the lambda grid"
    )
    if kappa.shape[0] >= 3:
        hull = ConvexHull(kappa)
        loop = np.append(hull.vertices, hull.vertices[0])
        ax.plot(kappa[loop, 0], kappa[loop, 1], color="tab:blue", lw=1, label="convex hull")
    for name, (kx, ky) in points.items():
        ax.plot(kx, ky, "x", ms=8, mew=2)
        ax.annotate(name, (kx, ky), textcoords="offset points", xytext=(5, 5), fontsize=8)
    ax.axhline(0, color="grey", lw=0.5)
    ax.axvline(0, color="grey", lw=0.5)
    ax.set_xlabel("centre curvature kappa_x [1/mm] (circle; dome negative)")
    ax.set_ylabel("centre curvature kappa_y [1/mm]")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7, loc="best")
    fig.tight_layout()
    from lcefem.validation.app.plots import save_figure

    try:  # through the one figure writer: a .part name, no planted link followed
        return save_figure(fig, pathlib.Path(path), 130)
    finally:
        plt.close(fig)


def layout_plan_figure(path: pathlib.Path, plan: dict, title: str) -> pathlib.Path:
    """Plan view of a gridshell layout (:meth:`lcefem.meshes.gridshell_layout.Layout.plan`): each
    ribbon centre line drawn as a band of the ribbon's width [mm] (to scale), junction centres as
    black dots; axes in mm."""
    from matplotlib.figure import Figure
    from matplotlib.patches import Polygon

    from lcefem.validation.app.plots import save_figure

    fig = Figure(figsize=(5.5, 5.0), layout="constrained")
    ax = fig.subplots()
    half = 0.5 * float(plan["width"])
    for a, b in np.asarray(plan["lines"], dtype=float):
        t = (b - a) / np.linalg.norm(b - a)
        n = np.array([-t[1], t[0]]) * half
        ax.add_patch(
            Polygon(
                [a + n, b + n, b - n, a - n],
                closed=True,
                facecolor="goldenrod",
                edgecolor="saddlebrown",
                lw=0.5,
                alpha=0.6,
            )
        )
    j = np.asarray(plan["junctions"], dtype=float)
    ax.plot(j[:, 0], j[:, 1], "k.", ms=4, label="junction centres")
    pts = np.asarray(plan["lines"], dtype=float).reshape(-1, 2)
    pad = 2 * half + 5.0
    ax.set_xlim(pts[:, 0].min() - pad, pts[:, 0].max() + pad)
    ax.set_ylim(pts[:, 1].min() - pad, pts[:, 1].max() + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7, loc="upper right")
    return save_figure(fig, pathlib.Path(path), 120)


def reach_figure(path: pathlib.Path, designs: dict) -> pathlib.Path:
    """Branches in the (kappa_x, kappa_y) plane [1/mm]: per target (``designs[label]``: "target",
    "loop", "flat", "design" as (kx, ky) pairs and "kind"), the target (x), the design loop's
    equilibrium (o), the run from flat at the loop's lambdas (square) joined to it by a dashed line
    (the jump between branches), and the final design's run from flat (star; open for a program;
    "overshoot", optional: where a program's first drive lands from flat, triangle, arrow to the
    release; "runs", optional: every one-drive run from flat the search tried, dots)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 5.5))
    for j, (label, d) in enumerate(designs.items()):
        c = f"C{j % 10}"
        runs = np.asarray(d.get("runs") or [], dtype=float).reshape(-1, 2)
        ax.plot(runs[:, 0], runs[:, 1], ".", color=c, alpha=0.5, ms=6)
        ax.plot(*d["target"], "x", color=c, ms=10, mew=2, label=f"{label} ({d['kind']})")
        ax.plot(*d["loop"], "o", color=c, mfc="none", ms=7)
        ax.plot(*d["flat"], "s", color=c, mfc="none", ms=7)
        ax.plot([d["loop"][0], d["flat"][0]], [d["loop"][1], d["flat"][1]], "--", color=c, lw=0.8)
        ax.plot(*d["design"], "*", color=c, ms=12, mfc=c if d["kind"] == "constant" else "none")
        if d.get("overshoot") is not None:  # a program: the overshoot's landing, then the release
            ax.plot(*d["overshoot"], "^", color=c, ms=8, mfc="none")
            ax.annotate(
                "",
                xy=d["design"],
                xytext=d["overshoot"],
                arrowprops={"arrowstyle": "->", "color": c, "lw": 1.0},
            )
            ax.plot(
                [], [], "^", color="k", mfc="none", label="program: the overshoot's run from flat"
            )
    ax.plot([], [], ".", color="k", alpha=0.5, label="other runs from flat tried (one drive)")
    ax.plot([], [], "o", color="k", mfc="none", label="design loop (holds the target)")
    ax.plot([], [], "s", color="k", mfc="none", label="run from flat at those lambdas")
    ax.plot([], [], "*", color="k", ms=10, label="reached design (open: program)")
    ax.set_xlabel("centre curvature kappa_x [1/mm] (circle; dome negative)")
    ax.set_ylabel("centre curvature kappa_y [1/mm]")
    ax.set_title("Designs and the branch the run from flat lands on", fontsize=9)
    ax.legend(fontsize=7, loc="best")
    fig.tight_layout()
    from lcefem.validation.app.plots import save_figure

    try:  # through the one figure writer: a .part name, no planted link followed
        return save_figure(fig, pathlib.Path(path), 130)
    finally:
        plt.close(fig)
