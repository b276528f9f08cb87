"""The reference data of validation/data/*.toml: complete, consistent with their quotes and seed."""

import pathlib
import re

import pytest

from lcefem.models.errors import InputError
from lcefem.validation.cases import reference_data as rd

SEED = pathlib.Path("/work/shared/seeds/001_217c433b95a08c4e.txt")
# a minus sign counts only when it does not join two numbers ("0.04-0.09") or a word ("0.2-A")
NUMBER = re.compile(r"(?:(?<=[\s=$(])|^)-?\d+(?:\.\d+)?|(?<![\d.])\d+(?:\.\d+)?")
WORDS = {"one": 1, "two": 2, "three": 3, "four": 4, "five": 5, "six": 6, "nine": 9}


def _quoted_numbers(quote: str) -> list[float]:
    nums = [float(m) for m in NUMBER.findall(quote)]
    nums += [v for w, v in WORDS.items() if re.search(rf"\b{w}\b", quote)]
    return nums


def _normalise(text: str) -> str:
    return " ".join(text.split())


@pytest.mark.parametrize("dataset", rd.DATASETS)
def test_every_entry_has_value_unit_and_source(dataset):
    refs = rd.load(dataset)
    assert len(refs) >= 50  # seed 001 holds about sixty numbers the models can speak to
    for key, ref in refs.items():
        assert ref.unit and ref.published_unit in rd.UNIT_CONVERSIONS, key
        assert ref.kind in rd.KINDS, key
        assert ref.section and ref.quote and ref.citation, key
        assert ref.quote in ref.source and ref.section in ref.source, key


@pytest.mark.parametrize("dataset", rd.DATASETS)
def test_each_published_value_appears_in_its_quote(dataset):
    for key, ref in rd.load(dataset).items():
        values = (
            ref.published_value
            if isinstance(ref.published_value, tuple)
            else (ref.published_value,)
        )
        quoted = _quoted_numbers(ref.quote)
        for v in values:
            assert any(abs(v - q) <= 1e-12 * max(1.0, abs(v)) for q in quoted), (key, v, quoted)
        if ref.spread is not None:
            spreads = ref.spread if isinstance(ref.spread, tuple) else (ref.spread,)
            published = [s / rd.UNIT_CONVERSIONS[ref.published_unit][1] for s in spreads]
            for s in published:
                assert any(abs(s - q) <= 1e-9 for q in quoted), (key, s)


@pytest.mark.skipif(not SEED.exists(), reason="seed file not on this machine")
def test_quotes_are_verbatim_excerpts_of_the_seed():
    seed = _normalise(SEED.read_text(encoding="utf-8"))
    missing = [key for key, ref in rd.load("seed001").items() if _normalise(ref.quote) not in seed]
    assert not missing, missing


def test_units_are_converted_to_lcefem_units():
    p = rd.reference("strip.transient_powers")
    assert p.unit == "mW" and p.value == pytest.approx((1500.0, 3260.0, 5790.0))
    assert p.spread == pytest.approx((68.0, 150.0, 270.0))
    assert rd.reference("eq1.gamma_2").value == pytest.approx(11.97e-3)  # 1/mW
    assert rd.reference("ribbon.thickness").value == pytest.approx(0.127)  # mm
    assert rd.reference("surface.mass").value == pytest.approx(33e-6)  # t
    assert rd.reference("tension.strain_at_ribbon_load").value == pytest.approx(0.05)
    saddle = rd.reference("surface.saddle.curvature_exp")
    assert (saddle["kx"], saddle["ky"]) == (-0.012, 0.015)


def test_values_agree_with_the_models_that_quote_them():
    # models/empirical.py carries Eq. 1 and Eq. 2 constants with their own source strings
    from lcefem.models.empirical import Eq1, Eq2

    assert Eq1().gamma_1 == rd.reference("eq1.gamma_1").value
    assert Eq1().gamma_2 == pytest.approx(rd.reference("eq1.gamma_2").value)
    assert Eq1().gamma_3 == pytest.approx(rd.reference("eq1.gamma_3").value)
    assert Eq2().eta == rd.reference("eq2.eta").value


def test_unknown_key_names_close_matches():
    with pytest.raises(InputError, match="did you mean: blocked.rupture_force"):
        rd.reference("blocked.rupture_forse")
    with pytest.raises(InputError, match="no component 'kz'"):
        rd.reference("surface.dome.curvature_sim")["kz"]


def test_each_coil_and_nematic_number_has_one_definition_matching_the_seed():
    """models/ holds the numbers; the seed records in validation/data are the evidence they must
    match."""
    from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N, LCEStripBars
    from lcefem.models.empirical import EQ1_LAMBDA_N, Eq1, Eq2
    from lcefem.models.heat import Coil, GridSegmentCoil
    from lcefem.models.lce import NematicTransition
    from lcefem.validation.cases.reference_data import reference

    seg = GridSegmentCoil()
    assert seg.resistance == reference("coil.segment_resistance").value == 25.0
    assert seg.resistance_per_length == reference("coil.resistance_per_length").value
    assert seg.power(0.2) == pytest.approx(0.2**2 * 25.0 * 1e3)  # mW
    assert Coil().power(0.2) == pytest.approx(5864.0)  # seed 001: 5.79 +- 0.27 W at 0.2 A
    assert EQ1_LAMBDA_N == 1.0 + Eq1().gamma_1 == NematicTransition().lambda_N
    assert Eq2().lambda_N == LCEStripBars().lambda_N == PUBLISHED_LAMBDA_N == 1.4
