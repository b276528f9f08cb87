"""The measured-curve CSV (lcefem.solvers.contraction_curve, issue 44): what it reads, its one-line
errors naming file and row, and the option in the rolling ribbon (material.curve) and the lumped
strip of the bar-and-hinge current routes (current_route.curve). The FE strip's option:
tests/solvers/test_strip_curve.py."""

from __future__ import annotations

import pathlib

import numpy as np
import pytest

from lcefem.models import lumped_heat as lh
from lcefem.models.errors import InputError
from lcefem.models.lce import MeasuredContraction, NematicTransition, spontaneous_stretch
from lcefem.models.ribbon import RibbonLCE
from lcefem.solvers.contraction_curve import read_contraction_csv, write_contraction_csv
from lcefem.solvers.current_routes import route_from_config

CURVES = pathlib.Path(__file__).resolve().parents[2] / "validation" / "data" / "curves"


def write(tmp_path, text: str, name: str = "curve.csv") -> pathlib.Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def test_shipped_curve_reads_with_its_source():
    """The LTNI ink's free stretch (Kotikian et al. 2024): 16 rows 25-150 C, the source kept, the
    smallest stretch 0.5831 at 70 C as the isotropic length (lambda_N = 1/0.583070989)."""
    m = read_contraction_csv(CURVES / "kotikian2024_LTNI.csv")
    assert len(m.temperatures) == 16 and m.temperatures[0] == 25.0 and m.temperatures[-1] == 150.0
    assert "Kotikian" in m.source and "morphing-lattices" in m.source
    assert m.lambda_N == pytest.approx(1.0 / 0.583070989, rel=1e-12)
    assert float(m.stretch(70.0)) == 1.0


@pytest.mark.parametrize(
    "header, rows, scale",
    [
        ("temperature [C],stretch [-]", [(25, 1.0), (60, 0.8), (100, 0.7)], lambda v: v),
        ("temperature [C],strain [-]", [(25, 0.0), (60, -0.2), (100, -0.3)], lambda v: 1.0 + v),
        (
            "temperature [C],strain [%]",
            [(25, 0.0), (60, -20.0), (100, -30.0)],
            lambda v: 1.0 + v / 100.0,
        ),
        ("temperature [K],stretch [-]", [(298.15, 1.0), (333.15, 0.8), (373.15, 0.7)], lambda v: v),
    ],
)
def test_units_are_converted(tmp_path, header, rows, scale):
    text = "# a test curve\n" + header + "\n" + "\n".join(f"{t},{v}" for t, v in rows) + "\n"
    m = read_contraction_csv(write(tmp_path, text))
    np.testing.assert_allclose(m.temperatures, [25.0, 60.0, 100.0], atol=1e-12)
    np.testing.assert_allclose(m.values, [scale(v) for _, v in rows], atol=1e-15)
    assert m.source == "a test curve"


def test_write_then_read_is_exact(tmp_path):
    """write_contraction_csv writes repr floats: the curve comes back bit for bit."""
    T = np.arange(0.0, 200.5, 0.7)
    m = MeasuredContraction.from_rows(
        T, spontaneous_stretch(T, NematicTransition()), source="sigmoid"
    )
    back = read_contraction_csv(write_contraction_csv(tmp_path / "s.csv", m))
    assert back == m
    assert not (tmp_path / "s.csv.part").exists()


@pytest.mark.parametrize(
    "text, row, says",
    [
        ("temperature [C],stretch [-]\n25,1.0\n60,0.8\n40,0.7\n", 4, "strictly monotonic"),
        ("temperature [C],stretch [-]\n25,1.0\n", None, "at least 2 rows"),
        ("temperature,stretch\n25,1.0\n60,0.8\n", 1, "has no unit"),
        ("temperature [F],stretch [-]\n25,1.0\n60,0.8\n", 1, "unknown unit [F]"),
        ("temperature [C],strain [mm]\n25,1.0\n60,0.8\n", 1, "unknown unit [mm]"),
        ("temperature [C],stretch [-]\n25,1.0\n60,nan\n", 3, "finite"),
        ("temperature [C],stretch [-]\n25,1.0\n60,0\n", 3, "stretch > 0"),
        ("temperature [C],strain [%]\n25,0\n60,-100\n", 3, "stretch > 0"),
        ("temperature [C],stretch [-]\n25,1.0\n60,abc\n", 3, "not two numbers"),
        ("temperature [C],stretch [-],extra [-]\n25,1.0,1\n", 1, "two"),
    ],
)
def test_bad_files_are_one_line_errors_naming_file_and_row(tmp_path, text, row, says):
    with pytest.raises(InputError) as err:
        read_contraction_csv(write(tmp_path, text, "bad.csv"))
    message = str(err.value)
    assert "\n" not in message and message.startswith("bad.csv") and says in message, message
    if row is not None:
        assert f"row {row}" in message
    assert "allowed" in message


