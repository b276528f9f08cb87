"""The bar-and-hinge current route of the Fig. 4 shapes in both bar-and-hinge model sets, next to
the stored FE current route and the experiment (issue 31, docs/gridshell_thermal.md).

Per shape, three drives of the same surface:

- ``rule``: the currents the paper's rule gives (Eq. 1 inverted at the shape's Fig. 4 lambdas
  through the grid strip's 130 ohm coil, :func:`lcefem.models.lumped_heat.shape_currents`), through
  the lumped grid strip (thermal model 'strip') to the strips' lambdas, with the grid exchange
  factor calibrated with each model set (:func:`set_route`,
  validation/data/grid_exchange_calibration*.json);
- ``fig4``: the Fig. 4 lambdas themselves (the lambda route): the rule against this splits the
  thermal chain from the lambda route;
- ``experiment``: the currents the experiment applied (the dome's 0.04 / 0.07 A, the same Fig. 2C
  pair for saddle and cylinder, :data:`lcefem.validation.studies.gridshell.gridshell_bh.SHAPES`
  "currents").

Model sets (:data:`lcefem.validation.studies.gridshell.calibrate.MODEL_SETS`):

- ``published``: the bar-and-hinge model as the validation cases build it by default (two-node strip
  bars, N5B8 panels' torsion, hinge factor 5.5, the shape's published support);
- ``fe-calibrated``: the strip element 'beam', the plate's torsion and the fitted factors of
  validation/data/bar_hinge_calibration.json, in the configuration they were fitted in (published
  supports and glue squares + strip-ribbon contact + the constant-volume bar law,
  :data:`lcefem.validation.studies.gridshell.calibrate.AS_FE`), i.e. exactly
  :func:`lcefem.validation.studies.gridshell.calibrate.shape_setup` with other lambdas.

``python -m lcefem.validation.studies.gridshell.gridshell_current_route [--out FILE.json]`` writes
validation/data/gridshell_current_route_bh_sets.json (to a .part name, then renamed). The BH solves
take seconds each.
"""

from __future__ import annotations

import argparse
import functools
import json
import pathlib
import time

from lcefem.models import lumped_heat

DATA = pathlib.Path(__file__).parents[2] / "data"
STORE = DATA / "gridshell_current_route_bh_sets.json"
FE_STORE = DATA / "gridshell_fe_current_route_level1.json"
SHAPES = ("dome", "saddle", "cylinder")
DRIVES = ("rule", "fig4", "experiment")
KEYS = ("circle_x", "circle_y", "quad_kx", "quad_ky")


def drive_lambdas(
    shape: str, drive: str, route: lumped_heat.CurrentRouteConfig = lumped_heat.CurrentRouteConfig()
) -> tuple[dict | None, dict]:
    """(currents [A] or None, lambdas [-]) of ``shape`` under ``drive`` (:data:`DRIVES`)."""
    from lcefem.validation.studies.gridshell import gridshell_bh as gs

    spec = gs.SHAPES[shape]
    if drive == "fig4":
        return None, dict(spec["lambdas"])
    currents = (
        lumped_heat.shape_currents(spec["lambdas"]) if drive == "rule" else dict(spec["currents"])
    )
    return currents, lumped_heat.lambda_assignments_from_currents(currents, route)


def set_route(
    model_set: str, exchange_factor: float | None = None
) -> lumped_heat.CurrentRouteConfig:
    """The current route ('strip') of ``model_set``: its own calibrated grid exchange factor
    (:attr:`lcefem.validation.studies.gridshell.calibrate.ModelSet.exchange_factor`), or
    ``exchange_factor`` [-]."""
    from lcefem.validation.studies.gridshell import calibrate

    return calibrate.model_set(model_set).current_route(exchange_factor=exchange_factor)


