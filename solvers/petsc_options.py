"""lcefem's entries in PETSc's options database (numerics; no import of PETSc at module level), and
what a case file's ``[petsc]`` section may set (:func:`check_case_options`).

A ``[petsc]`` table is data from a file a user may have been sent, and PETSc's options database can
run code (``pc_type = "python"`` with ``pc_python_type = "file.py:fn"`` imports and runs a Python
file) and write files (``snes_monitor = "ascii:path"``, ``-log_view``, any viewer). So a case file
may set only the numerical options listed in :data:`CASE_OPTIONS` (solver types from fixed sets,
tolerances, iteration limits, factorisation and multigrid settings, MUMPS' ICNTL/CNTL), each with
its value checked against its type; anything else is refused with one line. ``PETSC_OPTIONS`` in
the environment is not honoured (:func:`own_petsc_environment`): lcefem's solvers read their options
under their own prefixes (``lcefem_mech_``, ...), and the environment would bypass this check.
"""

from __future__ import annotations

import contextlib
import math
import os
import re
import sys

from lcefem.models.errors import InputError

BOOL = "true/false"
INT = "an integer"
REAL = "a finite real number"
REALS = "finite real numbers separated by commas"

#: Option -> the values a case file may give it: BOOL, INT, REAL or a set of names. Only numerics:
#: nothing that names code (``*_python_type``, ``shell``), a viewer, a monitor or a file.
CASE_OPTIONS: dict[str, object] = {
    # SNES: Newton's method and its line search (lcefem.solvers.mechanics.NEWTON_OPTIONS)
    "snes_type": {
        "newtonls",
        "newtontr",
        "qn",
        "nrichardson",
        "ngmres",
        "anderson",
        "ncg",
        "ksponly",
    },
    "snes_linesearch_type": {"basic", "none", "bt", "l2", "secant", "cp", "nleqerr"},
    "snes_rtol": REAL,
    "snes_atol": REAL,
    "snes_stol": REAL,
    "snes_divergence_tolerance": REAL,
    "snes_max_it": INT,
    "snes_max_funcs": INT,
    "snes_max_fail": INT,
    "snes_max_linear_solve_fail": INT,
    "snes_lag_jacobian": INT,
    "snes_lag_preconditioner": INT,
    "snes_ksp_ew": BOOL,
    "snes_linesearch_damping": REAL,
    "snes_linesearch_maxstep": REAL,
    "snes_linesearch_max_it": INT,
    "snes_linesearch_order": INT,
    "snes_linesearch_minlambda": REAL,
    "snes_qn_type": {"lbfgs", "broyden", "badbroyden"},
    "snes_qn_m": INT,
    "snes_qn_scale_type": {"none", "scalar", "diagonal", "jacobian"},
    "snes_npc_side": {"left", "right"},
}
#: KSP, PC and factorisation options; also allowed under the scopes of :data:`SCOPE`
LINEAR_OPTIONS: dict[str, object] = {
    "ksp_type": {
        "preonly",
        "cg",
        "gmres",
        "fgmres",
        "lgmres",
        "minres",
        "bcgs",
        "bcgsl",
        "tfqmr",
        "richardson",
        "chebyshev",
        "gcr",
        "cr",
    },
    "ksp_rtol": REAL,
    "ksp_atol": REAL,
    "ksp_divtol": REAL,
    "ksp_max_it": INT,
    "ksp_gmres_restart": INT,
    "ksp_norm_type": {"default", "none", "preconditioned", "unpreconditioned", "natural"},
    "ksp_richardson_scale": REAL,
    "ksp_chebyshev_esteig": REALS,
    "ksp_initial_guess_nonzero": BOOL,
    "ksp_error_if_not_converged": BOOL,
    # "pmg": lcefem's Q2 -> Q1 p-multigrid (lcefem.solvers.pmultigrid), not a PETSc name
    "pc_type": {
        "lu",
        "cholesky",
        "ilu",
        "icc",
        "jacobi",
        "pbjacobi",
        "bjacobi",
        "sor",
        "asm",
        "gasm",
        "gamg",
        "mg",
        "hypre",
        "none",
        "pmg",
    },
    "pc_factor_mat_solver_type": {
        "mumps",
        "petsc",
        "superlu",
        "superlu_dist",
        "cholmod",
        "umfpack",
        "klu",
    },
    "pc_factor_mat_ordering_type": {
        "natural",
        "nd",
        "1wd",
        "rcm",
        "qmd",
        "rowlength",
        "amd",
        "metisnd",
    },
    "pc_factor_shift_type": {"none", "nonzero", "positive_definite", "inblocks"},
    "pc_factor_shift_amount": REAL,
    "pc_factor_levels": INT,
    "pc_factor_fill": REAL,
    "pc_factor_reuse_ordering": BOOL,
    "pc_gamg_type": {"agg", "classical", "geo"},
    "pc_gamg_threshold": REAL,
    "pc_gamg_square_graph": INT,
    "pc_gamg_agg_nsmooths": INT,
    "pc_gamg_coarse_eq_limit": INT,
    "pc_gamg_aggressive_coarsening": INT,
    "pc_gamg_reuse_interpolation": BOOL,
    "pc_mg_levels": INT,
    "pc_mg_type": {"multiplicative", "additive", "full", "kaskade"},
    "pc_mg_cycle_type": {"v", "w"},
    "pc_sor_omega": REAL,
    "pc_sor_its": INT,
    "pc_sor_symmetric": BOOL,
    "pc_asm_overlap": INT,
    "pc_asm_type": {"basic", "restrict", "interpolate", "none"},
    "pc_bjacobi_blocks": INT,
    "pc_hypre_type": {"boomeramg", "pilut", "parasails", "euclid"},
    "pc_hypre_boomeramg_strong_threshold": REAL,
    # lcefem's p-multigrid smoother (lcefem.solvers.pmultigrid)
    "pmg_smoother_mat_type": {"aij", "baij"},
    "pmg_smoother_blocks": {"none", "planes"},
}
#: MUMPS' integer and real controls: ``mat_mumps_icntl_<n>`` (INT), ``mat_mumps_cntl_<n>`` (REAL)
MUMPS = re.compile(r"mat_mumps_(icntl|cntl)_([0-9]{1,2})")
#: prefixes of the inner solvers of multigrid and block preconditioners and of a nonlinear
#: preconditioner, which nest (``mg_levels_ksp_type``, ``mg_coarse_mg_levels_pc_type``: GAMG on
#: p-multigrid's coarse level; ``npc_snes_type``)
SCOPE = re.compile(r"(mg_levels_(?:[0-9]{1,2}_)?|mg_coarse_|sub_|npc_)")
#: words in an option's name that mark output, code or files: named in the refusal
DANGEROUS = (
    "python",
    "monitor",
    "view",
    "options_file",
    "help",
    "log",
    "draw",
    "history",
    "test",
    "shell",
    "dump",
    "output",
    "viewer",
    "file",
    "save",
)


