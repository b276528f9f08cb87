"""Store the FE current route's runs for the case ``gridshell_heated_fe`` (issue 31): each run of
``lcefem run gridshell --model fe --shape NAME --route current --mesh-level L --out DIR`` writes
``DIR/summary.json`` (the heated FE gridshell, quarter, the shape's published support, held at the
currents the paper's rule gives, straight to the steady state). Such a run takes 10-40 min of one
core at level 1, so the case reads the stored summaries instead of running them.

``python -m lcefem.validation.studies.gridshell.gridshell_fe_current_store DIR [DIR ...] [--out
FILE.json]`` adds (or replaces) one entry per shape in
``validation/data/gridshell_fe_current_route_level1.json`` (written to a .part name, then renamed).
A summary below level 1 is refused by name (exit 2): the issue's "Done when" asks for level >= 1.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import sys

DATA = pathlib.Path(__file__).parents[2] / "data"
#: The stored file (read by validation.cases.gridshell_heated_fe._stored_current_route_rows).
STORE = DATA / "gridshell_fe_current_route_level1.json"
#: Shapes the issue's "Done when" needs from the FE current route (dome and saddle), and the one
#: it asks of the fast model only (cylinder): a missing one is an explicit row in the case.
REQUIRED = ("dome", "saddle")
#: Keys a summary must have (lcefem.solvers.problems.gridshell_fe_run.run_gridshell_fe, steady
#: hold).
KEYS = ("shape", "mesh level", "support", "current [A]", "current rule", "held", "cpu [s]")


def load(path: pathlib.Path) -> dict:
    """One run's summary.json (or the directory holding it), checked for the keys the case reads."""
    path = pathlib.Path(path)
    if path.is_dir():
        path = path / "summary.json"
    doc = json.loads(path.read_text())
    missing = [k for k in KEYS if k not in doc]
    if missing:
        raise ValueError(
            f"{path}: summary lacks {', '.join(missing)} (a run of lcefem run gridshell "
            "--model fe --route current)"
        )
    if doc["mesh level"] < 1:
        raise ValueError(
            f"{path}: mesh level = {doc['mesh level']}: allowed >= 1 (the issue's level)"
        )
    return doc


def main(argv=None) -> int:
    p = argparse.ArgumentParser(
        prog="python -m lcefem.validation.studies.gridshell.gridshell_fe_current_store",
        description=__doc__.split("\n\n")[0],
    )
    p.add_argument(
        "runs", nargs="+", type=pathlib.Path, help="run directories (or summary.json files)"
    )
    p.add_argument("--out", type=pathlib.Path, default=STORE)
    a = p.parse_args(argv)
    try:
        summaries = [load(r) for r in a.runs]
    except (OSError, ValueError) as exc:
        print(f"lcefem: error: {exc}", file=sys.stderr)
        return 2
    doc = json.loads(a.out.read_text()) if a.out.exists() else {}
    doc["what"] = (
        "FE heated gridshell current route (lcefem run gridshell --model fe --shape NAME "
        "--route current --mesh-level L): quarter model, published supports, held at the "
        "rule's currents straight to the steady state (HeatedGridshellFE.steady_hold); "
        "cpu [s] of one process on a shared 2-core machine under load"
    )
    runs = doc.setdefault("runs", {})
    for s in summaries:
        runs[s["shape"]] = s
        h = s["held"]
        print(
            f"{s['shape']}: level {s['mesh level']}, junction heating "
            f"{s.get('junction_heating', '?')}: "
            f"circle {h['kappa_circle_x [1/mm]']:.4f}/{h['kappa_circle_y [1/mm]']:.4f}; "
            f"{s['cpu [s]']:.0f} s CPU"
        )
    a.out.parent.mkdir(parents=True, exist_ok=True)
    part = a.out.with_suffix(".json.part")
    part.write_text(json.dumps(doc, indent=1) + "\n")
    part.replace(a.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