def bh_setup(
    shape: str,
    lambdas: dict,
    model_set: str = "published",
    lambda_N: float | None = None,
    support: str | None = None,
):
    """The bar-and-hinge gridshell of ``model_set`` set up at ``lambdas`` [-] on ``support``
    (default ``shape``'s published one; rest fractions lambda / ``lambda_N``, default the published
    1.4)."""
    from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
    from lcefem.solvers.problems import gridshell_bh as problem_bh
    from lcefem.validation.studies.gridshell import calibrate
    from lcefem.validation.studies.gridshell import gridshell_bh as gs

    lambda_N = PUBLISHED_LAMBDA_N if lambda_N is None else lambda_N
    support = support or gs.SHAPES[shape]["support"]
    ms = calibrate.model_set(
        model_set
    )  # in the configuration it was fitted in (calibrate.shape_setup)
    s = ms.structure()
    return problem_bh.setup_gridshell(
        problem_bh.targets_from_lambdas(s, lambdas, lambda_N),
        support,
        structure=s,
        materials=ms.materials,
    )


def bh_curvatures(
    shape: str, lambdas: dict, model_set: str = "published", support: str | None = None
) -> dict:
    """Centre curvatures [1/mm] (circle and quadratic fit) of :func:`bh_setup` solved from as built;
    cached per (shape, lambdas, model set, support) in a process."""
    return dict(_solved(shape, tuple(sorted(lambdas.items())), model_set, support))


@functools.lru_cache(maxsize=None)
def _solved(shape: str, lambdas: tuple, model_set: str, support: str | None) -> dict:
    from lcefem.solvers.problems import gridshell_bh as problem_bh

    t0 = time.process_time()
    sol = problem_bh.solve_gridshell(bh_setup(shape, dict(lambdas), model_set, support=support))
    return {**{k: float(sol.curvatures[k]) for k in KEYS}, "cpu [s]": time.process_time() - t0}


def fe_lambdas(held: dict) -> dict:
    """The FE held state's channel lambdas [-] (spontaneous stretch at each channel's mean T)."""
    return {c: float(held[f"lambda {c} [-]"]) for c in ("Tx", "Ty", "Bx", "By")}


def fe_stored() -> dict:
    """{shape: held observables} of the stored FE current route (level >= 1), or {}."""
    if not FE_STORE.exists():
        return {}
    return {s: r["held"] for s, r in json.loads(FE_STORE.read_text())["runs"].items()}


def measure(
    model_sets=("published", "fe-calibrated"), shapes=SHAPES, drives=DRIVES, log=print
) -> dict:
    from lcefem.validation.studies.gridshell import gridshell_bh as gs

    fe = fe_stored()
    out = {}
    for shape in shapes:
        row = {
            "support": gs.SHAPES[shape]["support"],
            "experiment circle x/y [1/mm]": list(gs.SHAPES[shape]["paper_exp"]),
        }
        if shape in fe:
            row["FE level 1, rule (stored)"] = {
                k: fe[shape][f"kappa_circle_{a} [1/mm]"]
                for k, a in (("circle_x", "x"), ("circle_y", "y"))
            }
        for drive in drives:
            currents, _ = drive_lambdas(shape, drive)
            d = {"currents [A]": currents}
            for ms in model_sets:  # each set's lambdas through its own calibrated exchange factor
                route = set_route(ms)
                _, lambdas = drive_lambdas(shape, drive, route)
                d[ms] = {
                    **bh_curvatures(shape, lambdas, ms),
                    "lambdas [-]": lambdas,
                    "exchange factor [-]": route.exchange_factor,
                }
                log(
                    f"{shape:8s} {drive:10s} {ms:13s} circle {d[ms]['circle_x']:+.4f} / "
                    f"{d[ms]['circle_y']:+.4f} "
                    f"({d[ms]['cpu [s]']:.1f} s CPU)"
                )
            row[drive] = d
        if shape in fe:
            # controlled change of the BH-FE comparison: the BH at the FE's own channel lambdas (the
            # mechanics alone) against the BH at the lumped strip's lambdas (mechanics + heat)
            lambdas = fe_lambdas(fe[shape])
            row["FE channel lambdas"] = {
                "lambdas [-]": lambdas,
                **{ms: bh_curvatures(shape, lambdas, ms) for ms in model_sets},
            }
        # controlled change of the support: the rule's currents on the table (seed 001: "not
        # anchored to the table"; gridshell_bh "table": weight + unilateral contact)
        row["rule, on the table"] = {}
        for ms in model_sets:
            _, lambdas = drive_lambdas(shape, "rule", set_route(ms))
            row["rule, on the table"][ms] = {
                **bh_curvatures(shape, lambdas, ms, "table"),
                "lambdas [-]": lambdas,
            }
        for key in ("FE channel lambdas", "rule, on the table"):
            if key in row:
                log(
                    f"{shape:8s} {key}: "
                    + "; ".join(
                        f"{ms} {row[key][ms]['circle_x']:+.4f} / {row[key][ms]['circle_y']:+.4f}"
                        for ms in model_sets
                    )
                )
        out[shape] = row
    return out


