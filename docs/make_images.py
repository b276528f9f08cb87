"""Regenerate the README's picture: the free strip after 20 s at 0.2 A (3D FE, default mesh level),
and the "Your own robot" page's: the LCE bilayer of examples/bodies/bilayer bent at 47.21 C and
the gripper finger of examples/bodies/gripper at its steady state at 0.2 A.

    .venv/bin/python docs/make_images.py           # all three (about 5 minutes)
    .venv/bin/python docs/make_images.py bilayer   # docs/images/bilayer.png only (about 30 s)
    .venv/bin/python docs/make_images.py gripper   # docs/images/gripper.png only (about 2 minutes)
"""

from __future__ import annotations

import pathlib
import tempfile

from lcefem.meshes.strip import StripMesh
from lcefem.solvers.problems.strip import StripConfig, StripRun, run_strip
from lcefem.validation.cases.strip import DEFAULT_LEVEL, render_strip_end

IMAGES = pathlib.Path(__file__).resolve().parent / "images"


def bilayer() -> pathlib.Path:
    """The bilayer case at its own size factor, drawn whole (its two mirror planes reflected)."""
    from lcefem.solvers.problems.body import BodyProblem
    from lcefem.solvers.problems.body_case import load_case
    from lcefem.validation.app.render import render_deformed

    case = load_case(IMAGES.parent.parent / "examples" / "bodies" / "bilayer" / "case.toml")
    problem = BodyProblem(case)
    problem.set_program(0.0)
    problem.equilibrate("t = 0 s")
    fields = problem.fields()
    IMAGES.mkdir(parents=True, exist_ok=True)
    return render_deformed(
        IMAGES / "bilayer.png",
        fields["displacement [mm]"],
        fields["spontaneous stretch [-]"],
        scalar_label="spontaneous stretch [-]",
        view="xz",
        size=(1200, 420),
        mirror=((0, 0.0), (1, 0.0)),
        zoom=1.6,
        title="LCE bilayer at 47.21 C: the LCE layer (bottom) contracts 1 %",
    )


def gripper() -> pathlib.Path:
    """The gripper finger's steady state at 0.2 A, coloured by temperature (the serpentine
    shows)."""
    from lcefem.solvers.problems.body import BodyProblem
    from lcefem.solvers.problems.body_case import load_case
    from lcefem.validation.app.render import render_deformed

    case = load_case(
        IMAGES.parent.parent / "examples" / "bodies" / "gripper" / "case.toml",
        overrides={("program", "steady"): True},
    )
    problem = BodyProblem(case)
    problem.set_program(0.0)
    problem.steady_state()
    fields = problem.fields()
    IMAGES.mkdir(parents=True, exist_ok=True)
    return render_deformed(
        IMAGES / "gripper.png",
        fields["displacement [mm]"],
        fields["temperature [C]"],
        scalar_label="temperature [C]",
        view="iso",
        size=(1200, 700),
        zoom=1.3,
        title="gripper finger, 0.2 A, steady state: it bends toward the LCE (top)",
    )


def main() -> None:
    import sys

    if sys.argv[1:] == ["bilayer"]:
        print(bilayer())
        return
    if sys.argv[1:] == ["gripper"]:
        print(gripper())
        return
    print(bilayer())
    print(gripper())
    config = StripConfig(
        run=StripRun(current=0.2, duration=20.0), mesh=StripMesh(level=DEFAULT_LEVEL)
    )
    with tempfile.TemporaryDirectory() as tmp:
        result = run_strip(config, pathlib.Path(tmp) / "run", fields=False)
    IMAGES.mkdir(parents=True, exist_ok=True)
    png = render_strip_end(
        IMAGES / "strip_0p2A_20s.png", result, "free LCE strip, 0.2 A, t = 20 s (3D FE)"
    )
    print(png)


if __name__ == "__main__":
    main()
