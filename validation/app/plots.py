"""Comparison, convergence and map plots for validation cases (matplotlib, Agg, PNG).

Every axis label carries its unit in brackets (``"time [s]"``) and every figure names the sources of
its data in a footer; the same sources go into the report caption (:func:`caption`). Figures are
built with :class:`matplotlib.figure.Figure` (no pyplot state) and written atomically.

Typical use in a case::

    from lcefem.validation.app import plots
    png = plots.comparison_plot(
        ctx.path("transient_0p2A.png"),
        [plots.Series(t, T, "model", "model"),
         plots.Series(t_exp, T_exp, "experiment (Fig. 2B)", "experiment", yerr=sd)],
        xlabel="time [s]", ylabel="temperature [C]",
        hlines=[plots.Line(70.0, "T_NI", "experiment")], sources=[ref.cite])
    ctx.add_figure(png, plots.caption("Strip temperature at 0.2 A.", [ref.cite]))
"""

from __future__ import annotations

import math
import pathlib
import textwrap
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from matplotlib.figure import Figure

from lcefem.models.errors import InputError
from lcefem.solvers.runtime.files import naming, open_new

KINDS = ("model", "experiment", "closed form", "published model", "reference")
_STYLE = {
    "model": dict(linestyle="-", linewidth=2.0, marker=None, color="C0"),
    "experiment": dict(linestyle="none", marker="o", markersize=5, color="k"),
    "closed form": dict(linestyle="--", linewidth=1.5, marker=None, color="C3"),
    "published model": dict(linestyle=":", linewidth=2.0, marker=None, color="C2"),
    "reference": dict(linestyle="-.", linewidth=1.2, marker=None, color="C7"),
}


@dataclass(frozen=True)
class Series:
    """One curve or point set. ``kind`` picks the style: model (solid), experiment (markers with
    error bars or a shaded ``band`` = (lower, upper)), closed form (dashed), published model
    (dotted)."""

    x: Sequence[float]
    y: Sequence[float]
    label: str
    kind: str = "model"
    yerr: Sequence[float] | float | None = None
    xerr: Sequence[float] | float | None = None
    band: tuple[Sequence[float], Sequence[float]] | None = None
    color: str | None = None
    marker: str | None = None  #: overrides the kind's marker (a lone point needs one)


@dataclass(frozen=True)
class Line:
    """A horizontal or vertical reference line (e.g. T_NI, a rupture force, a time bound)."""

    value: float
    label: str
    kind: str = "experiment"


@dataclass(frozen=True)
class Span:
    """A shaded interval (e.g. 'within 10 s', a measured range)."""

    lower: float
    upper: float
    label: str


def caption(text: str, sources: Sequence[str]) -> str:
    """Report caption: ``text`` followed by its sources."""
    src = "; ".join(dict.fromkeys(s for s in sources if s))
    return f"{text} Sources: {src}." if src else text


def _require_unit(label: str, what: str) -> None:
    if not (label.rstrip().endswith("]") and "[" in label):
        raise ValueError(f"{what} label {label!r} needs a unit in brackets, e.g. 'time [s]'")


def _check_kind(kind: str) -> None:
    if kind not in KINDS:
        raise ValueError(f"series kind {kind!r}: allowed: {', '.join(KINDS)}")


_FOOTER_PT = 6.5


def sources_footer(fig: Figure, sources: Sequence[str]) -> None:
    """Write the sources under the axes and keep the axes clear of them (constrained layout)."""
    src = "; ".join(dict.fromkeys(s for s in sources if s))
    if not src:
        return
    width_in, height_in = fig.get_size_inches()
    text = textwrap.fill("Sources: " + src, max(40, int(width_in * 72 / (0.62 * _FOOTER_PT))))
    fig.text(0.01, 0.005, text, fontsize=_FOOTER_PT, va="bottom", ha="left", color="0.25")
    bottom = (text.count("\n") + 1) * 1.3 * _FOOTER_PT / 72 / height_in + 0.01
    fig.get_layout_engine().set(rect=(0, bottom, 1, 1 - bottom))


def save_figure(fig: Figure, path: pathlib.Path, dpi: int) -> pathlib.Path:
    """Write ``fig`` to ``path`` through a ``*.part.png`` name (an unfinished figure never looks
    complete)."""
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.stem + ".part" + path.suffix)  # keeps the .png suffix for the writer
    try:
        with (
            naming(tmp),
            open_new(tmp, "wb") as fh,
        ):  # a planted link at tmp is refused, not followed
            fig.savefig(fh, dpi=dpi, format=path.suffix.lstrip(".") or "png")
    except InputError:
        raise
    except BaseException:
        tmp.unlink(missing_ok=True)  # a full disk: give the space back, leave no half figure
        raise
    tmp.replace(path)
    return path


