"""One run of ``lcefem run gridshell`` in the bar-and-hinge model (:class:`GridshellBHRunConfig`,
:func:`run_gridshell`) and the configuration departures (:data:`DEPARTURES`). The programs it runs
(named shapes: lambdas, currents and support per shape; named recipes: P0 per group and support) are
given with the configuration (``GridshellBHRunConfig.shapes``, ``.recipes``): the experiments' data,
which the caller reads (the command line: lcefem.validation.cases.programs). The problem itself is
:class:`lcefem.solvers.problems.gridshell_bh.GridshellBH`.

Units: mm, N, t, s.
"""

from __future__ import annotations

import pathlib
import time
from dataclasses import dataclass, field, replace

import numpy as np

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.meshes.composite_beam import BeamBarHingeMesh, CompositeBeamGeometry
from lcefem.meshes.gridshell import GridshellLayout, build_gridshell_bar_hinge
from lcefem.models import bar_hinge_materials as law
from lcefem.models.errors import InputError
from lcefem.models.limits import check_current
from lcefem.models.loads import SurfaceWeight
from lcefem.models.lumped_heat import CurrentRouteConfig, check_held_current, shape_currents
from lcefem.models.parameters import check, describe, param
from lcefem.solvers.bar_hinge import NewtonOptions, PathOptions, PathResult
from lcefem.solvers.contraction_curve import law_summary
from lcefem.solvers.current_routes import curve_law, route_from_config
from lcefem.solvers.exports import BarHingeFrames
from lcefem.solvers.problems.gridshell_bh import (
    GRIDSHELL_PATH,
    PENETRATION_LIMIT,
    RAMP_NEWTON,
    SUPPORTS,
    GridshellBH,
    GridshellBHConfig,
    shape_summary,
    strip_ribbon_penetration,
    targets_from_lambdas,
    targets_from_recipe,
)
from lcefem.solvers.runner import HistoryExport, run_quasi_static
from lcefem.solvers.runtime.files import write_text
from lcefem.solvers.runtime.run import Progress

#: Our departures from the published configuration, each a named option (``run.departures``,
#: ``--departure``) on top of it: what it changes and why we have it.
DEPARTURES = {
    "contact": "frictionless unilateral strip-ribbon contact (mesh.contact = true; the published "
    "model "
    "has only the weak strip-panel springs, so a strip can pass through its ribbon)",
    "contracting_squares": "the raised top squares contract with the top strips "
    "(mesh.top_junction = "
    "'lce', as lambda_T of Eq. 2 assumes; published: non-contracting glue bars)",
    "volume_law": "strip bar force (A/lambda) P(p) at constant volume (lce.force_law = 'volume'; "
    "published: A f P(p))",
    "middle_rollers": "the 8 rollers on both edges of the middle ribbons' ends ('middle_rollers', "
    "our "
    "former reading; published: the outer ribbons' outer-edge end nodes); only where "
    "the published support is 'rollers'",
    "strip_beam": "the strip element (mesh.strip_element = 'beam'): each LCE strip acts at its "
    "centroid, "
    "t_p/2 + h_s/2 = 0.909 mm off the ribbon, and has its own bending stiffness E I "
    "(published: two-node bars on the ribbon's nodes; docs/gridshell_calibration.md)",
}
#: The bar-and-hinge model sets (``run.model_set``, ``--model-set``), each the published
#: configuration (supports, glue squares) plus the departures it always takes: the ribbon stays
#: impenetrable in both (issue 46: without the contact the published model's strips pass up to 3.6
#: mm through the ribbon and the dustpan lands 11.7 mm RMS from the published code's own run; with
#: it 0.5 mm). 'fe-calibrated' adds the FE's constant-volume bar law and the strip element; its
#: fitted materials (hinge and strip E I factors, the plate's torsion) and exchange factor are the
#: caller's (lcefem.validation.studies.gridshell.calibrate.model_set).
MODEL_SET_DEPARTURES = {
    "published": ("contact",),
    "fe-calibrated": ("contact", "volume_law", "strip_beam"),
}
#: How a run is configured (``run.configuration``): "model-set" (default) = the model set's
#: configuration (:data:`MODEL_SET_DEPARTURES`) + ``run.departures``; "published" = the published
#: script exactly (no strip-ribbon contact: strips may pass through the ribbon) +
#: ``run.departures``, with the published model set only.
CONFIGURATIONS = ("model-set", "published")