def _kind(name: str):
    """The value rule of option ``name`` (BOOL, INT, REAL or a set), None if a case file may not set
    it."""
    rest = name
    for _ in range(4):  # at most a few nested scopes
        if rest in CASE_OPTIONS:
            return CASE_OPTIONS[rest]
        if rest in LINEAR_OPTIONS:
            return LINEAR_OPTIONS[rest]
        found = MUMPS.fullmatch(rest)
        if found:
            return INT if found.group(1) == "icntl" else REAL
        scope = SCOPE.match(rest)
        if scope is None:
            return None
        rest = rest[scope.end() :]
    return None


def _value_ok(kind, text: str) -> bool:
    if isinstance(kind, (set, frozenset)):
        return text in kind
    if kind == BOOL:
        return text.lower() in ("", "true", "false", "1", "0", "yes", "no", "on", "off")
    if kind == INT:
        return re.fullmatch(r"[+-]?[0-9]{1,9}", text) is not None
    if kind == REALS:
        return all(_value_ok(REAL, part.strip()) for part in text.split(","))
    try:  # REAL: ASCII digits only (float() also reads other scripts' digits)
        return text.isascii() and math.isfinite(float(text))
    except ValueError:
        return False


def check_case_options(table: dict, where: str = "[petsc]") -> dict[str, str]:
    """The options of a case file's ``[petsc]`` table as PETSc strings, every name in the allow-list
    (:data:`CASE_OPTIONS`, :data:`LINEAR_OPTIONS` under the scopes :data:`SCOPE`, MUMPS' controls)
    and every value of its type; else InputError naming the option and what is allowed."""
    options = {}
    for key, value in table.items():
        name = str(key)
        if isinstance(value, bool):  # TOML true/false
            value = "true" if value else "false"
        elif isinstance(value, (dict, list)):
            raise InputError(
                f"{where} {name}: must be a single value (a string or a number), not a "
                f"{'table' if isinstance(value, dict) else 'list'}"
            )
        text = str(value).strip() if isinstance(value, (int, float)) else str(value)
        kind = _kind(name)
        if kind is None:
            shown = name.encode("ascii", "backslashreplace").decode()
            if any(word in name.lower() for word in DANGEROUS):
                raise InputError(
                    f"{where} {shown}: may not be set from a case file (it names code, a "
                    "viewer, a monitor or a file); case files set numerics only, see "
                    "docs/failure_modes.md"
                )
            raise InputError(
                f"{where} {shown}: not an option a case file may set (solver types, "
                "tolerances, iteration limits, factorisation and multigrid settings, "
                "mat_mumps_icntl_N / mat_mumps_cntl_N: the list is in docs/failure_modes.md)"
            )
        if not _value_ok(kind, text):
            allowed = ", ".join(sorted(kind)) if isinstance(kind, (set, frozenset)) else kind
            shown = text.encode("ascii", "backslashreplace").decode()[:60]
            raise InputError(
                f"{where} {name} = {shown!r}: must be {'one of ' if isinstance(kind, set) else ''}"
                f"{allowed}"
            )
        options[name] = text
    return options


