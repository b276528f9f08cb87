"""The FE dome's whole lambda ramp from flat at one mesh level, logged step by step; and the mesh
study of the levels so run (issue 14).

    python benchmarks/gridshell_fe_dome_levels.py --level 2 --out DIR
    python benchmarks/gridshell_fe_dome_levels.py --analyse DIR [--data FILE]

A level runs what ``lcefem converge gridshell_shapes_fe`` runs at that level
(``validation.cases.gridshell_fe.fe_model('dome', mesh_level=L).ramp(Fig. 4 dome lambdas)``: quarter
model, published rollers, datasheet Kapton), one process per level, so that the levels can run side
by side and a long one can be watched: every accepted path step appends a JSON line to
``DIR/steps_level<L>.jsonl`` (path parameter, Newton iterations, CPU and wall time [s], peak memory
[MiB], the observables) and saves the state (``DIR/dome_state_level<L>.npz``,
``GridshellFE.save_state``); the last line (``"event": "final"``) has the totals.
``--analyse`` adds the logged levels to ``--data`` (default
``validation/data/gridshell_fe_dome_full_ramp_from_flat_levels.json``, which holds levels 0 and 1)
and analyses every finished level with :func:`lcefem.validation.app.converge.analyse` (observed
order, Richardson value, GCI; h = the in-plane element size of the level, ``GridshellFEMesh().size /
(L+1)``).

Not a test: it prints figures. CPU time is the process's; wall times on a shared machine are upper
bounds.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import resource
import time

DATA = (
    pathlib.Path(__file__).parents[1]
    / "validation"
    / "data"
    / "gridshell_fe_dome_full_ramp_from_flat_levels.json"
)
#: the curvature measures the study analyses
MEASURES = ("kappa_circle_x [1/mm]", "kappa_quad_x [1/mm]")
#: per-step series kept in the data file (JSON-lines key -> data key)
STEP_KEYS = {
    "t [-]": "t [-]",
    "newton": "newton iterations [-]",
    "kappa_circle_x [1/mm]": None,
    "kappa_quad_x [1/mm]": None,
    "quad_rms_residual [mm]": None,
    "apex_z [mm]": None,
    "energy [mJ]": None,
}
ANALYSIS = "analysis of the levels from flat (validation.converge.analyse; h [mm])"


def _observables(model) -> dict:
    return {k: float(v) for k, v in model.observables().items() if not k.startswith("junction_")}


def run_level(level: int, out: pathlib.Path) -> dict:
    """Ramp the dome at ``level`` from flat, logging into ``out``; returns the final record."""
    from lcefem.validation.cases.gridshell_fe import fe_model
    from lcefem.validation.studies.gridshell import gridshell_bh as gs

    out.mkdir(parents=True, exist_ok=True)
    log_path, state = out / f"steps_level{level}.jsonl", out / f"dome_state_level{level}.npz"
    t0, c0 = time.perf_counter(), time.process_time()

    def cost() -> dict:
        return {
            "cpu [s]": time.process_time() - c0,
            "wall [s]": time.perf_counter() - t0,
            "peak [MiB]": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
        }

    with log_path.open("w") as log:

        def write(rec: dict) -> None:
            log.write(json.dumps(rec) + "\n")
            log.flush()

        model = fe_model("dome", mesh_level=level)
        write({"event": "built", "level": level, "dofs": model.ndofs, **cost()})

        def on_step(s) -> None:
            write({"t [-]": s.load_factor, "newton": s.iterations, **cost(), **_observables(model)})
            model.save_state(state)

        model.ramp(gs.SHAPES["dome"]["lambdas"], on_step=on_step)
        f = model.last_follower
        final = {
            "event": "final",
            "level": level,
            "dofs": model.ndofs,
            "newton": f.iterations,
            "cuts": f.cuts,
            "substeps": f.substeps,
            **cost(),
            **_observables(model),
        }
        write(final)
    return final


def analyse_levels(folder: pathlib.Path, data: pathlib.Path = DATA) -> dict:
    """Add the levels logged in ``folder`` to ``data`` and analyse the finished ones; returns the
    analysis (also written into ``data``)."""
    from dataclasses import asdict

    from lcefem.meshes.gridshell_fe import GridshellFEMesh
    from lcefem.validation.app.converge import analyse, ratio_warnings

    d = json.loads(data.read_text())
    for log_path in sorted(folder.glob("steps_level*.jsonl")):
        level = int(log_path.stem.removeprefix("steps_level"))
        recs = [json.loads(line) for line in log_path.read_text().splitlines() if line.strip()]
        steps = [r for r in recs if "event" not in r]
        final = [r for r in recs if r.get("event") == "final"]
        entry = {
            "steps": {
                (k if v is None else v): [r.get(k) for r in steps] for k, v in STEP_KEYS.items()
            }
        }
        if final:
            entry["final"] = {k: v for k, v in final[-1].items() if k != "event"}
            entry["peak memory [MiB]"] = final[-1]["peak [MiB]"]
        elif steps:
            entry["unfinished"] = (
                f"last accepted t = {steps[-1]['t [-]']:.4f} after {steps[-1]['cpu [s]']:.0f} s CPU"
            )
        d["levels"][str(level)] = entry
    levels = sorted(int(k) for k, v in d["levels"].items() if "final" in v)
    h = [GridshellFEMesh().size / (level + 1) for level in levels]
    result = {"levels": levels, "h [mm]": h, "ratio warnings": ratio_warnings(h)}
    if len(levels) >= 3:
        for key in MEASURES:
            vals = [d["levels"][str(level)]["final"][key] for level in levels]
            result[key] = asdict(analyse(h, vals, key, "1/mm"))
    d[ANALYSIS] = result
    tmp = data.with_suffix(".json.part")
    tmp.write_text(json.dumps(d, indent=1) + "\n")
    tmp.replace(data)
    return result


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--level", type=int, default=None, help="mesh level to ramp (0, 1, 2, ...)")
    p.add_argument(
        "--out", type=pathlib.Path, default=None, help="folder of the step logs and states"
    )
    p.add_argument(
        "--analyse",
        type=pathlib.Path,
        default=None,
        metavar="DIR",
        help="add the levels logged in DIR to --data and analyse them",
    )
    p.add_argument("--data", type=pathlib.Path, default=DATA)
    args = p.parse_args(argv)
    if args.analyse is not None:
        print(json.dumps(analyse_levels(args.analyse, args.data), indent=1))
        return 0
    if args.level is None or args.level < 0 or args.out is None:
        p.error("give --level L (>= 0) and --out DIR, or --analyse DIR")
    print(json.dumps(run_level(args.level, args.out), indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
