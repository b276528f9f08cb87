"""Variance-based global sensitivity (Sobol indices) and sampling of uncertain inputs, with SALib
(Herman & Usher, JOSS 2017; Saltelli et al., Comput. Phys. Commun. 181, 2010).

An uncertain input is an :class:`UncertainInput`: a name, a distribution ("unif" over [lo, hi] or
"norm" with [mean, sd]) and an optional group (inputs of one group share an index, e.g. the four
channels' coil resistances). :func:`sample_inputs` draws independent Monte Carlo samples;
:func:`sobol_indices` evaluates a vectorised model on SALib's Saltelli/Sobol' design and returns the
first-order and total indices with their bootstrap 95 % confidence half-widths.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from lcefem.models.errors import InputError

DISTRIBUTIONS = ("unif", "norm")


@dataclass(frozen=True)
class UncertainInput:
    """One uncertain input: ``dist`` "unif" with ``params`` = (lo, hi), or "norm" with (mean,
    sd)."""

    name: str
    dist: str
    params: tuple[float, float]
    group: str = ""
    source: str = ""

    def checked(self) -> "UncertainInput":
        a, b = self.params
        if self.dist not in DISTRIBUTIONS:
            raise InputError(
                f"{self.name}: distribution {self.dist!r}: allowed {', '.join(DISTRIBUTIONS)}"
            )
        if self.dist == "unif" and not a < b:
            raise InputError(f"{self.name}: uniform bounds ({a}, {b}): need lo < hi")
        if self.dist == "norm" and not b > 0:
            raise InputError(f"{self.name}: normal sd = {b}: must be > 0")
        return self

    @property
    def mean(self) -> float:
        a, b = self.params
        return 0.5 * (a + b) if self.dist == "unif" else a

    @property
    def sd(self) -> float:
        a, b = self.params
        return (b - a) / np.sqrt(12.0) if self.dist == "unif" else b


def salib_problem(inputs: list[UncertainInput]) -> dict:
    """SALib's problem dictionary (groups only when every input names one)."""
    inputs = [i.checked() for i in inputs]
    problem = {
        "num_vars": len(inputs),
        "names": [i.name for i in inputs],
        "bounds": [list(i.params) for i in inputs],
        "dists": [i.dist for i in inputs],
    }
    if all(i.group for i in inputs):
        problem["groups"] = [i.group for i in inputs]
    return problem


def sample_inputs(inputs: list[UncertainInput], n: int, seed: int = 0) -> np.ndarray:
    """``n`` independent Monte Carlo samples (n, d) of the inputs."""
    rng = np.random.default_rng(seed)
    cols = []
    for i in (j.checked() for j in inputs):
        a, b = i.params
        cols.append(rng.uniform(a, b, n) if i.dist == "unif" else rng.normal(a, b, n))
    return np.column_stack(cols) if cols else np.zeros((n, 0))


def sobol_indices(
    model: Callable[[np.ndarray], np.ndarray],
    inputs: list[UncertainInput],
    base_samples: int = 1024,
    seed: int = 0,
    outputs: list[str] | None = None,
) -> dict:
    """First-order and total Sobol indices of a vectorised ``model`` (X (m, d) -> Y (m,) or (m, k)).

    ``base_samples`` N (a power of 2) gives N (2 D + 2) model evaluations, D the number of inputs or
    groups. Returns {output: {"names": [...], "S1", "S1_conf", "ST", "ST_conf": lists}}, the names
    being the groups when every input has one."""
    from SALib.analyze import sobol as analyze
    from SALib.sample import sobol as sample

    if base_samples < 2 or base_samples & (base_samples - 1):
        raise InputError(
            f"sobol base samples = {base_samples}: must be a power of 2 (SALib's Sobol' design)"
        )
    problem = salib_problem(inputs)
    X = sample.sample(problem, base_samples, calc_second_order=False, seed=seed)
    Y = np.asarray(model(X), dtype=float)
    Y = Y.reshape(len(X), -1)
    names = outputs or [f"y{k}" for k in range(Y.shape[1])]
    labels = list(dict.fromkeys(problem["groups"])) if "groups" in problem else problem["names"]
    out = {}
    for k, name in enumerate(names):
        y = Y[:, k]
        if np.ptp(y) == 0.0:  # a constant output: no variance to apportion
            zero = [0.0] * len(labels)
            out[name] = {
                "names": labels,
                "S1": zero,
                "S1_conf": zero,
                "ST": zero,
                "ST_conf": zero,
                "variance": 0.0,
            }
            continue
        res = analyze.analyze(problem, y, calc_second_order=False, seed=seed)
        out[name] = {
            "names": labels,
            "S1": res["S1"].tolist(),
            "S1_conf": res["S1_conf"].tolist(),
            "ST": res["ST"].tolist(),
            "ST_conf": res["ST_conf"].tolist(),
            "variance": float(np.var(y)),
        }
    return out
