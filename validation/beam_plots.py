"""Figures of the bar-and-hinge beam runs that :mod:`lcefem.validation.plots` does not cover: the
side view of a deformed composite beam, and the curvature-along-the-ramp + side-view figure of
``lcefem run beam`` (matplotlib, Agg; units on the axes)."""

from __future__ import annotations

import os
import pathlib

import numpy as np
from matplotlib.figure import Figure

from lcefem.meshes.bar_hinge_structure import BarHingeStructure


def _save(fig: Figure, path: pathlib.Path) -> pathlib.Path:
    """Save atomically (a .part file renamed when complete)."""
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.stem + ".part" + path.suffix)
    fig.savefig(tmp, dpi=130)
    os.replace(tmp, path)
    return path


def draw_side_view(ax, structure: BarHingeStructure, x: np.ndarray, *, label: bool = True) -> None:
    """x-z view of the ribbon edge y = 0 (black), bottom strips (red), top strips (blue), stations."""
    x = np.asarray(x).reshape(-1, 3)
    edge = structure.nodes[:, 1] < 0.5 * structure.nodes[:, 1].max()
    for p in structure.panels:
        q = x[[p[0], p[1]]]
        ax.plot(q[:, 0], q[:, 2], "k-", lw=1.2)
    styles = {"bottom_strips": ("tab:red", "bottom strip"), "top_strips": ("tab:blue", "top strip"),
              "glue": ("tab:green", "glue")}
    for group, (colour, name) in styles.items():
        for k, (i, j) in enumerate(structure.bars.get(group, [])):
            if not edge[i]:
                continue
            q = x[[i, j]]
            ax.plot(q[:, 0], q[:, 2], "-", color=colour, lw=1.0, label=name if label and k == 0 else None)
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("z [mm]")


def plot_beam_run(path, structure, x_final, load_factor, curvature, eq2, title: str) -> pathlib.Path:
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
    return _save(fig, path)