def parse_departures(text, name: str = "run.departures") -> tuple[str, ...]:
    """'contact,volume_law' (or a list) -> ('contact', 'volume_law'), each checked."""
    items = text if isinstance(text, (list, tuple)) else [t for t in str(text or "").split(",")]
    out = tuple(t.strip() for t in items if str(t).strip())
    for t in out:
        if t not in DEPARTURES:
            raise InputError(f"{name}: unknown departure {t!r} (allowed: {', '.join(DEPARTURES)})")
    return out


def published_configuration(
    mesh: BeamBarHingeMesh, lce: law.LCEStripBars, support: str, departures=()
) -> tuple[BeamBarHingeMesh, law.LCEStripBars, str]:
    """(mesh, lce, support) of the published model (no contact, glue squares, A f P(p), the given
    published support) with the named :data:`DEPARTURES` applied."""
    dep = parse_departures(departures)
    mesh = replace(
        mesh,
        contact="contact" in dep,
        top_junction="lce" if "contracting_squares" in dep else "glue",
        strip_element="beam" if "strip_beam" in dep else "bar",
    )
    lce = replace(lce, force_law="volume" if "volume_law" in dep else "published")
    if "middle_rollers" in dep and support == "rollers":
        support = "middle_rollers"
    return mesh, lce, support


#: How a named shape is driven (GridshellRun.route).
ROUTES = ("lambda", "current")


@dataclass(frozen=True)
class GridshellRun:
    """What the experimenter chooses: a named shape or recipe, and the support."""

    shape: str = param(
        "",
        "-",
        "a named shape of the configuration's programs (shapes: lambdas and "
        "currents per channel, support)",
    )
    recipe: str = param(
        "",
        "-",
        "a named recipe of the configuration's programs (recipes: rest "
        "fraction P0 per group, support)",
    )
    support: str = param(
        "",
        "-",
        "clamp, rollers, middle_rollers or table (default: the published "
        "support of the shape/recipe, rollers otherwise)",
    )
    model_set: str = param(
        "published",
        "-",
        "the bar-and-hinge model set whose configuration the run "
        "takes (MODEL_SET_DEPARTURES): 'published' or 'fe-calibrated' (its fitted "
        "materials in the kapton and lce sections are the caller's: "
        "lcefem.validation.studies.gridshell.calibrate.model_set; the command's default)",
    )
    configuration: str = param(
        "model-set",
        "-",
        "'model-set' (the model set's configuration, the "
        "ribbon impenetrable) or 'published' (the published script exactly: no "
        "strip-ribbon contact; published model set only); plus run.departures",
    )
    departures: str = param(
        "", "-", "comma-separated departures added to the configuration: " + ", ".join(DEPARTURES)
    )
    route: str = param(
        "lambda",
        "-",
        "with a shape: 'lambda' (the Fig. 4 lambdas) or 'current' (the "
        "currents the paper's rule gives at those lambdas, Eq. 1 inverted through the "
        "grid strip's coil, models.lumped_heat.shape_currents, through the current route)",
    )

    def checked(self) -> "GridshellRun":
        if self.route not in ROUTES:
            raise InputError(f"run.route = {self.route!r}: allowed {', '.join(ROUTES)}")
        if self.route == "current" and not self.shape:
            raise InputError(
                "run.route = 'current': needs a shape (--shape); give currents with --current"
            )
        if self.shape and self.recipe:
            raise InputError("run.shape and run.recipe: give one of them")
        if self.support and self.support not in SUPPORTS:
            raise InputError(f"run.support = {self.support!r}: allowed {', '.join(SUPPORTS)}")
        if self.model_set not in MODEL_SET_DEPARTURES:
            raise InputError(
                f"run.model_set = {self.model_set!r}: allowed {', '.join(MODEL_SET_DEPARTURES)}"
            )
        if self.configuration not in CONFIGURATIONS:
            raise InputError(
                f"run.configuration = {self.configuration!r}: allowed {', '.join(CONFIGURATIONS)}"
            )
        if self.configuration == "published" and self.model_set != "published":
            raise InputError(
                "run.configuration = 'published' (the published script): only with the "
                "published model set (--model-set published)"
            )
        parse_departures(self.departures)
        return self

    @property
    def resolved_departures(self) -> tuple[str, ...]:
        """The departures from the published script the run takes: the model set's (unless the
        configuration is the published script), then run.departures."""
        base = () if self.configuration == "published" else MODEL_SET_DEPARTURES[self.model_set]
        return tuple(dict.fromkeys((*base, *parse_departures(self.departures))))


