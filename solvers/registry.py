"""Every body registers once: its name, configuration, problem, default program and exports and
the ``lcefem run`` target that runs it; every validation case module registers once with the body
it validates (:func:`register_cases`; a case of no body's, e.g. the empirical laws, with None).
``lcefem run <target>`` (lcefem.validation.app.commands.RUN_TARGETS) and ``lcefem validate``'s cases
(lcefem.validation.cases.CASE_MODULES, in registration order) come from these registrations;
validation/data/case_costs.toml (read by lcefem.validation.app.farm.case_costs) gives the expected
wall time of the cases those modules define, by case name.

A registration names things by import path ("module:attribute"), so reading the registry imports
no solver (the bar-and-hinge commands start without FEniCSx)::

    from lcefem.solvers.registry import body
    strip = body("strip")
    cfg = strip.config_class()()                    # StripConfig()
    problem = strip.build(cfg)                      # StripSimulation(cfg)
    run(problem, strip.default_program(cfg), strip.default_exports(problem), out,
        config=cfg.resolved())

``program(config) -> Program`` and ``exports(problem) -> list`` are the body's defaults for the
one door (lcefem.solvers.runner.run). Every registered ``run`` goes through that door; a body
whose run follows a path of its own (``run_ribbon``, ``run_specimen_fe``, the FE gridshell's,
``run_body``) builds its problem for it there (lcefem.solvers.runner.PathProblem) and registers no
default program. Adding a body is one :func:`register` call here (and its command module, if it
has a target of its own), and one :func:`register_cases` for its validation cases.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass


def _load(path: str):
    """The object at "package.module:Attr.attr"."""
    module, _, attr = path.partition(":")
    obj = importlib.import_module(module)
    for part in attr.split("."):
        obj = getattr(obj, part)
    return obj


@dataclass(frozen=True)
class Body:
    """One body's registration (module docstring). ``target``: its ``lcefem run`` target (two
    models of one body, e.g. the bar-and-hinge and the FE beam, share one, chosen by --model);
    ``command``: the module of that target under lcefem.validation.app.commands; :attr:`cases`: its
    validation case modules (registered by :func:`register_cases`)."""

    name: str
    what: str
    target: str
    command: str
    config: str
    problem: str
    run: str | None
    program: str | None = None
    exports: str | None = None

    @property
    def cases(self) -> tuple[str, ...]:
        """Its validation case modules (:func:`register_cases` naming this body), in run order."""
        return tuple(m for m, owner in CASES.items() if owner == self.name)

    def config_class(self):
        return _load(self.config)

    def build(self, config, *args, **kw):
        """The body's problem from its configuration (forms compiled once)."""
        return _load(self.problem)(config, *args, **kw)

    def runner(self) -> Callable:
        """The body's run function (config, out, ...) -> summary or result (None: run by its
        command's own studies)."""
        return None if self.run is None else _load(self.run)

    def default_program(self, config):
        """The body's default program from its configuration (None: its run drives a path of its
        own)."""
        return None if self.program is None else _load(self.program)(config)

    def default_exports(self, problem) -> list:
        return [] if self.exports is None else list(_load(self.exports)(problem))


BODIES: dict[str, Body] = {}
#: {validation case module (under lcefem.validation.cases): the body it validates, or None (a case
#: of no body's, e.g. the empirical laws)}, in the order ``lcefem validate`` runs them.
CASES: dict[str, str | None] = {}


def register(entry: Body) -> Body:
    """Add a body (its name unique)."""
    if entry.name in BODIES:
        raise ValueError(f"body {entry.name!r} registered twice")
    BODIES[entry.name] = entry
    return entry


def register_cases(owner: str | None, *modules: str) -> None:
    """Add validation case modules (names under lcefem.validation.cases, each once), after those
    registered before, as the cases of the body ``owner`` (a registered body's name) or of none."""
    if owner is not None and owner not in BODIES:
        raise ValueError(f"cases {modules}: body {owner!r} not registered")
    for module in modules:
        if module in CASES:
            raise ValueError(f"case module {module!r} registered twice")
        CASES[module] = owner


def case_modules() -> list[str]:
    """The validation case modules, full names, in the order ``lcefem validate`` runs their cases
    (lcefem.validation.cases.CASE_MODULES)."""
    return [f"lcefem.validation.cases.{m}" for m in CASES]


def body(name: str) -> Body:
    from lcefem.models.errors import InputError

    if name not in BODIES:
        raise InputError(f"body {name!r}: allowed {', '.join(BODIES)}")
    return BODIES[name]


