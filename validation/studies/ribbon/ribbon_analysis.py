"""Figures of rolling-ribbon histories: the trajectory/speed figure and sweeps. (The rolling metrics
themselves are :mod:`lcefem.solvers.analysis.rolling`.)"""

from __future__ import annotations

import pathlib

import numpy as np

from lcefem.validation.app.plots import save_figure


def plot_trajectory(
    history: dict[str, np.ndarray], path: pathlib.Path, title: str = ""
) -> pathlib.Path:
    """PNG: centroid path in the plane (mm) and speed, end spin angles and temperatures against
    time."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    h = {k: np.asarray(v, float) for k, v in history.items()}
    t = h["time [s]"]
    fig, axes = plt.subplots(2, 2, figsize=(10, 7))
    ax = axes[0, 0]
    ax.plot(h["centroid_x [mm]"], h["centroid_y [mm]"], "-", lw=1.2)
    ax.plot(h["centroid_x [mm]"][0], h["centroid_y [mm]"][0], "o", label="start")
    ax.plot(h["centroid_x [mm]"][-1], h["centroid_y [mm]"][-1], "s", label="end")
    ax.set_xlabel("centroid x [mm]")
    ax.set_ylabel("centroid y [mm]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize=8)
    ax.set_title("trajectory (ribbon axis along x)")
    ax = axes[0, 1]
    ax.plot(t, h["speed [mm/s]"], lw=0.8, alpha=0.5, label="instantaneous")
    if len(t) > 20:
        k = max(1, len(t) // 20)
        kernel = np.ones(k) / k
        ax.plot(
            t,
            np.convolve(h["speed [mm/s]"], kernel, mode="same"),
            lw=1.5,
            label=f"moving mean ({k} samples)",
        )
    ax.set_xlabel("time [s]")
    ax.set_ylabel("centroid speed [mm/s]")
    ax.legend(fontsize=8)
    for ax, ylabel, curves in (
        (
            axes[1, 0],
            "end rotation about the axis [rad]",
            (("spin_start [rad]", "end at x = 0"), ("spin_end [rad]", "end at x = L")),
        ),
        (axes[1, 1], "ribbon temperature [C]", (("T_mean [C]", "mean"), ("T_max [C]", "max"))),
    ):
        for column, label in curves:
            ax.plot(t, h[column], label=label)
        ax.set_xlabel("time [s]")
        ax.set_ylabel(ylabel)
        ax.legend(fontsize=8)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    path = save_figure(fig, path, 120)
    plt.close(fig)
    return path


def plot_sweep(
    x,
    series: dict[str, list[float]],
    xlabel: str,
    ylabel: str,
    path: pathlib.Path,
    reference: tuple[float, str] | None = None,
) -> pathlib.Path:
    """PNG of one or more y-series against x, with an optional vertical reference line (value,
    label)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    for label, y in series.items():
        ax.plot(x, y, "o-", label=label)
    if reference is not None:
        ax.axvline(reference[0], color="k", ls="--", lw=1, label=reference[1])
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = save_figure(fig, path, 120)
    plt.close(fig)
    return path