@dataclass(frozen=True)
class GridshellBHRunConfig(law.BarHingeMaterials):
    """The bar-and-hinge gridshell's sections: its materials (kapton, lce, glue, strip_contact,
    contact, ogden: inherited from the one definition,
    :class:`lcefem.models.bar_hinge_materials.BarHingeMaterials`) plus the run, geometry, layout,
    mesh, weight, current route, solver and path sections, and the drives: lambdas [-] or currents
    [A] per selection."""

    run: GridshellRun = field(default_factory=GridshellRun)
    geometry: CompositeBeamGeometry = field(default_factory=CompositeBeamGeometry)
    layout: GridshellLayout = field(default_factory=GridshellLayout)
    mesh: BeamBarHingeMesh = field(default_factory=BeamBarHingeMesh)
    weight: SurfaceWeight = field(default_factory=SurfaceWeight)
    current_route: CurrentRouteConfig = field(default_factory=CurrentRouteConfig)
    solver: NewtonOptions = field(default_factory=lambda: RAMP_NEWTON)
    path: PathOptions = field(default_factory=lambda: GRIDSHELL_PATH)
    lambdas: dict = field(default_factory=dict)  # selection -> lambda [-]
    currents: dict = field(default_factory=dict)  # selection -> current [A]
    #: The named programs run.shape and run.recipe choose from (the experiments' data, given by the
    #: caller): shape -> {"lambdas": {channel: lambda [-]}, "currents": {channel: current [A]},
    #: "support"}; recipe -> ({group: P0 [-]}, support).
    shapes: dict = field(default_factory=dict)
    recipes: dict = field(default_factory=dict)

    PARAM_SECTIONS = (
        "run",
        "geometry",
        "layout",
        "mesh",
        "kapton",
        "lce",
        "glue",
        "strip_contact",
        "contact",
        "weight",
        "current_route",
        "solver",
        "path",
    )

    def validated(self) -> "GridshellBHRunConfig":
        for name in self.PARAM_SECTIONS:
            check(getattr(self, name), name)
        self.run.checked()
        if self.run.shape and self.run.shape not in self.shapes:
            raise InputError(f"run.shape = {self.run.shape!r}: allowed {', '.join(self.shapes)}")
        if self.run.recipe and self.run.recipe not in self.recipes:
            raise InputError(f"run.recipe = {self.run.recipe!r}: allowed {', '.join(self.recipes)}")
        self.layout.checked()
        self.mesh.checked()
        self.current_route.checked()
        curve_law(self.current_route)  # a bad curve file is an InputError before the run
        named = bool(self.run.shape or self.run.recipe)
        if named and (self.lambdas or self.currents):
            raise InputError(
                "--lambda/--current: not with --shape or --recipe (they set the strips)"
            )
        if self.lambdas and self.currents:
            raise InputError("--lambda and --current: give one of them")
        for sel, v in {**self.lambdas, **self.currents}.items():
            if not isinstance(v, (int, float)) or isinstance(v, bool):
                raise InputError(f"{sel} = {v!r}: must be a number")
        for sel, v in self.currents.items():
            check_current(f"current {sel}", v)
            # held for the whole run: its steady temperature bounded as a schedule's is (before the
            # run)
            check_held_current(
                f"current {sel}",
                v,
                *self.current_route.temperature_model(curve_law(self.current_route)),
            )
        return self

    @property
    def named_support(self) -> str:
        if self.run.support:
            return self.run.support
        if self.layout.support:  # the layout's own support (lcefem.meshes.gridshell_layout)
            return self.layout.support
        if self.run.shape:
            return self.shapes[self.run.shape]["support"]
        if self.run.recipe:
            return self.recipes[self.run.recipe][1]
        return "rollers"

    @property
    def effective(self) -> tuple[BeamBarHingeMesh, law.LCEStripBars, str]:
        """(mesh, lce, support) the run uses: the published configuration with the model set's
        departures and run.departures (``GridshellRun.resolved_departures``) on the mesh and lce
        sections (their other fields as given; the model set's materials are the caller's); a
        layout's own support wins over the shape's published one."""
        support = self.named_support
        if (
            not self.run.support and not self.layout.support and self.run.shape
        ):  # the shape's published one
            support = "clamp" if self.shapes[self.run.shape]["support"] == "clamp" else "rollers"
        return published_configuration(self.mesh, self.lce, support, self.run.resolved_departures)

    @property
    def support(self) -> str:
        return self.effective[2]

    @property
    def effective_materials(self) -> law.BarHingeMaterials:
        return replace(self.materials, lce=self.effective[1])

    def resolved(self) -> dict:
        out = {name: describe(getattr(self, name)) for name in self.PARAM_SECTIONS}
        out["current_route"]["segment"]["value"] = describe(self.current_route.segment)
        out["current_route"]["strip"]["value"] = describe(self.current_route.strip)
        out["current_route"].update(law_summary(curve_law(self.current_route)))
        out["lambda"] = dict(self.lambdas)
        out["current"] = dict(self.currents)
        mesh, lce, support = self.effective
        out["support (resolved)"] = support
        out["configuration (resolved)"] = {
            "model set": self.run.model_set,
            "configuration": self.run.configuration,
            "departures": list(self.run.resolved_departures),
            "mesh.contact": mesh.contact,
            "mesh.top_junction": mesh.top_junction,
            "mesh.strip_element": mesh.strip_element,
            "lce.force_law": lce.force_law,
            "lce.bending_factor": self.lce.bending_factor,
            "kapton.bending_factor": self.kapton.bending_factor,
            "kapton.twist": self.kapton.twist,
            "current_route.exchange_factor": self.current_route.exchange_factor,
        }
        return out


