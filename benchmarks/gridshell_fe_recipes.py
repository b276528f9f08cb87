"""CPU cost of the eight published recipes on the 3D FE gridshell at level 0 (issue 46: all eight
within 15 min CPU): each one the command a user types,

    lcefem run gridshell --recipe NAME --model fe --out DIR --quiet

run as a child process, its CPU seconds (user + system, ``resource.getrusage(RUSAGE_CHILDREN)``: the
whole command, imports, mesh, forms, ramp and the output files) and its summary (mirror model, DOFs,
path steps, Newton iterations, centre curvatures).

    python benchmarks/gridshell_fe_recipes.py [--recipes saddle dome ...]
        [--mesh-level 0] [--out DIR] [--json out.json] [--taskset CPU]

``--taskset CPU`` pins each command to one core (``taskset -c CPU``, Linux), so that the CPU seconds
are those of one serial process. Not a test: it prints figures for docs/performance.md. On the
shared 2-core machine compare CPU seconds, not wall (the load is printed with the figures).
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import platform
import resource
import shutil
import subprocess
import sys
import tempfile
import time

#: The issue's budget for the eight recipes at level 0 [s CPU] (issue 46).
BUDGET_CPU = 15 * 60.0


def run_recipe(recipe: str, level: int, out: pathlib.Path, taskset: str | None) -> dict:
    """One ``lcefem run gridshell --recipe NAME --model fe`` in a child process; its figures."""
    folder = out / recipe
    # the installed console script's entry point, with this interpreter
    cmd = [
        sys.executable,
        "-c",
        "import sys; from lcefem.validation.app.cli import main; sys.exit(main())",
        "run",
        "gridshell",
        "--recipe",
        recipe,
        "--model",
        "fe",
        "--mesh-level",
        str(level),
        "--out",
        str(folder),
        "--overwrite",
        "--quiet",
    ]
    if taskset is not None:
        if shutil.which("taskset") is None:
            raise SystemExit("--taskset: the taskset command is not on this machine")
        cmd = ["taskset", "-c", taskset, *cmd]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    wall0 = time.perf_counter()
    done = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - wall0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    row = {"recipe": recipe, "exit code": done.returncode, "cpu [s]": cpu, "wall [s]": wall}
    summary = folder / "summary.json"
    if done.returncode != 0 or not summary.exists():
        row["error"] = (done.stderr.strip().splitlines() or ["(no message)"])[-1]
        return row
    s = json.loads(summary.read_text())
    res = s["results"]
    row.update(
        {
            "symmetry": s["symmetry"],
            "support": s["support"],
            "dofs [-]": s["dofs [-]"],
            "path steps [-]": s["path steps [-]"],
            "newton iterations [-]": s["newton iterations [-]"],
            "step cuts [-]": s["step cuts [-]"],
            **{
                k: res[k]
                for k in (
                    "kappa_circle_x [1/mm]",
                    "kappa_circle_y [1/mm]",
                    "kappa_quad_x [1/mm]",
                    "kappa_quad_y [1/mm]",
                )
            },
        }
    )
    return row


def main(argv: list[str] | None = None) -> int:
    from lcefem.validation.cases.programs import RECIPES

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--recipes", nargs="+", default=list(RECIPES), choices=list(RECIPES))
    parser.add_argument("--mesh-level", type=int, default=0, choices=range(4), help="FE mesh level")
    parser.add_argument("--out", default=None, help="the runs' folders (default: a temporary one)")
    parser.add_argument("--json", default=None, help="also write the figures to this file")
    parser.add_argument("--taskset", default=None, help="pin each run to this core (taskset -c)")
    args = parser.parse_args(argv)
    print(
        f"python {platform.python_version()}, {platform.machine()}; FE gridshell recipes, level "
        f"{args.mesh_level}; load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores",
        flush=True,
    )
    rows = []
    with tempfile.TemporaryDirectory(prefix="fe_recipes_") as tmp:
        out = pathlib.Path(args.out) if args.out else pathlib.Path(tmp)
        for recipe in args.recipes:
            r = run_recipe(recipe, args.mesh_level, out, args.taskset)
            rows.append(r)
            if "error" in r:
                print(
                    f"{recipe}: FAILED (exit {r['exit code']}, {r['cpu [s]']:.1f} s CPU): "
                    f"{r['error']}",
                    flush=True,
                )
                continue
            print(
                f"{recipe}: {r['cpu [s]']:.1f} s CPU ({r['wall [s]']:.0f} s wall), "
                f"{r['symmetry']}, "
                f"{r['support']}, {r['dofs [-]']} DOFs, {r['path steps [-]']} steps, "
                f"{r['newton iterations [-]']} Newton its ({r['step cuts [-]']} cuts); circle "
                f"{r['kappa_circle_x [1/mm]']:+.6f} {r['kappa_circle_y [1/mm]']:+.6f}, quadratic "
                f"{r['kappa_quad_x [1/mm]']:+.6f} {r['kappa_quad_y [1/mm]']:+.6f} 1/mm",
                flush=True,
            )
    total = sum(r["cpu [s]"] for r in rows)
    failed = [r["recipe"] for r in rows if "error" in r]
    print(
        f"all {len(rows)}: {total:.1f} s CPU ({total / 60:.1f} min) against the budget of "
        f"{BUDGET_CPU / 60:.0f} min: {'met' if total <= BUDGET_CPU and not failed else 'NOT met'}"
        + (f"; failed: {', '.join(failed)}" if failed else ""),
        flush=True,
    )
    if args.json:
        from lcefem.solvers.runtime.files import write_json

        write_json(args.json, {"budget cpu [s]": BUDGET_CPU, "total cpu [s]": total, "rows": rows})
    return 1 if failed else 0


if __name__ == "__main__":
    raise SystemExit(main())
