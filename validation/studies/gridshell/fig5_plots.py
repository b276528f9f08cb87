"""Figures and movies of the robotic surface's Fig. 5 tasks (matplotlib, off-screen): the covered
surface (ribbons and the cover-scale disks in each junction's tangent plane, optionally the ball),
the bare/covered curvature chart, curvature and ball trajectories over time, and GIF movies (pillow;
no video encoder needed)."""

from __future__ import annotations

import pathlib
from collections.abc import Sequence

import numpy as np

from lcefem.solvers.exports import ribbon_triangles


def _figure(size=(7.0, 5.0)):
    from matplotlib.figure import Figure

    return Figure(figsize=size, layout="constrained")


def junction_frames(structure, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(centres (m, 3), unit normals (m, 3)) of the junctions: normal of each square's diagonals,
    pointing to +z as built."""
    x = np.asarray(x, dtype=float).reshape(-1, 3)
    q = x[structure.node_sets["junction_corners"].reshape(-1, 4)]
    normal = np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 1])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    return q.mean(axis=1), normal


def disk_outline(centre: np.ndarray, normal: np.ndarray, radius: float, n: int = 48) -> np.ndarray:
    """(n, 3) points of a circle of ``radius`` [mm] in the plane through ``centre`` normal to
    ``normal``."""
    a = np.cross(normal, [0.0, 1.0, 0.0])
    a /= np.linalg.norm(a)
    b = np.cross(normal, a)
    phi = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    return centre + radius * (np.cos(phi)[:, None] * a + np.sin(phi)[:, None] * b)


def draw_surface(
    ax, structure, x, scales=None, ball: tuple[np.ndarray, float] | None = None, lift: float = 1.0
) -> None:
    """Ribbons (grey triangles), scales (translucent orange disks, ``lift`` mm above the junction)
    and a ball (centre [mm], radius [mm])."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    x = np.asarray(x, dtype=float).reshape(-1, 3)
    tri = ribbon_triangles(structure)
    ax.add_collection3d(Poly3DCollection(x[tri], facecolor="0.6", edgecolor="none", alpha=0.9))
    if scales is not None:
        c, n = junction_frames(structure, x)
        disks = [disk_outline(ci + lift * ni, ni, 0.5 * scales.diameter) for ci, ni in zip(c, n)]
        ax.add_collection3d(
            Poly3DCollection(
                disks,
                facecolor=(1.0, 0.6, 0.1, 0.35),
                edgecolor=(0.7, 0.35, 0.0, 0.8),
                linewidth=0.6,
            )
        )
    if ball is not None:
        centre, r = ball
        u, v = np.mgrid[0 : 2 * np.pi : 16j, 0 : np.pi : 9j]
        ax.plot_surface(
            centre[0] + r * np.cos(u) * np.sin(v),
            centre[1] + r * np.sin(u) * np.sin(v),
            centre[2] + r * np.cos(v),
            color="royalblue",
            linewidth=0,
        )
    lo, hi = x[:, :2].min() - 20.0, x[:, :2].max() + 20.0
    ax.set_xlim(lo, hi)
    ax.set_ylim(lo, hi)
    zc = float(np.median(x[:, 2]))
    ax.set_zlim(zc - 40.0, zc + 40.0)
    ax.set_box_aspect((1, 1, 0.5))
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_zlabel("z [mm]")
    ax.view_init(elev=28, azim=-60)


def render_covered(path, structure, x, scales, title: str, ball=None) -> pathlib.Path:
    from lcefem.validation.app.plots import save_figure

    fig = _figure()
    ax = fig.add_subplot(projection="3d")
    draw_surface(ax, structure, x, scales, ball)
    ax.set_title(title, fontsize=9)
    return save_figure(fig, pathlib.Path(path), 110)


def scale_chart(path, chart: dict, sources: Sequence[str]) -> pathlib.Path:
    """Grouped bars per shape: kappa_x and kappa_y [1/mm] of each series ({shape: {label: (kx,
    ky)}})."""
    from lcefem.validation.app.plots import save_figure, sources_footer

    fig = _figure((11, 4.5))
    axes = fig.subplots(1, 2, sharey=True)
    shapes = list(chart)
    labels = list(next(iter(chart.values()))) if chart else []
    width = 0.8 / max(len(labels), 1)
    pos = np.arange(len(shapes))
    for k, (ax, comp) in enumerate(zip(axes, ("kappa_x", "kappa_y"))):
        for i, label in enumerate(labels):
            ax.bar(
                pos + (i - 0.5 * (len(labels) - 1)) * width,
                [chart[s][label][k] for s in shapes],
                width,
                label=label,
            )
        ax.set_xticks(pos, shapes)
        ax.axhline(0.0, color="k", lw=0.8)
        ax.set_title(f"{comp} at the centre (dome negative)", fontsize=9)
        ax.grid(alpha=0.3, axis="y")
    axes[0].set_ylabel("curvature [1/mm]")
    axes[1].legend(fontsize=7)
    sources_footer(fig, sources)
    return save_figure(fig, pathlib.Path(path), 130)


def write_gif(path, frames: Sequence[np.ndarray], seconds_per_frame: float = 0.2) -> pathlib.Path:
    """Animated GIF from RGB(A) frames (pillow), written through a .part name."""
    from PIL import Image

    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    images = [Image.fromarray(np.asarray(f)[..., :3]) for f in frames]
    tmp = path.with_name(path.stem + ".part.gif")
    images[0].save(
        tmp,
        format="GIF",
        save_all=True,
        append_images=images[1:],
        duration=int(1000 * seconds_per_frame),
        loop=0,
    )
    tmp.replace(path)
    return path


def frame_image(draw, size=(6.4, 4.8), dpi: int = 80) -> np.ndarray:
    """RGBA array of a figure drawn by ``draw(fig)`` (Agg canvas)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig = _figure(size)
    canvas = FigureCanvasAgg(fig)
    fig.set_dpi(dpi)
    draw(fig)
    canvas.draw()
    return np.asarray(canvas.buffer_rgba()).copy()


def surface_frame(structure, x, scales, title: str, ball=None) -> np.ndarray:
    def draw(fig):
        ax = fig.add_subplot(projection="3d")
        draw_surface(ax, structure, x, scales, ball)
        ax.set_title(title, fontsize=9)

    return frame_image(draw)


def ball_trajectory_plot(
    path, traj: dict, times: dict, half_width: float, radius: float
) -> pathlib.Path:
    """Top view of the ball's path (footprint square) and its x, y against time (phases marked)."""
    from lcefem.validation.app.plots import save_figure

    fig = _figure((10, 4))
    a, b = fig.subplots(1, 2, width_ratios=(1, 1.6))
    a.plot(traj["u [mm]"], traj["v [mm]"], lw=1)
    a.plot(traj["u [mm]"][0], traj["v [mm]"][0], "go", label="start (corner scale)")
    a.plot(traj["u [mm]"][-1], traj["v [mm]"][-1], "rs", label="end")
    w = half_width
    a.plot([-w, w, w, -w, -w], [-w, -w, w, w, -w], "k-", lw=0.8, label="scales' footprint")
    a.set_aspect("equal")
    a.set_xlabel("x - x_c [mm]")
    a.set_ylabel("y - y_c [mm]")
    a.legend(fontsize=7)
    t = traj["time [s]"]
    b.plot(t, traj["u [mm]"], label="x - x_c [mm]")
    b.plot(t, traj["v [mm]"], label="y - y_c [mm]")
    for name, value in times.items():
        b.axvline(value, color="0.8", lw=0.8)
        b.text(
            value,
            1.0,
            " " + name,
            rotation=90,
            va="top",
            fontsize=7,
            transform=b.get_xaxis_transform(),
        )
    b.axhspan(-radius, radius, color="0.9", label="within one ball radius of the centre")
    b.set_xlabel("time [s]")
    b.set_ylabel("ball centre [mm]")
    b.legend(fontsize=7, loc="lower left")
    return save_figure(fig, pathlib.Path(path), 120)


def pad_height_plot(path, record, rows: dict, flat: float) -> pathlib.Path:
    """Pad height [mm] against its mass [g]: the loads of Fig. 5C and the ramp on to the give-way
    load."""
    from lcefem.validation.app.plots import save_figure

    fig = _figure((6.5, 4))
    ax = fig.add_subplot()
    if record:
        m, h = np.array(record).T
        ax.plot(m / 1e-6, h, "-", color="0.5", label="ramp beyond 200 g")
    ax.plot(
        rows["pad mass [g]"], rows["pad height [mm]"], "o", label="Fig. 5C loads (100, 150, 200 g)"
    )
    ax.axhline(flat, color="k", lw=0.8, ls="--", label="pad on the flat surface")
    ax.set_xlabel("pad mass [g]")
    ax.set_ylabel("pad height above the table plane [mm]")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    return save_figure(fig, pathlib.Path(path), 120)
