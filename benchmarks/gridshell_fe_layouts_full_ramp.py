"""The FE dome at the full ramp on the new layouts (issue 47, item 2): the Fig. 4 dome's lambdas
ramped from the as-built state, mesh level 0, on the refined 5 x 5 (quarter, the published
rollers) and the rhombic 60 deg grid (whole surface, the centre clamp: the rollers do not carry over
to a rhombic grid, docs/layouts/index.md), each the command

    lcefem run gridshell --model fe --layout LAYOUT --shape dome --support SUPPORT --out DIR/LAYOUT

run in its own process, and the data file the case gridshell_bh_vs_fe reads:

    python benchmarks/gridshell_fe_layouts_full_ramp.py --out DIR [--only 5x5] [--level 0]
        [--data validation/data/gridshell_fe_layouts_full_ramp_level0.json]

A layout whose ``DIR/LAYOUT_levelL/summary.json`` exists is not run again (its run is read), so the
runs can be made side by side (``--only``) and collected afterwards.

At a mesh level above 0 (``--level 1``, validation/data/gridshell_fe_layouts_full_ramp_level1.json,
issue 47: how much of the BH-vs-FE gaps is the level-0 FE's own mesh error) the data file holds the
layouts run (``--only``), and the control ``published`` may be among them: the published 3 x 3 under
the same centre clamp, ``lcefem run gridshell --model fe --shape dome --support clamp`` (no
``--layout``: the structured quarter mesh, as its level-0 value -0.021672 1/mm was measured,
docs/notes/fe_bodies_log.md, "The layouts at the full ramp"). CPU seconds are the run's own
(summary.json, ``time.process_time`` of the ramp; the mesh build not included); wall seconds on a
shared machine are upper bounds. Not a test: it prints figures.
"""

from __future__ import annotations

import argparse
import datetime
import json
import pathlib
import subprocess
import sys

DATA = (
    pathlib.Path(__file__).parents[1]
    / "validation"
    / "data"
    / "gridshell_fe_layouts_full_ramp_level0.json"
)
#: layout -> support of its run (module docstring)
RUNS = {"5x5": "rollers", "rhombic60": "clamp"}
#: controls, at levels above 0 only (module docstring): layout -> support
CONTROLS = {"published": "clamp"}
SUPPORTS = {**RUNS, **CONTROLS}


def command(layout: str, support: str, out: pathlib.Path, level: int) -> list[str]:
    exe = pathlib.Path(sys.executable).with_name("lcefem")
    # the control runs the default (structured) quarter mesh of the published surface
    chosen = [] if layout in CONTROLS else ["--layout", layout]
    return [
        str(exe) if exe.exists() else "lcefem",
        "run",
        "gridshell",
        "--model",
        "fe",
        *chosen,
        "--shape",
        "dome",
        "--support",
        support,
        "--mesh-level",
        str(level),
        "--out",
        str(out),
        "--quiet",
    ]


def run(layout: str, folder: pathlib.Path, level: int) -> dict:
    """The summary of the run of ``layout`` (made if ``folder/layout/summary.json`` is missing)."""
    out = folder / f"{layout}_level{level}"
    summary = out / "summary.json"
    if not summary.exists():
        subprocess.run(command(layout, SUPPORTS[layout], out, level), check=True)
    return json.loads(summary.read_text())