def strip_targets(cfg: GridshellBHRunConfig, structure: BarHingeStructure) -> tuple[dict, dict]:
    """(rest fractions per bar by group, description of the drive) for the configuration."""
    lam_n = cfg.lce.lambda_N
    if cfg.run.recipe:
        recipe = cfg.recipes[cfg.run.recipe][0]
        return targets_from_recipe(structure, recipe), {"recipe": cfg.run.recipe, "P0": recipe}
    if cfg.run.shape and cfg.run.route == "current":
        currents = shape_currents(
            cfg.shapes[cfg.run.shape]["lambdas"], cfg.current_route.strip.resistance
        )
        lambdas = route_from_config(cfg.current_route, lam_n).lambdas(currents)
        return targets_from_lambdas(structure, lambdas, lam_n, "current"), {
            "shape": cfg.run.shape,
            "route": "current",
            "current [A]": currents,
            "current rule": "Eq. 1 inverted at the Fig. 4 lambdas through the grid strip's coil "
            "(models.lumped_heat.eq1_current)",
            "lambda (from current)": lambdas,
            "thermal model": cfg.current_route.thermal_model,
        }
    if cfg.run.shape:
        lambdas = cfg.shapes[cfg.run.shape]["lambdas"]
        return targets_from_lambdas(structure, lambdas, lam_n), {
            "shape": cfg.run.shape,
            "lambda": lambdas,
        }
    if cfg.currents:
        lambdas = route_from_config(cfg.current_route, lam_n).lambdas(cfg.currents)
        return targets_from_lambdas(structure, lambdas, lam_n, "current"), {
            "current [A]": cfg.currents,
            "lambda (from current)": lambdas,
            "thermal model": cfg.current_route.thermal_model,
        }
    return targets_from_lambdas(structure, cfg.lambdas, lam_n), {"lambda": cfg.lambdas}


def write_nodes_csv(path: pathlib.Path, reference: np.ndarray, x: np.ndarray) -> pathlib.Path:
    """Node table with units: id, as-built x0, y0, z0 and final x, y, z [mm] (.part, then
    renamed)."""
    lines = ["node id [-],x0 [mm],y0 [mm],z0 [mm],x [mm],y [mm],z [mm]"]
    lines += [
        f"{i}," + ",".join(f"{v:.9g}" for v in (*r, *xi))
        for i, (r, xi) in enumerate(zip(reference, x))
    ]
    return write_text(path, "\n".join(lines) + "\n")


COLUMNS = [
    "load factor [-]",
    "circle kappa_x [1/mm]",
    "circle kappa_y [1/mm]",
    "quad kappa_x [1/mm]",
    "quad kappa_y [1/mm]",
    "z range [mm]",
    "newton iterations [-]",
]
SIGN = (
    "kappa = d^2 w/ds^2 with w along the centre junction's normal on the top strips' side: "
    "negative for a dome (cap), positive for a bowl (seed 001: dome negative)"
)


