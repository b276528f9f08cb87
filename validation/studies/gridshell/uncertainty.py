"""``lcefem uncertainty gridshell``: prediction bands of the robotic surface's centre curvatures
from the measured spreads of seed 001, and which input dominates (Sobol indices).

``lcefem uncertainty gridshell --shape dome|saddle|cylinder|table [--samples N] [--sobol-samples M]
[--thermal-model eq1|segment] [--seed S] [--out DIR] [--overwrite] [--quiet]``

The chain per channel c (Tx, Ty, Bx, By; each an independent coil, so every input is sampled per
channel; the LCE modulus is one material):

    P_c = I_c^2 R_coil (R_c / 130 ohm) p_c  ->  lambda_c = law(P_c)
        ->  f_c = min(lambda_c, lambda_N,c) / lambda_N,c

law: Eq. 1 (thermal model 'eq1', the paper's own estimate, R_coil = 146.6 ohm) or the lumped steady
balance of a 25 ohm grid segment ('segment'); f_c the rest fraction of the channel's strip bars. The
bar-and-hinge surface then gives the centre curvatures (both measures), warm-started from the
nominal equilibrium. Inputs (:func:`gridshell_inputs`, each with its source): string resistance R_c
uniform 126-134 ohm; current I_c uniform within +-5 % of its set value; lambda_N,c normal with the
nematic length's relative SD (130.22 +- 8.01 mm); Eq. 1 power factor p_c uniform within +-5 %; Ogden
moduli factor uniform within +-10 %.

Bands: median and 5-95 % of N Monte Carlo forward solves. Sobol indices (first order S1, total ST,
by input kind, SALib): on a surrogate, a least-squares polynomial of the curvatures in the five
quantities the mechanics sees (four rest fractions, modulus factor), validated by leave-one-out
(Q^2 reported; indices flagged when Q^2 < 0.9); the heat chain stays exact. They are computed only
when the equilibria outnumber the linear surrogate's six coefficients (at least 7; with fewer the
fit interpolates and leave-one-out cannot test it).

Outputs (run skeleton): samples.csv (inputs, rest fractions, curvatures per sample, units in the
headers), bands.csv (quantity, median, 5 %, 95 %, nominal, paper measured, inside), sobol.csv,
summary.json.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import pathlib
import time
from dataclasses import dataclass

import numpy as np

from lcefem.models import lumped_heat
from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
from lcefem.models.empirical import eq1_stretch
from lcefem.models.errors import ConvergenceError, InputError
from lcefem.models.heat import GRID_STRING_RESISTANCE_RANGE, Coil, GridSegmentCoil
from lcefem.models.hyperelastic import OgdenLaw
from lcefem.models.limits import check_current
from lcefem.models.lumped_heat import GRID_STRIP, HeatedStrip, grid_thermal, steady_stretch
from lcefem.solvers.analysis.sensitivity import UncertainInput, sample_inputs, sobol_indices
from lcefem.solvers.problems import gridshell_bh as problem_bh
from lcefem.solvers.problems.gridshell_bh_sequence import QuasiStaticSurface
from lcefem.solvers.runtime.checks import check_seed
from lcefem.solvers.runtime.files import write_text
from lcefem.solvers.runtime.outdir import add_out_arguments
from lcefem.solvers.runtime.run import Progress, Run
from lcefem.validation.studies.gridshell import calibrate
from lcefem.validation.studies.gridshell import gridshell_bh as gs

PARALLEL = False  # serial numpy/scipy bar-and-hinge model
TARGETS = ("gridshell",)
CHANNELS = ("Tx", "Ty", "Bx", "By")
DEFAULT_SAMPLES = (
    8  #: forward solves per band: small, each warm-started solve of the dome takes 1-200 s
)
#: (an asymmetric sample breaks the dome's symmetry near a bifurcation: 95-1314 Newton iterations
#: measured; 5 dome samples took 45 min on 2 cores at load 8-17)
MAX_SOBOL = 8192  #: largest --sobol-samples: chosen, 8 x the default (98,304 surrogate evaluations)
DEFAULT_SOBOL = 1024  #: SALib base samples on the surrogate (N (2 G + 2) evaluations, G = 5 kinds)
Q2_VALID = 0.9  #: leave-one-out Q^2 above which the surrogate's Sobol indices are reported as valid
#: Path from the nominal equilibrium to a sample: a sample is a small perturbation, so try the whole
#: step first (halved on failure, as the default ramp) instead of the as-built ramp's 0.1
#: increments.
WARM_PATH = dataclasses.replace(problem_bh.GRIDSHELL_PATH, initial_increment=1.0, max_increment=1.0)

#: The string resistance range [ohm] (models.heat) and its mid-range, the nominal string.
STRING_RESISTANCE = GRID_STRING_RESISTANCE_RANGE
NOMINAL_STRING = 0.5 * sum(STRING_RESISTANCE)
KINDS = {
    "resistance": (
        "string resistance",
        "ohm",
        "seed 001, Results: coil resistances 'ranging from 126 to "
        "134 ohms': uniform; the strip's coil resistance scaled by R/130 ohm",
    ),
    "current": (
        "current factor",
        "-",
        "seed 001: 'the magnitude of current flowing through each LCE strip "
        "varies around the assigned values' (no number): assumed uniform +-5 %",
    ),
    "lambda_N": (
        "lambda_N",
        "-",
        "seed 001, Results: nematic length 130.22 +- 8.01 mm (1 SD, 9 strips) "
        "on 80 mm: relative SD 6.15 %, applied to the grid's lambda_N = 1.4 (normal)",
    ),
    "power": (
        "Eq. 1 power factor",
        "-",
        "issue 15: Eq. 1 power +-5 % (seed 001's powers 1.5 +- 0.068, "
        "3.26 +- 0.15, 5.79 +- 0.27 W are +-4.5-4.7 %): uniform",
    ),
    "modulus": (
        "Ogden modulus factor",
        "-",
        "assumed uniform +-10 % on the published Ogden moduli: the "
        "tension fit (Fig. 2E, published reduced-order model) gives no uncertainty; 10 % is a "
        "typical specimen-to-specimen spread of LCE tension tests",
    ),
}
LAMBDA_N_REL_SD = 8.01 / 130.22


def gridshell_inputs(shape: str) -> list[UncertainInput]:
    """The 17 uncertain inputs of a Fig. 4 shape (module docstring): per channel resistance,
    current factor, lambda_N, power factor; one modulus factor. Groups: the input kinds."""
    out = []
    for c in CHANNELS:
        out += [
            UncertainInput(
                f"{c} resistance", "unif", STRING_RESISTANCE, "resistance", KINDS["resistance"][2]
            ),
            UncertainInput(
                f"{c} current factor", "unif", (0.95, 1.05), "current", KINDS["current"][2]
            ),
            UncertainInput(
                f"{c} lambda_N",
                "norm",
                (PUBLISHED_LAMBDA_N, LAMBDA_N_REL_SD * PUBLISHED_LAMBDA_N),
                "lambda_N",
                KINDS["lambda_N"][2],
            ),
            UncertainInput(f"{c} power factor", "unif", (0.95, 1.05), "power", KINDS["power"][2]),
        ]
    out.append(UncertainInput("modulus factor", "unif", (0.9, 1.1), "modulus", KINDS["modulus"][2]))
    return out


def nominal_row(inputs: list[UncertainInput]) -> np.ndarray:
    return np.array([i.mean for i in inputs])


@dataclass(frozen=True)
class StretchLaw:
    """Steady lambda [-] of a strip against the Joule power I^2 R [mW] of its coil (vectorised)."""

    thermal_model: str = "eq1"
    #: The grid strip's exchange factor [-] (thermal model 'strip'): the model set's calibrated one
    #: (:attr:`lcefem.validation.studies.gridshell.calibrate.ModelSet.exchange_factor`; default the
    #: published set's).
    exchange_factor: float = lumped_heat.GRID_EXCHANGE_FACTOR

    @property
    def coil_resistance(self) -> float:
        """Nominal coil resistance [ohm] the set currents meet (Coil: Eq. 1's free strip, 146.6 ohm;
        GridSegmentCoil: a 25 ohm grid segment; 'strip': the grid strip's 130 ohm, issue 31)."""
        if self.thermal_model == "strip":
            return GRID_STRIP.resistance
        return Coil().resistance if self.thermal_model == "eq1" else GridSegmentCoil().resistance

    def __call__(self, power):
        power = np.asarray(power, dtype=float)
        if self.thermal_model == "eq1":
            return eq1_stretch(power)
        # the lumped steady stretch depends on I^2 R only: tabulate over the power once
        table_p, table_l = (
            _segment_table()
            if self.thermal_model == "segment"
            else _strip_table(self.exchange_factor)
        )
        return np.interp(power, table_p, table_l)


_SEGMENT_TABLE: list = []
_STRIP_TABLES: dict = {}


def _strip_table(exchange_factor: float = lumped_heat.GRID_EXCHANGE_FACTOR):
    """(power [mW], steady lambda [-]) of the grid strip with the grid exchange factor
    ``exchange_factor`` [-] (issue 31), per factor."""
    if exchange_factor not in _STRIP_TABLES:
        r = GRID_STRIP.resistance
        currents = np.linspace(0.0, 0.3, 601)
        model = grid_thermal(exchange_factor)
        lam = np.array([steady_stretch(float(i), GRID_STRIP, model) for i in currents])
        _STRIP_TABLES[exchange_factor] = [currents**2 * r * 1.0e3, lam]  # mW
    return _STRIP_TABLES[exchange_factor]


def _segment_table():
    if not _SEGMENT_TABLE:
        r = GridSegmentCoil().resistance
        currents = np.linspace(0.0, 0.3, 601)
        lam = np.array([steady_stretch(float(i), HeatedStrip(resistance=r)) for i in currents])
        _SEGMENT_TABLE[:] = [currents**2 * r * 1.0e3, lam]  # mW
    return _SEGMENT_TABLE


def rest_fractions_of(
    X: np.ndarray, shape: str, law: StretchLaw, currents: dict | None = None
) -> np.ndarray:
    """Per-channel rest fractions f_c (m, 4) of input samples X (m, 17) (module docstring) around
    the nominal ``currents`` [A] per channel (default: the shape's programmed currents)."""
    X = np.atleast_2d(X)
    currents = gs.SHAPES[shape]["currents"] if currents is None else currents
    f = np.empty((X.shape[0], len(CHANNELS)))
    for k, c in enumerate(CHANNELS):
        r, i_fac, lam_n, p_fac = (X[:, 4 * k + j] for j in range(4))
        current = currents[c] * i_fac
        power = current**2 * law.coil_resistance * (r / NOMINAL_STRING) * p_fac * 1.0e3  # mW
        lam_n = np.maximum(lam_n, 1.0 + 1e-6)  # a normal tail below 1 would be no LCE strip at all
        f[:, k] = np.minimum(law(power), lam_n) / lam_n
    return f


def features(
    X: np.ndarray, shape: str, law: StretchLaw, currents: dict | None = None
) -> np.ndarray:
    """What the mechanics sees: (f_Tx, f_Ty, f_Bx, f_By, modulus factor), (m, 5)."""
    X = np.atleast_2d(X)
    return np.column_stack([rest_fractions_of(X, shape, law, currents), X[:, -1]])


# -------------------------------------------------------------------------------- surrogate
def _design(Z: np.ndarray, degree: int) -> np.ndarray:
    cols = [np.ones(len(Z))] + [Z[:, j] for j in range(Z.shape[1])]
    if degree >= 2:
        cols += [Z[:, i] * Z[:, j] for i in range(Z.shape[1]) for j in range(i, Z.shape[1])]
    return np.column_stack(cols)


@dataclass
class PolynomialSurrogate:
    """Least-squares polynomial y(z) (degree 1 or 2) on centred, scaled features, with leave-one-out
    validation: Q^2 = 1 - PRESS / sum (y - mean)^2 (PRESS from the hat matrix, exact for least
    squares)."""

    centre: np.ndarray
    scale: np.ndarray
    coef: np.ndarray
    degree: int
    q2: np.ndarray
    loo_rms: np.ndarray

    @classmethod
    def fit(cls, Z: np.ndarray, Y: np.ndarray, degree: int | None = None) -> "PolynomialSurrogate":
        Z, Y = np.asarray(Z, float), np.asarray(Y, float).reshape(len(Z), -1)
        d = Z.shape[1]
        quad_terms = 1 + d + d * (d + 1) // 2
        degree = degree or (2 if len(Z) >= 3 * quad_terms else 1)
        centre, scale = Z.mean(axis=0), Z.std(axis=0)
        scale[scale == 0] = 1.0
        A = _design((Z - centre) / scale, degree)
        coef, *_ = np.linalg.lstsq(A, Y, rcond=None)
        if len(Z) <= A.shape[1]:
            # No more points than coefficients: the fit interpolates, the hat matrix is the identity
            # and leave-one-out has nothing to test (it would report Q^2 = 1): not validated.
            nan = np.full(Y.shape[1], np.nan)
            return cls(centre, scale, coef, degree, nan, nan.copy())
        hat = np.einsum("ij,ji->i", A, np.linalg.pinv(A))
        resid = Y - A @ coef
        loo = resid / np.maximum(1.0 - hat, 1e-12)[:, None]
        ss = ((Y - Y.mean(axis=0)) ** 2).sum(axis=0)
        with np.errstate(invalid="ignore", divide="ignore"):
            q2 = np.where(ss > 0, 1.0 - (loo**2).sum(axis=0) / ss, 1.0)
        return cls(centre, scale, coef, degree, q2, np.sqrt((loo**2).mean(axis=0)))

    @property
    def validated(self) -> bool:
        """Whether leave-one-out could test the fit (more points than coefficients; else Q^2 is
        nan)."""
        return bool(np.all(np.isfinite(self.q2)))

    @staticmethod
    def min_points(features: int) -> int:
        """Fewest points for which the linear surrogate in ``features`` variables is validated by
        leave-one-out (one more than its 1 + features coefficients)."""
        return features + 2

    def __call__(self, Z: np.ndarray) -> np.ndarray:
        return _design((np.atleast_2d(Z) - self.centre) / self.scale, self.degree) @ self.coef


# -------------------------------------------------------------------------------- study
OUTPUTS = {
    "circle kappa_x [1/mm]": "circle_x",
    "circle kappa_y [1/mm]": "circle_y",
    "quad kappa_x [1/mm]": "quad_kx",
    "quad kappa_y [1/mm]": "quad_ky",
}


@dataclass(frozen=True)
class BandsConfig:
    shape: str = "dome"
    samples: int = DEFAULT_SAMPLES
    sobol_samples: int = DEFAULT_SOBOL
    thermal_model: str = "eq1"
    seed: int = 0
    model_set: str = calibrate.DEFAULT_MODEL_SET
    #: Nominal currents [A] per channel around which the spreads are drawn (None: the shape's
    #: programmed currents, validation/data/programs.toml).
    currents: dict | None = None
    #: Grid exchange factor [-] of the 'strip' thermal model: None, the one calibrated with the
    #: model set (:attr:`lcefem.validation.studies.gridshell.calibrate.ModelSet.exchange_factor`); a
    #: number overrides it.
    exchange_factor: float | None = None
    #: Also actuate every sample from flat (the run's ramp, what the robot does) and count the
    #: samples whose run from flat ends on another branch than the nominal's, continued warm to the
    #: sample (issue 50; doubles the solves).
    branch_check: bool = True

    def checked(self) -> "BandsConfig":
        if self.shape not in gs.SHAPES:
            raise InputError(f"--shape {self.shape!r}: allowed {', '.join(gs.SHAPES)}")
        if not 4 <= self.samples <= 10000:
            raise InputError(f"--samples {self.samples}: must be between 4 and 10000")
        if self.sobol_samples < 2 or self.sobol_samples & (self.sobol_samples - 1):
            raise InputError(f"--sobol-samples {self.sobol_samples}: must be a power of 2")
        if self.sobol_samples > MAX_SOBOL:  # N (2 G + 2) surrogate evaluations and their arrays
            raise InputError(f"--sobol-samples {self.sobol_samples}: must be <= {MAX_SOBOL}")
        check_seed("--seed", self.seed)
        if self.thermal_model not in lumped_heat.THERMAL_MODELS:
            raise InputError(
                f"--thermal-model {self.thermal_model!r}: allowed "
                f"{', '.join(lumped_heat.THERMAL_MODELS)}"
            )
        if self.model_set not in calibrate.MODEL_SETS:
            raise InputError(
                f"--model-set {self.model_set!r}: allowed {', '.join(calibrate.MODEL_SETS)}"
            )
        if self.currents is not None:
            if set(self.currents) != set(CHANNELS):
                raise InputError(
                    f"currents: one per channel, {', '.join(CHANNELS)}; got "
                    f"{', '.join(self.currents)}"
                )
            for c, i in self.currents.items():
                check_current(f"currents[{c}]", i)
        if self.exchange_factor is not None and not (
            math.isfinite(self.exchange_factor) and self.exchange_factor > 0
        ):
            raise InputError(f"--exchange-factor {self.exchange_factor}: must be > 0")
        return self


def sample_columns() -> list[str]:
    cols = ["sample [-]"]
    for c in CHANNELS:
        cols += [
            f"{c} string resistance [ohm]",
            f"{c} current [A]",
            f"{c} lambda_N [-]",
            f"{c} power factor [-]",
            f"{c} lambda [-]",
            f"{c} rest fraction [-]",
        ]
    return cols + ["modulus factor [-]", *OUTPUTS, "newton iterations [-]"]


def paper_measured(shape: str) -> dict:
    """The paper's measured centre curvatures (circle measure, seed 001) by output column, or {}."""
    exp = gs.SHAPES[shape]["paper_exp"]
    if exp[0] is None:
        return {}
    return {"circle kappa_x [1/mm]": exp[0], "circle kappa_y [1/mm]": exp[1]}


def bands_table(values: dict, nominal: dict, shape: str) -> list[dict]:
    """Median and 5-95 % band per output, with the paper's measured value and whether it lies
    inside."""
    paper = paper_measured(shape)
    rows = []
    for col, v in values.items():
        v = np.asarray(v, float)
        lo, med, hi = np.percentile(v, [5, 50, 95])
        ref = paper.get(col)
        rows.append(
            {
                "quantity": col,
                "median": float(med),
                "p5": float(lo),
                "p95": float(hi),
                "nominal": float(nominal[col]),
                "paper measured": ref,
                "inside": None if ref is None else bool(lo <= ref <= hi),
            }
        )
    return rows


#: Two equilibria of one sample are on different branches when a circle curvature differs by more
#: than this [1/mm]: the design tolerance
#: (lcefem.validation.studies.design.gridshell_design.DESIGN_TOLERANCE).
BRANCH_TOLERANCE = 1.0e-4


def ends_elsewhere_from_flat(flat: QuasiStaticSurface, targets: dict, nominal_branch: dict) -> bool:
    """True when ``flat`` (a surface at the as-built state) actuated to ``targets`` ends more than
    :data:`BRANCH_TOLERANCE` from ``nominal_branch``'s circle curvatures, or finds no
    equilibrium."""
    try:
        flat.advance(targets)
    except ConvergenceError:
        return True
    k = flat.curvatures()
    return (
        max(
            abs(k["circle_x"] - nominal_branch["circle_x"]),
            abs(k["circle_y"] - nominal_branch["circle_y"]),
        )
        > BRANCH_TOLERANCE
    )


def run_bands(cfg: BandsConfig, out: pathlib.Path | None, progress: bool = True) -> dict:
    """Monte Carlo bands, surrogate and Sobol indices of one shape (module docstring)."""
    cfg = cfg.checked()
    spec = gs.SHAPES[cfg.shape]
    currents = dict(spec["currents"] if cfg.currents is None else cfg.currents)
    model_set = calibrate.model_set(
        cfg.model_set
    )  # its configuration (squares, contact, element) too
    route = model_set.current_route(
        exchange_factor=cfg.exchange_factor
    )  # the set's factor unless given
    law = StretchLaw(cfg.thermal_model, route.exchange_factor)
    inputs = gridshell_inputs(cfg.shape)
    structure, base = model_set.structure(), model_set.materials
    started = time.perf_counter()

    def targets(fr: np.ndarray) -> dict:
        return problem_bh.targets_from_recipe(structure, dict(zip(CHANNELS, map(float, fr))))

    def surface(modulus: float, start=None) -> QuasiStaticSurface:
        ogden = OgdenLaw()
        materials = dataclasses.replace(
            base, ogden=OgdenLaw(tuple(modulus * m for m in ogden.mu), ogden.alpha)
        )
        return QuasiStaticSurface(
            structure,
            spec["support"],
            materials,
            start=start,
            path=problem_bh.GRIDSHELL_PATH if start is None else WARM_PATH,
        )

    x_nom = nominal_row(inputs)
    f_nom = rest_fractions_of(x_nom, cfg.shape, law, currents)[0]
    nominal = surface(1.0)
    nominal.advance(targets(f_nom))
    start = (nominal.fractions, nominal.x)
    nom_summary = nominal.curvatures()
    nominal_values = {col: nom_summary[key] for col, key in OUTPUTS.items()}

    X = sample_inputs(inputs, cfg.samples, cfg.seed)
    F = rest_fractions_of(X, cfg.shape, law, currents)
    bar = Progress(float(cfg.samples), f"bands {cfg.shape}", "solves", ".0f", progress)
    config = {
        "shape": cfg.shape,
        "support": spec["support"],
        "currents [A]": currents,
        "thermal model": cfg.thermal_model,
        "model set": cfg.model_set,
        "model set configuration": {
            **model_set.configuration,
            "current.exchange_factor": route.exchange_factor,
        },
        "samples": cfg.samples,
        "seed": cfg.seed,
        "inputs": [dataclasses.asdict(i) for i in inputs],
    }
    with Run(
        out, config=config, columns=sample_columns(), history="samples.csv", progress=bar
    ) as run:
        Y = np.full((cfg.samples, len(OUTPUTS)), np.nan)
        found = np.zeros(cfg.samples, dtype=bool)
        lost: list[dict] = []  # inputs of the samples without an equilibrium
        other = np.zeros(cfg.samples, dtype=bool)  # from flat: another branch than the nominal's
        for s in range(cfg.samples):
            surf = surface(float(X[s, -1]), start)
            try:
                surf.advance(targets(F[s]))
            except ConvergenceError:
                # Neither the warm start nor a ramp from as built reaches this sample's equilibrium
                # (a fold on the way, e.g. the dome near t = 0.84): it is left out of the bands and
                # counted, not the end of the study.
                pass
            else:
                summ = surf.curvatures()
                Y[s] = [summ[key] for key in OUTPUTS.values()]
                found[s] = True
                if cfg.branch_check:
                    other[s] = ends_elsewhere_from_flat(
                        surface(float(X[s, -1])), targets(F[s]), summ
                    )
            row = {
                "sample [-]": s,
                "modulus factor [-]": X[s, -1],
                "newton iterations [-]": surf.iterations,
            }
            for k, c in enumerate(CHANNELS):
                r, i_fac, lam_n, p_fac = X[s, 4 * k : 4 * k + 4]
                row.update(
                    {
                        f"{c} string resistance [ohm]": r,
                        f"{c} current [A]": currents[c] * i_fac,
                        f"{c} lambda_N [-]": lam_n,
                        f"{c} power factor [-]": p_fac,
                        f"{c} lambda [-]": F[s, k] * max(lam_n, 1.0 + 1e-6),
                        f"{c} rest fraction [-]": F[s, k],
                    }
                )
            if found[s]:
                row.update(dict(zip(OUTPUTS, Y[s])))
                run.record(row, where=f"sample {s}", at=float(s + 1))
            else:  # samples.csv holds equilibria only; this sample's inputs go to summary.json
                lost.append({k: float(v) for k, v in row.items()})
                run.progress.to(float(s + 1))
        if 2 * found.sum() < cfg.samples:
            raise ConvergenceError(
                f"bands {cfg.shape}",
                f"only {int(found.sum())} of {cfg.samples} samples reached an equilibrium",
            )
        values = {col: Y[found, j] for j, col in enumerate(OUTPUTS)}
        bands = bands_table(values, nominal_values, cfg.shape)

        Z = features(X[found], cfg.shape, law, currents)
        sur = PolynomialSurrogate.fit(Z, Y[found])
        # Sobol indices need a surrogate that leave-one-out can test (more equilibria than its
        # coefficients); with fewer (e.g. the validation case's 4 samples) they are not computed.
        sobol = {}
        if sur.validated:
            sobol = sobol_indices(
                lambda XX: sur(features(XX, cfg.shape, law, currents)),
                inputs,
                cfg.sobol_samples,
                cfg.seed,
                list(OUTPUTS),
            )
        for j, col in enumerate(OUTPUTS if sobol else ()):
            sobol[col]["surrogate Q2"] = float(sur.q2[j])
            sobol[col]["surrogate LOO rms [1/mm]"] = float(sur.loo_rms[j])
            sobol[col]["valid"] = bool(sur.q2[j] >= Q2_VALID)
            st = sobol[col]["ST"]
            sobol[col]["dominant"] = (
                sobol[col]["names"][int(np.argmax(st))] if max(st) > 0 else None
            )
        if out is not None:
            write_bands(pathlib.Path(out) / "bands.csv", bands)
            write_sobol(pathlib.Path(out) / "sobol.csv", sobol)
        return run.complete(
            {
                "model": "bar-hinge gridshell, Monte Carlo prediction bands",
                "shape": cfg.shape,
                "support": spec["support"],
                "thermal model": cfg.thermal_model,
                "samples": cfg.samples,
                "samples without equilibrium": int(cfg.samples - found.sum()),
                "lost samples": lost,
                "samples on another branch from flat": (
                    {
                        "count": int(other[found].sum()),
                        "share [-]": float(other[found].mean()),
                        "criterion": f"the run from flat ends more than {BRANCH_TOLERANCE:g} 1/mm "
                        "(either "
                        "circle "
                        "curvature) from the nominal branch continued to the sample (or has no "
                        "equilibrium)",
                    }
                    if cfg.branch_check
                    else None
                ),
                "nominal": nominal_values,
                "bands": bands,
                "surrogate": {
                    "degree": sur.degree,
                    "features": ["f_Tx", "f_Ty", "f_Bx", "f_By", "modulus factor"],
                    "points": int(len(Z)),
                    "min points for Sobol": PolynomialSurrogate.min_points(Z.shape[1]),
                },
                "sobol": sobol,
                "input kinds": {
                    k: {"name": v[0], "unit": v[1], "source": v[2]} for k, v in KINDS.items()
                },
                "wall_time [s]": time.perf_counter() - started,
            }
        )


def _fmt(v) -> str:
    return "" if v is None else (f"{v:.6g}" if isinstance(v, float) else str(v))


def write_bands(path: pathlib.Path, bands: list[dict]) -> pathlib.Path:
    lines = [
        "quantity,median [1/mm],p5 [1/mm],p95 [1/mm],nominal [1/mm],paper measured [1/mm],inside "
        "[-]"
    ]
    lines += [
        ",".join(
            [b["quantity"].split(" [")[0]]
            + [_fmt(b[k]) for k in ("median", "p5", "p95", "nominal", "paper measured", "inside")]
        )
        for b in bands
    ]
    return write_text(path, "\n".join(lines) + "\n")


def write_sobol(path: pathlib.Path, sobol: dict) -> pathlib.Path:
    lines = [
        "quantity,input kind,S1 [-],S1 conf95 [-],ST [-],ST conf95 [-],surrogate Q2 [-],valid [-]"
    ]
    for col, s in sobol.items():
        for k, name in enumerate(s["names"]):
            lines.append(
                ",".join(
                    [
                        col.split(" [")[0],
                        name,
                        *(f"{s[key][k]:.4f}" for key in ("S1", "S1_conf", "ST", "ST_conf")),
                        f"{s['surrogate Q2']:.4f}",
                        str(s["valid"]),
                    ]
                )
            )
    return write_text(path, "\n".join(lines) + "\n")


# -------------------------------------------------------------------------------- command line
def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("target", choices=TARGETS, help="the body: gridshell (bar-and-hinge)")
    p.add_argument(
        "--shape",
        default="dome",
        help="a Fig. 4 shape: " + ", ".join(gs.SHAPES) + " (default dome)",
    )
    p.add_argument(
        "--samples",
        type=int,
        default=DEFAULT_SAMPLES,
        help=f"Monte Carlo forward solves (default {DEFAULT_SAMPLES}: small, the solves are slow)",
    )
    p.add_argument(
        "--sobol-samples",
        type=int,
        default=DEFAULT_SOBOL,
        help=f"SALib base samples on the surrogate, a power of 2 (default {DEFAULT_SOBOL})",
    )
    p.add_argument(
        "--thermal-model",
        choices=lumped_heat.THERMAL_MODELS,
        default="eq1",
        help="current -> lambda: 'eq1' (the paper's estimate, default) or 'segment'",
    )
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument(
        "--model-set",
        default=calibrate.DEFAULT_MODEL_SET,
        help="bar-and-hinge model set with its configuration: fe-calibrated (default; glue "
        "squares, contact, strip element 'beam', the fitted factors) or published (two-node "
        "strip bars, contracting squares; docs/gridshell_calibration.md)",
    )
    p.add_argument(
        "--exchange-factor",
        type=float,
        default=None,
        help="grid exchange factor of thermal model 'strip' (default: the one calibrated with "
        "the model set, validation/data/grid_exchange_calibration*.json)",
    )
    add_out_arguments(p, None)


def prepare(args: argparse.Namespace) -> BandsConfig:
    return BandsConfig(
        args.shape,
        args.samples,
        args.sobol_samples,
        args.thermal_model,
        args.seed,
        args.model_set,
        exchange_factor=args.exchange_factor,
    ).checked()


def out_folder(args: argparse.Namespace) -> pathlib.Path:
    return args.out or pathlib.Path("results") / "uncertainty" / f"gridshell_{args.shape}"


def main(args: argparse.Namespace) -> int:
    cfg = args.prepared
    out = out_folder(args)
    summary = run_bands(cfg, out, progress=not args.quiet)
    for b in summary["bands"]:
        ref = (
            ""
            if b["paper measured"] is None
            else (f"; paper {b['paper measured']:+.4f} {'inside' if b['inside'] else 'OUTSIDE'}")
        )
        print(
            f"lcefem: {cfg.shape} {b['quantity']}: median {b['median']:+.4f}, 5-95 % "
            f"[{b['p5']:+.4f}, {b['p95']:+.4f}]{ref}"
        )
    if not summary["sobol"]:
        print(
            f"lcefem: Sobol indices not computed: {summary['surrogate']['points']} equilibria, the "
            "surrogate "
            f"needs {summary['surrogate']['min points for Sobol']}"
        )
    for col, s in summary["sobol"].items():
        if col.startswith("circle kappa_x"):
            print(
                f"lcefem: Sobol (circle kappa_x, surrogate Q2 {s['surrogate Q2']:.2f}): "
                + ", ".join(
                    f"{n} S1 {a:.2f} ST {b:.2f}" for n, a, b in zip(s["names"], s["S1"], s["ST"])
                )
            )
    other = summary["samples on another branch from flat"]
    if other is not None:
        print(
            f"lcefem: {other['count']} samples ({100 * other['share [-]']:.0f} %) end on another "
            "branch "
            "than "
            "the nominal when actuated from flat"
        )
    print(f"lcefem: {cfg.samples} samples, {summary['wall_time [s]']:.1f} s; results in {out}")
    return 0