def row(layout: str, s: dict) -> dict:
    r = s["results"]
    return {
        "layout": layout,
        "shape": "dome",
        "support": SUPPORTS[layout],
        "symmetry": s["symmetry"],
        "circle_x": r["kappa_circle_x [1/mm]"],
        "circle_y": r["kappa_circle_y [1/mm]"],
        "quad_x": r["kappa_quad_x [1/mm]"],
        "quad_y": r["kappa_quad_y [1/mm]"],
        "z_range": r["z_range [mm]"],
        "dofs": s["dofs [-]"],
        "cpu": s["cpu time [s]"],
        "wall": s["wall time [s]"],
        "newton": s["newton iterations [-]"],
        "steps": s["path steps [-]"],
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True, help="folder of the runs")
    ap.add_argument("--only", default="", help="comma-separated layouts (default: all)")
    ap.add_argument("--level", type=int, default=0, help="mesh level (default 0)")
    ap.add_argument("--data", default="", help=f"data file to write (default {DATA.name})")
    ap.add_argument(
        "--machine",
        default="serial, shared 2-core machine",
        help="where the runs were made, for the source (e.g. the load average)",
    )
    a = ap.parse_args(argv)
    only = [x for x in a.only.split(",") if x] or list(RUNS)
    allowed = RUNS if a.level == 0 else SUPPORTS
    unknown = [x for x in only if x not in allowed]
    if unknown:
        print(f"--only: {unknown[0]!r}: allowed {', '.join(allowed)}", file=sys.stderr)
        return 2
    if a.level < 0:
        print(f"--level: {a.level}: allowed 0 or more", file=sys.stderr)
        return 2
    folder = pathlib.Path(a.out)
    rows = [row(layout, run(layout, folder, a.level)) for layout in only]
    for r in rows:
        print(
            f"{r['layout']} ({r['support']}, {r['symmetry']}): circle {r['circle_x']:.6f} / "
            f"{r['circle_y']:.6f} 1/mm, quadratic {r['quad_x']:.6f} / {r['quad_y']:.6f} 1/mm, "
            f"z range {r['z_range']:.2f} mm; {r['dofs']} DOFs, {r['cpu']:.0f} s CPU, "
            f"{r['wall']:.0f} s wall, {r['steps']} steps, {r['newton']} Newton iterations"
        )
    if a.level == 0 and set(only) != set(RUNS):  # the case's level-0 file holds every layout
        return 0
    data = pathlib.Path(a.data) if a.data else DATA
    if a.level != 0 and not a.data:
        data = DATA.with_name(DATA.name.replace("level0", f"level{a.level}"))
    costs = "; ".join(
        f"{r['layout']}: {r['symmetry']}, {r['support']}, {r['dofs']:,} DOFs, {r['cpu']:.0f} s CPU"
        f" ({r['wall']:.0f} s wall), {r['steps']} path steps, {r['newton']} Newton iterations"
        for r in rows
    )
    from lcefem.validation.studies.gridshell import gridshell_bh as gs

    control = ""
    if CONTROLS.keys() & set(only):
        control = "; the control published: no --layout, the structured quarter mesh"
    drive = ", ".join(f"{k} = {v:g}" for k, v in gs.SHAPES["dome"]["lambdas"].items())
    record = {
        "source": (
            "lcefem.solvers.problems.gridshell.GridshellFE on the gmsh mesh "
            f"(meshes.gridshell_fe_gmsh.build_layout_fe), mesh level {a.level}, datasheet Kapton, "
            f"the Fig. 4 dome's lambdas ({drive}) ramped from the as-built "
            "state, the path control of lcefem run gridshell --model fe (the Fig. 4 dome's); "
            f"python benchmarks/gridshell_fe_layouts_full_ramp.py --level {a.level} (lcefem run "
            "gridshell --model fe --layout L --shape dome --support S --mesh-level "
            f"{a.level}{control}), {datetime.date.today()} (issue 47); "
            f"{costs}; {a.machine}"
        ),
        "fraction": 1.0,
        "mesh level": a.level,
        "units": {
            "circle_x": "1/mm",
            "circle_y": "1/mm",
            "quad_x": "1/mm",
            "quad_y": "1/mm",
            "z_range": "mm",
            "dofs": "-",
            "cpu": "s",
            "wall": "s",
        },
        "rows": rows,
    }
    tmp = data.with_suffix(".json.part")
    tmp.write_text(json.dumps(record, indent=1) + "\n")
    tmp.replace(data)
    print(f"wrote {data}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