def run_gridshell(
    cfg: GridshellBHRunConfig, out: pathlib.Path, progress: bool = True, report=None
) -> dict:
    """Ramp the gridshell (:class:`GridshellBH`, its rest fractions per bar set to the configured
    drives) through the one door (:func:`lcefem.solvers.runner.run_quasi_static`) and write
    history.csv (:data:`COLUMNS`; the quadratic fit needs >= 3 x 3 junctions), gridshell.pvd +
    gridshell_steps/*.vtp, nodes.csv and summary.json into ``out``; returns the summary.
    ``report(out, cfg, structure, x, drive)`` (optional: the validation's render) runs before the
    summary is written."""
    cfg = cfg.validated()
    out = pathlib.Path(out)
    mesh, _, support = cfg.effective
    structure = build_gridshell_bar_hinge(cfg.geometry, cfg.layout, mesh)
    targets, drive_info = strip_targets(cfg, structure)
    problem = GridshellBH(
        structure,
        GridshellBHConfig(
            materials=cfg.effective_materials,
            weight=cfg.weight,
            geometry=cfg.geometry,
            support=support,
            solver=cfg.solver,
            path=cfg.path,
        ),
    )
    model = problem.model
    quad = cfg.layout.ribbons >= 3
    columns = [c for c in COLUMNS if quad or not c.startswith("quad")]

    def row(state) -> dict:
        summ = shape_summary(structure, state.x)
        values = {
            "load factor [-]": state.t,
            "circle kappa_x [1/mm]": summ["circle_x"],
            "circle kappa_y [1/mm]": summ["circle_y"],
            "z range [mm]": summ["z_range [mm]"],
            "newton iterations [-]": state.iterations,
        }
        if quad:
            values.update(
                {"quad kappa_x [1/mm]": summ["quad_kx"], "quad kappa_y [1/mm]": summ["quad_ky"]}
            )
        return values

    bar = Progress(1.0, "gridshell", "load", ".3f", progress)
    started = time.perf_counter()
    problem.set_rest_fractions(targets)  # per bar: the load program below sets no drives of its own

    def summarize(run, path: PathResult) -> dict:
        wall = time.perf_counter() - started
        x = path.states[-1].x
        write_nodes_csv(out / "nodes.csv", structure.nodes, x)
        if report is not None:
            report(out, cfg, structure, x, drive_info)
        final_fraction = model.rest_fractions()
        reached = all(np.array_equal(final_fraction[g], targets[g]) for g in targets)
        lam_n = cfg.lce.lambda_N
        per_strip: dict[int, list[float]] = {}
        for g, ids in structure.info["strip_of_bar"].items():
            for sid, f in zip(ids, targets[g]):
                per_strip.setdefault(int(sid), []).append(float(f) * lam_n)
        depth = strip_ribbon_penetration(x, cfg.geometry, cfg.layout, mesh)
        return {
            "model": "bar-hinge gridshell",
            "drive": drive_info,
            "support": cfg.support,
            "model set": cfg.run.model_set,
            "strip-ribbon penetration [mm]": depth,
            "strips pass through the ribbon": bool(depth > PENETRATION_LIMIT),
            "penetration limit [mm]": PENETRATION_LIMIT,
            "strips": [
                {
                    "id": s.id,
                    "group": s.group,
                    "channel": s.channel,
                    "midpoint [mm]": s.midpoint,
                    "lambda [-]": float(np.mean(per_strip[s.id])),
                }
                for s in structure.info["strips"]
            ],
            "results": {
                **shape_summary(structure, x),
                "sign convention": SIGN,
                "target reached exactly": bool(reached),
            },
            "dofs": int(model.ndof),
            "nodes": int(structure.num_nodes),
            "increments": len(path.states) - 1,
            "newton_iterations": int(sum(path.newton_iterations)),
            "failed_increments": path.failed_increments,
            "wall_time [s]": wall,
        }

    return run_quasi_static(
        problem,
        {},
        out,
        config=cfg.resolved(),
        history=HistoryExport(tuple(columns), row),
        fields=BarHingeFrames("gridshell", structure, model),
        progress=bar,
        summarize=summarize,
    )
