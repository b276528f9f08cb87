"""Parameter dataclasses: resolved configuration and one-line errors for bad overrides."""

import pytest

from lcefem.models.errors import InputError
from lcefem.models.heat import Coil, joule_power
from lcefem.models.lce import NematicTransition
from lcefem.models.parameters import describe, with_overrides


def test_every_field_has_unit_and_source():
    for obj in (NematicTransition(), Coil()):
        for name, entry in describe(obj).items():
            assert entry["unit"] and entry["source"], name


def test_override_and_errors():
    p = with_overrides(NematicTransition(), {"T_NI": 71}, "transition")
    assert p.T_NI == 71.0 and isinstance(p.T_NI, float)
    with pytest.raises(InputError, match=r"unknown key 'transition.foo'; allowed: T_NI"):
        with_overrides(NematicTransition(), {"foo": 1}, "transition")
    with pytest.raises(InputError, match=r"transition.width = 0.0: must be > 0 K"):
        with_overrides(NematicTransition(), {"width": 0.0}, "transition")
    with pytest.raises(InputError, match=r"expected float"):
        with_overrides(NematicTransition(), {"width": "wide"}, "transition")


def test_negative_current_rejected():
    with pytest.raises(InputError, match="current = -0.1 A: must be between 0 and 1 A"):
        joule_power(-0.1, 146.6)
