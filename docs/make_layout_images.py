"""Regenerate the pictures of docs/layouts.md: a plan of every layout type and, for the two the
bar-and-hinge model builds, the shape of the round-dome drive (FE-calibrated set, as
tests/solvers/test_gridshell_layouts_bh.py).

    .venv/bin/python docs/make_layout_images.py [--no-shapes]   # writes docs/images/layout_*.png
"""

from __future__ import annotations

import pathlib
import sys

from lcefem.meshes.gridshell_layout import NAMED_LAYOUTS
from lcefem.validation.gridshell_plots import layout_plan_figure, render_gridshell

IMAGES = pathlib.Path(__file__).resolve().parent / "images"
PLANS = {"published": "orthogonal 3 x 3 (published, seed 001 Fig. 4)", "5x5": "orthogonal 5 x 5 (refined)",
         "rhombic60": "rhombic, 60 deg, 3 x 3", "triangular": "triangular, 5 per family (plan only)",
         "hexagonal": "hexagonal 3 x 3 cells (plan only)"}
SHAPES = {"5x5": ("rollers", {"B": 1.37}), "rhombic60": ("clamp", {"B": 1.395})}


def main(shapes: bool = True) -> None:
    for name, title in PLANS.items():
        print(layout_plan_figure(IMAGES / f"layout_{name}_plan.png", NAMED_LAYOUTS[name].plan(), title))
    if not shapes:
        return
    from lcefem.solvers.problems.gridshell_bh import GridshellBH, GridshellBHConfig
    from lcefem.validation import calibrate

    ms = calibrate.model_set("fe-calibrated")
    for name, (support, drive) in SHAPES.items():
        layout = NAMED_LAYOUTS[name]
        p = GridshellBH(ms.structure(layout), GridshellBHConfig(materials=ms.materials_for(layout),
                                                                support=support))
        p.set_drives(drive)
        p.advance()
        label = ", ".join(f"lambda_{k} = {v}" for k, v in drive.items())
        print(render_gridshell(IMAGES / f"layout_{name}_shape.png", p.structure, p.x,
                               f"{name}: {label} ({support}; FE-calibrated bar-and-hinge)"))


if __name__ == "__main__":
    main(shapes="--no-shapes" not in sys.argv)
