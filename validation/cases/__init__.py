"""Registry of validation cases.

A case is a function ``f(ctx: CaseContext) -> list[Metric]`` registered with :func:`case`. It runs
the models it needs, writes its CSV data and PNG figures into ``ctx.out``, records figures with
``ctx.add_figure(path, caption)``, sets ``ctx.mesh_size`` (characteristic element size [mm], or
another resolution measure for reduced-order models, e.g. rod edge length) when it has one, and
returns metrics.

``ctx.quick`` asks for the coarse resolution used in CI; ``ctx.level`` (int or None) asks for a
given refinement level (used by ``lcefem converge``; None means the case's default resolution).

Case modules are listed in CASE_MODULES (from their registrations with the bodies they validate,
lcefem.solvers.registry) and imported on first use, so a case that needs no FEniCSx never imports
it.

Helpers: ``ctx.case`` is the running case's name (a Metric built with case "" gets it from the
runner); ``ctx.path(name)`` is ``ctx.out / name``; :func:`write_csv` writes columns with units in
the headers; reference numbers come from :func:`lcefem.validation.cases.reference_data.reference`,
figures from
:mod:`lcefem.validation.app.plots` (curves, convergence, maps) and
:mod:`lcefem.validation.app.render` (deformed 3D bodies). ``lcefem validate`` writes
``ctx.out/metrics.json`` after the case returns.
"""

from __future__ import annotations

import dataclasses
import importlib
import math
import pathlib
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from lcefem.solvers.registry import case_modules

#: Marks an informative row that has a reference but is deliberately not judged; the text after it
#: says why (a what-if, a model vs model comparison with no agreed band, a pre-asymptotic pair...).
#: The report counts informative rows with a reference that lack it as "without a reason".
NOT_JUDGED = "not judged: "

#: Modules that define cases (imported lazily by :func:`registry`), in the order of their
#: registration with the bodies they validate (lcefem.solvers.registry.register_cases).
CASE_MODULES: list[str] = case_modules()


@dataclass(frozen=True)
class Metric:
    """One checked number. ``passed`` is ``|value - reference| <= tolerance`` (None when
    informative).

    Keys match metrics.json: case, metric, value, unit, reference, tolerance, passed, source.
    A range check lo <= value <= hi is stored as reference (lo+hi)/2, tolerance (hi-lo)/2.
    """

    case: str
    metric: str
    value: float
    unit: str
    reference: float | None
    tolerance: float | None
    passed: bool | None
    source: str

    @classmethod
    def within(
        cls,
        case: str,
        metric: str,
        value: float,
        unit: str,
        reference: float,
        tolerance: float,
        source: str,
    ) -> "Metric":
        """Pass when |value - reference| <= tolerance (absolute, in ``unit``)."""
        ok = bool(math.isfinite(value) and abs(value - reference) <= tolerance)
        return cls(case, metric, float(value), unit, float(reference), float(tolerance), ok, source)

    @classmethod
    def relative(
        cls,
        case: str,
        metric: str,
        value: float,
        unit: str,
        reference: float,
        rel_tol: float,
        source: str,
    ) -> "Metric":
        """Pass when |value - reference| <= rel_tol |reference|."""
        return cls.within(case, metric, value, unit, reference, rel_tol * abs(reference), source)

    @classmethod
    def between(
        cls,
        case: str,
        metric: str,
        value: float,
        unit: str,
        lower: float,
        upper: float,
        source: str,
    ) -> "Metric":
        """Pass when lower <= value <= upper."""
        return cls.within(
            case, metric, value, unit, 0.5 * (lower + upper), 0.5 * (upper - lower), source
        )

    @classmethod
    def info(
        cls,
        case: str,
        metric: str,
        value: float,
        unit: str,
        source: str,
        reference: float | None = None,
    ) -> "Metric":
        """A reported number with no pass/fail (``passed`` is None)."""
        ref = None if reference is None else float(reference)
        return cls(case, metric, float(value), unit, ref, None, None, source)

    def as_dict(self) -> dict:
        return dataclasses.asdict(self)