def targets() -> dict[str, str]:
    """{``lcefem run`` target: its command module name}, in registration order."""
    out: dict[str, str] = {}
    for b in BODIES.values():
        out.setdefault(b.target, b.command)
    return out


_P = "lcefem.solvers.problems."
register(
    Body(
        "ribbon",
        "a twisted LCE ribbon rolling on a hot plate (Discrete Elastic Rods)",
        "ribbon",
        "ribbon",
        _P + "twisted_ribbon_der:RibbonConfig",
        _P + "twisted_ribbon_der:RollingRibbonDER",
        _P + "twisted_ribbon_der:run_ribbon",
    )
)
register(
    Body(
        "strip",
        "the LCE strip heated by its coil, 3D FE thermo-mechanics (seed 001, Fig. 2)",
        "strip",
        "strip",
        _P + "strip:StripConfig",
        _P + "strip:StripSimulation",
        _P + "strip:run_strip",
        program=_P + "strip:strip_program",
        exports=_P + "strip:strip_exports",
    )
)
register(
    Body(
        "beam",
        "the composite beam, bar-and-hinge (Fig. 3)",
        "beam",
        "beam",
        _P + "composite_beam_bh:BeamConfig",
        _P + "composite_beam_bh:beam_problem",
        _P + "composite_beam_bh:run_beam",
        program=_P + "composite_beam_bh:beam_program",
    )
)
register(
    Body(
        "beam-fe",
        "the composite beam in 3D FE, lambdas prescribed or a coil current",
        "beam",
        "beam",
        _P + "composite_beam_run:BeamFEConfig",
        _P + "composite_beam_run:beam_fe_problem",
        _P + "composite_beam_run:run_beam_fe",
        program=_P + "composite_beam_run:beam_fe_program",
        exports=_P + "composite_beam_run:beam_fe_exports",
    )
)
register(
    Body(
        "ribbon-buckling",
        "the Kapton ribbon's buckling test, bar-and-hinge (Fig. 2G)",
        "ribbon-buckling",
        "ribbon_buckling",
        _P + "kapton_specimen_bh:KaptonSpecimenConfig",
        _P + "kapton_specimen_bh:specimen_problem",
        _P + "kapton_specimen_bh:run_specimen",
    )
)
register(
    Body(
        "ribbon-buckling-fe",
        "the Kapton ribbon's buckling test in 3D FE",
        "ribbon-buckling",
        "ribbon_buckling",
        _P + "kapton_specimen:KaptonSpecimenFEConfig",
        _P + "kapton_specimen:KaptonSpecimenFE",
        _P + "kapton_specimen:run_specimen_fe",
    )
)
register(
    Body(
        "gridshell",
        "the robotic surface, bar-and-hinge (Fig. 4, 5)",
        "gridshell",
        "gridshell",
        _P + "gridshell_bh_run:GridshellBHRunConfig",
        _P + "gridshell_bh:GridshellBH",
        _P + "gridshell_bh_run:run_gridshell",
    )
)
register(
    Body(
        "gridshell-fe",
        "the robotic surface in 3D FE, lambdas prescribed or heated",
        "gridshell",
        "gridshell",
        _P + "gridshell:GridshellConfig",
        _P + "gridshell:GridshellFE",
        None,
    )
)
register(
    Body(
        "body",
        "your own 3D FE LCE body from a mesh and a case file (docs/own_robot.md)",
        "body",
        "body",
        _P + "body_case:BodyCase",
        _P + "body:BodyProblem",
        _P + "body:run_body",
    )
)


# The validation cases (lcefem.validation.cases.CASE_MODULES and so ``lcefem validate``'s order and
# names; validation/data/case_costs.toml is keyed by the names of the cases these modules define),
# each with the body it validates.
register_cases("ribbon", "ribbon")
register_cases(None, "empirical")  # the empirical laws (Eq. 1, Eq. 2, the tension law): no body's
register_cases("beam", "beam_bar_hinge")
register_cases("strip", "strip")
register_cases("beam-fe", "beam_fe")
register_cases("ribbon-buckling-fe", "ribbon_fe")
register_cases("gridshell", "gridshell_bh")
register_cases("gridshell-fe", "gridshell_fe", "gridshell_heated_fe")
register_cases(
    "gridshell",
    "gridshell_uncertainty",
    "gridshell_design_bh",
    "gridshell_reach_bh",
    "gridshell_reach_study_bh",
    "gridshell_fig5_bh",
    "gridshell_control_bh",
    "gridshell_bh_vs_fe",
)


__all__ = [
    "BODIES",
    "Body",
    "CASES",
    "body",
    "case_modules",
    "register",
    "register_cases",
    "targets",
]