def _draw_series(ax, s: Series) -> None:
    _check_kind(s.kind)
    style = dict(_STYLE[s.kind])
    if s.color:
        style["color"] = s.color
    if s.marker:
        style["marker"] = s.marker
        if len(s.x) == 1:
            style["linestyle"] = "none"
    x, y = np.asarray(s.x, float), np.asarray(s.y, float)
    if s.band is not None:
        ax.fill_between(x, s.band[0], s.band[1], color=style["color"], alpha=0.2, linewidth=0)
    if s.yerr is not None or s.xerr is not None:
        ax.errorbar(x, y, yerr=s.yerr, xerr=s.xerr, label=s.label, capsize=3, **style)
    else:
        ax.plot(x, y, label=s.label, **style)


def comparison_plot(
    path: pathlib.Path,
    series: Sequence[Series],
    *,
    xlabel: str,
    ylabel: str,
    sources: Sequence[str],
    title: str = "",
    hlines: Sequence[Line] = (),
    vlines: Sequence[Line] = (),
    vspans: Sequence[Span] = (),
    logx: bool = False,
    logy: bool = False,
    secondary_y: tuple[float, str] | None = None,
    size: tuple[float, float] = (6.4, 4.4),
    dpi: int = 150,
) -> pathlib.Path:
    """Model vs experiment vs closed form on one axes; returns the PNG path.

    ``secondary_y = (factor, label)`` adds a right axis showing ``factor * y`` (e.g. stress ->
    force).
    """
    _require_unit(xlabel, "x")
    _require_unit(ylabel, "y")
    fig = Figure(figsize=size, layout="constrained")
    ax = fig.add_subplot()
    for sp in vspans:
        ax.axvspan(sp.lower, sp.upper, color="0.85", alpha=0.6, label=sp.label, linewidth=0)
    for s in series:
        _draw_series(ax, s)
    for ln in hlines:
        _check_kind(ln.kind)
        ax.axhline(
            ln.value, color=_STYLE[ln.kind]["color"], linestyle=":", linewidth=1, label=ln.label
        )
    for ln in vlines:
        _check_kind(ln.kind)
        ax.axvline(
            ln.value, color=_STYLE[ln.kind]["color"], linestyle="-.", linewidth=1, label=ln.label
        )
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if logx:
        ax.set_xscale("log")
    if logy:
        ax.set_yscale("log")
    if secondary_y is not None:
        factor, label = secondary_y
        _require_unit(label, "secondary y")
        ax.secondary_yaxis(
            "right", functions=(lambda v: v * factor, lambda v: v / factor)
        ).set_ylabel(label)
    if title:
        ax.set_title(title, fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    sources_footer(fig, sources)
    return save_figure(fig, path, dpi)


@dataclass(frozen=True)
class ConvergenceSeries:
    """|value - extrapolated| per level of one metric, with its observed order (nan if none)."""

    label: str  #: metric name with unit, e.g. "time to 70 C [s]"
    errors: Sequence[float]
    order: float


def convergence_plot(
    path: pathlib.Path,
    mesh_sizes: Sequence[float],
    series: Sequence[ConvergenceSeries],
    *,
    xlabel: str = "mesh size [mm]",
    title: str = "",
    sources: Sequence[str] = (),
    dpi: int = 150,
) -> pathlib.Path:
    """Log-log |value - extrapolated| vs mesh size, one panel per metric, with a slope-p guide line
    through the finest point (Celik et al. 2008 extrapolation)."""
    _require_unit(xlabel, "x")
    n = max(1, len(series))
    ncols = min(3, n)
    nrows = math.ceil(n / ncols)
    fig = Figure(figsize=(4.2 * ncols, 3.4 * nrows + 0.4), layout="constrained")
    h = np.asarray(mesh_sizes, float)
    for k, s in enumerate(series):
        _require_unit(s.label, "metric")
        ax = fig.add_subplot(nrows, ncols, k + 1)
        err = np.abs(np.asarray(s.errors, float))
        ok = np.isfinite(err) & (err > 0)
        name, unit = s.label.rsplit("[", 1)
        if ok.any():
            ax.loglog(h[ok], err[ok], "o-", color="C0", label="|value - extrapolated|")
            if math.isfinite(s.order) and s.order > 0:
                idx = np.flatnonzero(ok)[-3:]  # the finest levels: where p was measured
                i = idx[-1]
                hh = np.array([h[idx].min(), h[idx].max()])
                ax.loglog(
                    hh,
                    err[i] * (hh / h[i]) ** s.order,
                    "--",
                    color="C3",
                    label=f"slope p = {s.order:.2f}",
                )
            ax.legend(fontsize=7)
        else:
            ax.text(
                0.5,
                0.5,
                "no mesh dependence\nor no extrapolation",
                ha="center",
                va="center",
                transform=ax.transAxes,
                fontsize=8,
            )
            ax.set_xticks([])
            ax.set_yticks([])
        ax.set_xlabel(xlabel)
        ax.set_ylabel(f"|error| [{unit}")
        ax.set_title(name.strip(), fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
    if title:
        fig.suptitle(title, fontsize=10)
    sources_footer(fig, sources)
    return save_figure(fig, path, dpi)


@dataclass(frozen=True)
class MapPoints:
    """Scattered (x, y, z) data drawn on a map, coloured with the map's colour scale."""

    x: Sequence[float]
    y: Sequence[float]
    z: Sequence[float]
    label: str
    kind: str = "experiment"


def map_plot(
    path: pathlib.Path,
    x: Sequence[float],
    y: Sequence[float],
    z: np.ndarray,
    *,
    xlabel: str,
    ylabel: str,
    zlabel: str,
    sources: Sequence[str],
    title: str = "",
    points: Sequence[MapPoints] = (),
    style: str = "map",
    contours: int = 8,
    cmap: str = "RdBu_r",
    symmetric: bool = True,
    dpi: int = 150,
) -> pathlib.Path:
    """A field z(x, y) on a grid (``z[j, i]`` at ``x[i], y[j]``), e.g. kappa(lambda_T, lambda_B).

    ``style="map"``: colour map with contour lines; ``style="surface"``: 3D surface (as Fig. 3B of
    seed 001). ``points`` (experiment: crosses, model: dots) share the colour scale.
    ``symmetric`` centres the colour scale on zero (signed curvatures).
    """
    for label, what in ((xlabel, "x"), (ylabel, "y"), (zlabel, "z")):
        _require_unit(label, what)
    if style not in ("map", "surface"):
        raise ValueError(f"style {style!r}: allowed: map, surface")
    x, y, z = np.asarray(x, float), np.asarray(y, float), np.asarray(z, float)
    if z.shape != (y.size, x.size):
        raise ValueError(f"z has shape {z.shape}; expected (len(y), len(x)) = {(y.size, x.size)}")
    values = [z[np.isfinite(z)]] + [np.asarray(p.z, float) for p in points]
    vmin, vmax = (
        float(min(v.min() for v in values if v.size)),
        float(max(v.max() for v in values if v.size)),
    )
    if symmetric:
        m = max(abs(vmin), abs(vmax))
        vmin, vmax = -m, m
    fig = Figure(figsize=(6.4, 4.8), layout="constrained")
    X, Y = np.meshgrid(x, y)
    marker = {
        "experiment": "X",
        "model": "o",
        "published model": "s",
        "closed form": "^",
        "reference": "d",
    }
    if style == "map":
        ax = fig.add_subplot()
        mesh = ax.pcolormesh(X, Y, z, cmap=cmap, vmin=vmin, vmax=vmax, shading="auto")
        if contours:
            cs = ax.contour(X, Y, z, levels=contours, colors="k", linewidths=0.5, alpha=0.6)
            ax.clabel(cs, fontsize=6, fmt="%.3g")
        for p in points:
            _check_kind(p.kind)
            ax.scatter(
                p.x,
                p.y,
                c=p.z,
                cmap=cmap,
                vmin=vmin,
                vmax=vmax,
                marker=marker[p.kind],
                edgecolors="k",
                s=60,
                label=p.label,
            )
    else:
        ax = fig.add_subplot(projection="3d")
        mesh = ax.plot_surface(X, Y, z, cmap=cmap, vmin=vmin, vmax=vmax, alpha=0.8, linewidth=0)
        for p in points:
            _check_kind(p.kind)
            ax.scatter(
                p.x,
                p.y,
                p.z,
                color="k" if p.kind == "experiment" else "C1",
                marker=marker[p.kind],
                s=30,
                label=p.label,
                depthshade=False,
            )
        ax.set_zlabel(zlabel)
    fig.colorbar(mesh, ax=ax, label=zlabel, shrink=0.85)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if points:
        ax.legend(fontsize=8, loc="upper left")
    if title:
        ax.set_title(title, fontsize=10)
    sources_footer(fig, sources)
    return save_figure(fig, path, dpi)