def test_case_file_curve_is_read_beside_the_case_file(tmp_path, monkeypatch):
    """[lce] curve = "name.csv" in a case file names a file in the case file's folder, wherever the
    run starts; a bad file is an InputError at validation (before any mesh)."""
    from lcefem.solvers.problems.strip import StripConfig
    from lcefem.validation.app.config import config_from_toml

    folder = tmp_path / "robot"
    folder.mkdir()
    write(folder, "temperature [C],stretch [-]\n25,1.4\n200,1.0\n", "my_lce.csv")
    case = write(folder, '[lce]\ncurve = "my_lce.csv"\n', "case.toml")
    monkeypatch.chdir(tmp_path)
    cfg = config_from_toml(case, StripConfig())
    assert pathlib.Path(cfg.lce.curve) == folder / "my_lce.csv"
    assert cfg.law().lambda_N == pytest.approx(1.4)
    bad = write(folder, '[lce]\ncurve = "missing.csv"\n', "bad.toml")
    with pytest.raises(InputError, match="file not found"):
        config_from_toml(bad, StripConfig()).validated()
    assert isinstance(StripConfig().law(), NematicTransition)  # default: the sigmoid


def test_ribbon_material_curve_reaches_the_ribbon_table(tmp_path):
    """material.curve: the rolling ribbon's a(T) table (solvers.der.ribbon.tabulated_contraction) is
    built from the curve; without it, from the material's sigmoid as before."""
    from lcefem.solvers.der.ribbon import tabulated_contraction
    from lcefem.solvers.problems.twisted_ribbon_der import RibbonConfig

    assert isinstance(RibbonConfig().setup().transition, NematicTransition)
    cfg = RibbonConfig(material=RibbonLCE(curve=str(CURVES / "kotikian2024_HTNI.csv"))).validated()
    law = cfg.setup().transition
    assert isinstance(law, MeasuredContraction)
    table = tabulated_contraction(law)
    T = np.array([25.0, 47.5, 100.0, 150.0, 170.0])
    np.testing.assert_allclose(table(T), law.contraction(T), atol=1e-12)
    assert cfg.resolved()["material"]["lambda_N"]["value"] == pytest.approx(1.0 / 0.466140095)


def test_curve_shape_benchmark_table_is_the_former_table(tmp_path):
    """ribbon_curve_shape.py now passes its shaped a(T) as material.curve, sampled at the a(T)
    table's nodes: the ribbon's table is the former one (the in-code replacement) coefficient for
    coefficient, so its runs give the same numbers (checked: HTNI and LTNI at 55 C, 61 nodes, 120 s,
    every JSON field equal)."""
    from lcefem.solvers.der.ribbon import CONTRACTION_TABLE, tabulated_contraction
    from lcefem.solvers.der.tabulated import TabulatedLaw
    from ribbon_curve_shape import contraction_of_shape, shaped_curve_file

    for name in ("LTNI", "HTNI"):
        former = TabulatedLaw.of(contraction_of_shape(name, 1.35), *CONTRACTION_TABLE)
        law = read_contraction_csv(shaped_curve_file(name, 1.35, tmp_path / f"{name}.csv"))
        np.testing.assert_array_equal(tabulated_contraction(law).coefficients, former.coefficients)


def test_lumped_route_with_a_sampled_sigmoid_is_the_sigmoid_route(tmp_path):
    """A table of the calibrated sigmoid every 1 K gives the grid strip's steady lambda at the
    dome's hold currents within the interpolation error (1e-4); a curve that contracts earlier gives
    a lower lambda at the same current; Eq. 1 takes no curve."""
    T = np.arange(0.0, 200.5, 1.0)
    tr = NematicTransition()
    path = write_contraction_csv(
        tmp_path / "s.csv", MeasuredContraction.from_rows(T, spontaneous_stretch(T, tr))
    )
    currents = {"Tx": 0.04, "Bx": 0.07, "hot": 0.09}
    plain = route_from_config(lh.CurrentRouteConfig()).lambdas(currents)
    table = route_from_config(lh.CurrentRouteConfig(curve=str(path))).lambdas(currents)
    for k in currents:
        assert table[k] == pytest.approx(plain[k], abs=1e-4)
    early = NematicTransition(T_NI=tr.T_NI - 10.0)
    path_early = write_contraction_csv(
        tmp_path / "e.csv", MeasuredContraction.from_rows(T, spontaneous_stretch(T, early))
    )
    shifted = route_from_config(lh.CurrentRouteConfig(curve=str(path_early))).lambdas(currents)
    assert shifted["Bx"] < plain["Bx"] - 0.05
    with pytest.raises(InputError, match="thermal_model"):
        route_from_config(lh.CurrentRouteConfig(thermal_model="eq1", curve=str(path)))