#: the options lcefem itself puts in PETSC_OPTIONS before PETSc starts
#: (lcefem.solvers.runtime.signals)
OWN_ENVIRONMENT = ("-no_signal_handler",)


def own_petsc_environment() -> str | None:
    """Set ``PETSC_OPTIONS`` to lcefem's own options only, before PETSc initialises; returns what a
    user had put there (to be named as ignored in one line), or None. Why not honour it: the options
    there would reach every solver unchecked (code and viewers, :func:`check_case_options`), and
    lcefem's solvers read theirs under their own prefixes, so a plain ``-snes_rtol`` never reached
    them anyway."""
    given = os.environ.get("PETSC_OPTIONS", "").split()
    ignored = [w for w in given if w not in OWN_ENVIRONMENT]
    os.environ["PETSC_OPTIONS"] = " ".join(OWN_ENVIRONMENT)
    return " ".join(ignored) or None


def skip_petscrc_files() -> list[str]:
    """PETSc reads ``~/.petscrc``, ``./.petscrc`` and ``./petscrc`` when it initialises: options
    from a file in the folder a command runs in (a shared project folder) would reach PETSc
    unchecked, like ``PETSC_OPTIONS`` (``-log_view :path`` writes a file). When one exists and PETSc
    is not yet initialised, initialise it now with ``-skip_petscrc`` (which PETSc honours only on
    its command line, not in PETSC_OPTIONS; measured 0.3 s, so only when such a file exists);
    returns the files ignored (to be named in one line)."""
    import pathlib

    found = [
        str(p)
        for p in (
            pathlib.Path.home() / ".petscrc",
            pathlib.Path(".petscrc"),
            pathlib.Path("petscrc"),
        )
        if p.is_file()
    ]
    if not found or "petsc4py.PETSc" in sys.modules:
        return []
    import dolfinx_solver  # noqa: F401  (orders MPI before petsc4py)
    import petsc4py

    petsc4py.init(["lcefem", "-skip_petscrc"])
    return found


def forget_solver_options(prefix: str = "lcefem_") -> None:
    """Remove lcefem's solver options (prefix ``lcefem_``) from PETSc's options database when a
    command ends. Each problem puts its options there for its own SNES, KSP and factorisation, which
    read them when they first need them; a problem that never needed one (a beam confirmed in 0
    Newton iterations never factorises, so ``mat_mumps_icntl_7`` is never read) left it for PETSc to
    report at exit as "options you set that were not used". Options a user gives are checked
    when the solver has read its own (lcefem.solvers.mechanics: an unread [petsc] option is
    refused)."""
    petsc = sys.modules.get("petsc4py.PETSc")
    if petsc is None:
        return
    with contextlib.suppress(Exception):
        db = petsc.Options()
        for name in db.getAll():
            if name.startswith(prefix):
                db.delValue(name)
