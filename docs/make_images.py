"""Regenerate the README's picture: the free strip after 20 s at 0.2 A (3D FE, default mesh level).

    .venv/bin/python docs/make_images.py   # writes docs/images/strip_0p2A_20s.png (about 2 minutes)
"""

from __future__ import annotations

import pathlib
import tempfile

from lcefem.validation.cases.strip import DEFAULT_LEVEL, render_strip_end
from lcefem.solvers.problems.strip import StripConfig, StripRun, run_strip
from lcefem.meshes.strip import StripMesh

IMAGES = pathlib.Path(__file__).resolve().parent / "images"


def main() -> None:
    config = StripConfig(run=StripRun(current=0.2, duration=20.0), mesh=StripMesh(level=DEFAULT_LEVEL))
    with tempfile.TemporaryDirectory() as tmp:
        result = run_strip(config, pathlib.Path(tmp) / "run", fields=False)
    IMAGES.mkdir(parents=True, exist_ok=True)
    png = render_strip_end(IMAGES / "strip_0p2A_20s.png", result, "free LCE strip, 0.2 A, t = 20 s (3D FE)")
    print(png)


if __name__ == "__main__":
    main()