@dataclass
class CaseContext:
    """What a case gets: resolution wishes and where to write; what it gives back besides
    metrics."""

    out: pathlib.Path
    quick: bool = False
    level: int | None = None
    progress: bool = True
    mesh_size: float | None = None
    figures: list[tuple[pathlib.Path, str]] = field(default_factory=list)
    case: str = ""  #: name of the running case (set by the runner; Metric.case may be left "")
    mesh_size_unit: str = "mm"  #: unit of ``mesh_size`` (e.g. "mm", or "-" for a count)
    #: ``lcefem converge --prolong``: the previous (coarser) level's folder; a case registered with
    #: ``prolong=True`` starts from the state it saved there instead of solving from scratch
    prolong_from: pathlib.Path | None = None

    def __post_init__(self) -> None:
        # Absolute from the start: every path a case builds from ``out`` (``ctx.path``) then means
        # the same file whatever the working directory, and is never joined to ``out`` a second
        # time.
        self.out = pathlib.Path(self.out).absolute()
        if self.prolong_from is not None:
            self.prolong_from = pathlib.Path(self.prolong_from).absolute()

    def add_figure(self, path: pathlib.Path, caption: str) -> None:
        """Record a figure written by the case; ``caption`` should name the sources of its data.

        A relative ``path`` is taken relative to ``ctx.out`` (as ``ctx.path`` builds them)."""
        path = pathlib.Path(path)
        self.figures.append((path if path.is_absolute() else self.out / path, caption))

    def path(self, name: str) -> pathlib.Path:
        """``ctx.out / name``, creating ``ctx.out`` if needed."""
        self.out.mkdir(parents=True, exist_ok=True)
        return self.out / name


@dataclass(frozen=True)
class Case:
    name: str
    run: Callable[[CaseContext], list[Metric]]
    description: str
    fe: bool  # needs FEniCSx
    convergence: bool  # meaningful under ``lcefem converge`` (honours ctx.level)
    prolong: bool = False  # honours ctx.prolong_from (``lcefem converge --prolong``)


_CASES: dict[str, Case] = {}

#: Affinity groups: cases that share an in-process cache, so that ``mpiexec -n N lcefem validate``
#: runs each group on one rank, in registry order, as the serial run does: the shared work is done
#: once and each case starts from the state it has in the serial run (same answers for any N).
AFFINITY: dict[str, tuple[str, ...]] = {
    # ribbon.ribbon_metrics' _RUNS: every one of them runs the 100 C plate, 0.05 turn/mm ribbon
    "ribbon_rolling": (
        "ribbon_threshold",
        "ribbon_twist_density",
        "ribbon_helical",
        "ribbon_end_spin",
    ),
    # beam_fe._EQUILIBRIA: beam_curvature_fe starts from the map's (1.33, 1.05) equilibrium
    "beam_fe": ("beam_curvature_map_fe", "beam_curvature_fe"),
    # Not grouped: gridshell_fe._bh_shape (the bar-and-hinge shape that gridshell_shapes_fe,
    # gridshell_sweep_fe and gridshell_heated_fe compare with) costs seconds, while the three FE
    # cases together (2100 s at the full level) would outlast every other rank's work.
}


def case(
    name: str, description: str, *, fe: bool, convergence: bool = False, prolong: bool = False
):
    """Decorator registering a case function under ``name``."""

    def register(func: Callable[[CaseContext], list[Metric]]):
        if name in _CASES:
            raise ValueError(f"case {name!r} registered twice")
        _CASES[name] = Case(name, func, description, fe, convergence, prolong)
        return func

    return register


def not_judged(metrics: list[Metric], reason: str) -> list[Metric]:
    """``metrics`` with ``NOT_JUDGED + reason`` prefixed to the source of every informative row that
    has a reference and no reason yet (e.g. a block of model vs model rows sharing one reason)."""
    return [
        dataclasses.replace(m, source=f"{NOT_JUDGED}{reason}; {m.source}")
        if m.passed is None and m.reference is not None and NOT_JUDGED not in m.source
        else m
        for m in metrics
    ]


def registry() -> dict[str, Case]:
    """All cases, importing the case modules on first call."""
    for module in CASE_MODULES:
        importlib.import_module(module)
    return dict(_CASES)


def write_csv(
    path: pathlib.Path, columns: dict[str, Sequence[float]], *, fmt: str = "{:.9g}"
) -> pathlib.Path:
    """Write equal-length columns to CSV, atomically (``*.part`` then rename).

    Column names carry their unit, e.g. ``{"time [s]": t, "temperature [C]": T}``.
    """
    import csv

    names = list(columns)
    missing = [n for n in names if not (n.endswith("]") and "[" in n)]
    if missing:
        raise ValueError(f"CSV column names need a unit in brackets: {missing}")
    cols = [list(columns[n]) for n in names]
    if len({len(c) for c in cols}) > 1:
        raise ValueError(f"columns of {path} differ in length: {[len(c) for c in cols]}")
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".part")
    from lcefem.solvers.runtime.files import naming

    try:
        with naming(tmp), tmp.open("w", newline="") as fh:
            writer = csv.writer(fh)
            writer.writerow(names)
            for row in zip(*cols):
                writer.writerow([fmt.format(float(v)) for v in row])
    except BaseException:
        tmp.unlink(missing_ok=True)  # a full disk: give the space back
        raise
    tmp.replace(path)
    return path
