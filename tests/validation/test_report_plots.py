"""Plot helpers: units on axes, sources in the footer, the three kinds of figure."""

import numpy as np
import pytest
from matplotlib.image import imread

from lcefem.models.empirical import eq2_curvature
from lcefem.validation.app import plots
from lcefem.validation.cases.reference_data import reference


def test_axis_labels_must_carry_units(tmp_path):
    with pytest.raises(ValueError, match="unit in brackets"):
        plots.comparison_plot(
            tmp_path / "x.png",
            [plots.Series([0, 1], [0, 1], "m")],
            xlabel="time",
            ylabel="T [C]",
            sources=[],
        )
    with pytest.raises(ValueError, match="series kind"):
        plots.comparison_plot(
            tmp_path / "x.png",
            [plots.Series([0, 1], [0, 1], "m", "simulation")],
            xlabel="t [s]",
            ylabel="T [C]",
            sources=[],
        )


def test_comparison_plot_with_experiment_bands_and_lines(tmp_path):
    t = np.linspace(0, 30, 31)
    png = plots.comparison_plot(
        tmp_path / "transient.png",
        [
            plots.Series(t, 25 + 50 * (1 - np.exp(-t / 8)), "model", "model"),
            plots.Series([5, 10, 20], [50, 65, 72], "experiment", "experiment", yerr=[2, 2, 3]),
            plots.Series(
                t, 25 + 2.0 * t, "closed form", "closed form", band=(25 + 1.8 * t, 25 + 2.2 * t)
            ),
        ],
        xlabel="time [s]",
        ylabel="temperature [C]",
        hlines=[plots.Line(70, "T_NI")],
        vspans=[plots.Span(0, 10, "within 10 s")],
        sources=[reference("strip.T_NI").cite],
    )
    img = imread(png)
    assert img.shape[0] > 400 and img[..., :3].std() > 0.05
    assert not list(tmp_path.glob("*.part*"))


def test_map_plot_of_eq2_curvature(tmp_path):
    """kappa(lambda_T, lambda_B) of Eq. 2 as a map and as a surface, with points on the same
    scale."""
    lt = np.linspace(1.0, 1.4, 21)
    lb = np.linspace(1.0, 1.4, 19)
    kappa = eq2_curvature(lt[None, :], lb[:, None])
    pts = plots.MapPoints(
        [1.33, 1.05],
        [1.05, 1.33],
        eq2_curvature(np.array([1.33, 1.05]), np.array([1.05, 1.33])),
        "Eq. 2 at Fig. 4 settings",
        "closed form",
    )
    for style in ("map", "surface"):
        png = plots.map_plot(
            tmp_path / f"kappa_{style}.png",
            lt,
            lb,
            kappa,
            xlabel="lambda_T [-]",
            ylabel="lambda_B [-]",
            zlabel="curvature [1/mm]",
            points=[pts],
            style=style,
            sources=[reference("eq2.eta").cite],
        )
        assert imread(png)[..., :3].std() > 0.05
    with pytest.raises(ValueError, match="expected"):
        plots.map_plot(
            tmp_path / "bad.png",
            lt,
            lb,
            kappa.T,
            xlabel="a [-]",
            ylabel="b [-]",
            zlabel="k [1/mm]",
            sources=[],
        )


def test_caption_lists_each_source_once():
    assert plots.caption("A.", ["s1", "s2", "s1", ""]) == "A. Sources: s1; s2."
