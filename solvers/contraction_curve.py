"""Reading a measured contraction curve (a CSV of free stretch or strain against temperature) into
the law of :class:`lcefem.models.lce.MeasuredContraction`.

The file is data, read with the csv module (nothing in it runs)::

    # source: Kotikian et al., Adv. Mater. 2024, 2310743 (LTNI ink), free stretch L(T)/L(25 C)
    temperature [C],stretch [-]
    25,1.0
    35,0.921391013
    ...

Lines starting with ``#`` before the header are the curve's source text (kept with the law and
written to summary.json). The header names two columns with their units: ``temperature [C]`` (or
``[K]``), then ``stretch [-]``, ``strain [-]`` or ``strain [%]`` (a contraction is a negative
strain; stretch = 1 + strain). Rows: at least 2, temperatures strictly monotonic (increasing or
decreasing), every number finite, stretch > 0. Bad input is one :class:`InputError` line naming the
file, the row (the file's line number) and what is allowed.
"""

from __future__ import annotations

import csv
import math
import pathlib
import re
from dataclasses import dataclass

from lcefem.models.errors import InputError
from lcefem.models.lce import MeasuredContraction, NematicTransition
from lcefem.models.parameters import param
from lcefem.solvers.runtime.inputs import read_text

#: Allowed units of each column: name -> {unit: (scale, offset)} to C or stretch.
TEMPERATURE_UNITS = {"C": (1.0, 0.0), "K": (1.0, -273.15)}
VALUE_UNITS = {"stretch": {"-": (1.0, 0.0)}, "strain": {"-": (1.0, 1.0), "%": (0.01, 1.0)}}
_HEADER = re.compile(r"^\s*([A-Za-z_ ]*?)\s*\[([^\]]*)\]\s*$")


def _column(
    path_name: str, line: int, text: str, allowed: dict[str, dict]
) -> tuple[str, tuple[float, float]]:
    """(quantity, (scale, offset)) of one header cell ``name [unit]``."""
    choices = ", ".join(f"'{q} [{u}]'" for q, units in allowed.items() for u in units)
    m = _HEADER.match(text)
    if not m:
        raise InputError(
            f"{path_name}, row {line} (header): column {text.strip()!r} has no unit; "
            f"allowed {choices}"
        )
    name, unit = m.group(1).strip().lower(), m.group(2).strip()
    if name not in allowed:
        raise InputError(
            f"{path_name}, row {line} (header): column {text.strip()!r}; allowed {choices}"
        )
    if unit not in allowed[name]:
        raise InputError(
            f"{path_name}, row {line} (header): unknown unit [{unit}] of {name}; allowed {choices}"
        )
    return name, allowed[name][unit]


def read_contraction_csv(path, T_ref: float = 25.0) -> MeasuredContraction:
    """The measured curve in the CSV at ``path`` (module docstring) as a MeasuredContraction, its
    as-built temperature ``T_ref`` [C]; any bad input is one InputError naming file and row."""
    path = pathlib.Path(path)
    name = path.name
    text = read_text(path, f"curve = {str(path)!r}")
    source, header, rows = [], None, []
    for line, cells in enumerate(csv.reader(text.splitlines()), start=1):
        if not cells or all(not c.strip() for c in cells):
            continue
        if header is None and cells[0].lstrip().startswith("#"):
            source.append(",".join(cells).lstrip().lstrip("#").strip())
            continue
        if header is None:
            if len(cells) != 2:
                raise InputError(
                    f"{name}, row {line} (header): {len(cells)} columns; allowed two, "
                    "'temperature [C]' then 'stretch [-]', 'strain [-]' or 'strain [%]'"
                )
            header = (
                _column(name, line, cells[0], {"temperature": TEMPERATURE_UNITS}),
                _column(name, line, cells[1], VALUE_UNITS),
            )
            continue
        if len(cells) != 2:
            raise InputError(
                f"{name}, row {line}: {len(cells)} values; allowed two (temperature, "
                f"{header[1][0]})"
            )
        try:
            T, v = (float(c) for c in cells)
        except ValueError:
            raise InputError(
                f"{name}, row {line}: {','.join(cells)!r} is not two numbers; allowed numbers"
            ) from None
        if not (math.isfinite(T) and math.isfinite(v)):
            raise InputError(
                f"{name}, row {line}: {','.join(cells)!r}; allowed finite numbers (no NaN or inf)"
            )
        (t_scale, t_offset), (v_scale, v_offset) = header[0][1], header[1][1]
        T, stretch = T * t_scale + t_offset, v * v_scale + v_offset
        if stretch <= 0.0:
            raise InputError(
                f"{name}, row {line}: {header[1][0]} {v:g} gives stretch {stretch:g}; allowed "
                "stretch > 0 (strain > -1)"
            )
        if (
            len(rows) >= 2
            and (T - rows[-1][1]) * (rows[-1][1] - rows[-2][1]) <= 0
            or rows
            and T == rows[-1][1]
        ):
            raise InputError(
                f"{name}, row {line}: temperature {T:g} C after {rows[-1][1]:g} C; allowed "
                "strictly monotonic temperatures (all increasing or all decreasing)"
            )
        rows.append((line, T, stretch))
    if header is None:
        raise InputError(
            f"{name}: no header; allowed 'temperature [C],stretch [-]' (or strain [-], strain [%]) "
            "then one row per temperature"
        )
    if len(rows) < 2:
        raise InputError(f"{name}: {len(rows)} data row; allowed at least 2 rows")
    return MeasuredContraction.from_rows(
        [r[1] for r in rows],
        [r[2] for r in rows],
        "stretch",
        source="; ".join(source) or f"file {name}",
        T_ref=T_ref,
    )


def write_contraction_csv(path, curve: MeasuredContraction) -> pathlib.Path:
    """Write ``curve`` as a CSV :func:`read_contraction_csv` reads back exactly (repr floats, the
    source as ``#`` lines), through a .part file renamed at the end."""
    path = pathlib.Path(path)
    part = path.with_name(path.name + ".part")
    with open(part, "w", newline="") as f:
        for line in (curve.source or "").splitlines() or [""]:
            if line:
                f.write(f"# {line}\n")
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["temperature [C]", "stretch [-]"])
        w.writerows([(repr(T), repr(L)) for T, L in curve.rows()])
    part.replace(path)
    return path


@dataclass(frozen=True)
class LCECurve:
    """A body's choice of contraction law: the sigmoid of its transition section (default) or a
    measured curve from a CSV file (the case file's ``curve = "file.csv"``; a relative path is read
    from the case file's folder)."""

    curve: str = param(
        "",
        "-",
        "CSV of the LCE's measured free stretch or strain against temperature "
        "(header 'temperature [C],stretch [-]', or strain [-] / strain [%]; "
        "lcefem.solvers.contraction_curve); empty: the sigmoid law (the transition section)",
    )

    def law(self, transition: NematicTransition) -> NematicTransition | MeasuredContraction:
        """The measured curve (as built at ``transition.T_ref``) if a file is named, else
        ``transition``."""
        return read_contraction_csv(self.curve, transition.T_ref) if self.curve else transition


def law_summary(law) -> dict:
    """What summary.json records of a measured curve (rows, source, derived lambda_N); {} for the
    sigmoid."""
    if not isinstance(law, MeasuredContraction):
        return {}
    return {
        "table": {
            "value": [list(r) for r in law.rows()],
            "unit": "C, -",
            "source": law.source + " (free stretch L(T); piecewise linear, constant outside)",
        },
        "lambda_N": {"value": law.lambda_N, "unit": "-", "source": "L(T_ref)/L_min of the table"},
    }