#: Stored prediction bands of the current route from the rule's currents (validation/data/...).
RULE_BANDS = DATA / "current_route_bands_rule"


def rule_bands(shape: str, samples: int, model_set: str, out: pathlib.Path, seed: int = 0) -> dict:
    """Monte Carlo prediction bands of the current route from the rule's currents: the measured
    spreads of :func:`lcefem.validation.studies.gridshell.uncertainty.gridshell_inputs` (coils
    126-134 ohm, current +-5 %, lambda_N SD 6.15 %, Eq. 1 power +-5 %, modulus +-10 %) around the
    rule's currents, through the lumped grid strip ('strip') and the bar-and-hinge surface of
    ``model_set`` (:func:`lcefem.validation.studies.gridshell.uncertainty.run_bands`, the same
    sampling and warm starts)."""
    from lcefem.validation.studies.gridshell import gridshell_bh as gs
    from lcefem.validation.studies.gridshell import uncertainty

    rule = lumped_heat.shape_currents(gs.SHAPES[shape]["lambdas"])
    return uncertainty.run_bands(
        uncertainty.BandsConfig(
            shape=shape,
            samples=samples,
            thermal_model="strip",
            seed=seed,
            model_set=model_set,
            currents=rule,
        ),
        out,
        progress=False,
    )


def main(argv=None) -> int:
    p = argparse.ArgumentParser(
        prog="python -m lcefem.validation.studies.gridshell.gridshell_current_route",
        description=__doc__.split("\n\n")[0],
    )
    p.add_argument(
        "--out",
        type=pathlib.Path,
        default=None,
        help=f"output (default {STORE.name}; with --bands the folder, default "
        f"{RULE_BANDS.name}/<shape>/)",
    )
    p.add_argument(
        "--bands",
        metavar="SHAPE",
        choices=SHAPES,
        help="instead: the prediction bands of the rule's currents for SHAPE",
    )
    p.add_argument(
        "--samples", type=int, default=64, help="Monte Carlo samples with --bands (default 64)"
    )
    p.add_argument(
        "--model-set",
        default="fe-calibrated",
        help="model set with --bands (default fe-calibrated)",
    )
    a = p.parse_args(argv)
    if a.bands:
        out = a.out or RULE_BANDS / a.bands
        res = rule_bands(a.bands, a.samples, a.model_set, out)
        for b in res["bands"]:
            print(
                f"{a.bands} {b['quantity']}: nominal {b['nominal']:+.4f}, 5-95 % [{b['p5']:+.4f}, "
                f"{b['p95']:+.4f}], measured {b['paper measured']}, inside {b['inside']}"
            )
        return 0
    a.out = a.out or STORE
    doc = {
        "what": __doc__.split("\n\n")[0].replace("\n", " "),
        "command": "python -m lcefem.validation.studies.gridshell.gridshell_current_route",
        "shapes": measure(),
    }
    part = a.out.with_suffix(".json.part")
    part.write_text(json.dumps(doc, indent=1) + "\n")
    part.replace(a.out)
    print(a.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
