"""The friction-law contract and registry (``models.base``): JSON round trips, errors,
kernel families, registration of a new law."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.errors import DataError, ParameterError
from frictionkit.models import (
    FrictionLaw,
    kernel_family,
    law_entry,
    law_from_dict,
    law_to_dict,
    register_law,
    registered_laws,
    unregister_law,
)
from frictionkit.models.pack import kind_of

LAW = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=1.7, sigma2=0.4, shape="lorentzian")
NEG = fk.Stribeck(Fc=0.8, Fs=1.1, vs=4e-3, sigma2=0.3)

#: (law, kernel family): at least one of every registered law
CASES = [
    (LAW, "static"),
    (fk.Stribeck(Fc=0.0, Fs=1.5, vs=1e-3), "static"),
    (fk.CoulombViscous(Fc=2.0, sigma2=10.0), "static"),
    (fk.TDMSSC(Fc0=-4.52, Fc1=6450.0, Fs0=-19.56, Fs1=6450.0, vs=6.5e-5, delta=1.7, sigma2=-1120.0,
               eps=5.852e6), "static"),
    (fk.Directional(positive=LAW, negative=NEG), "static"),
    (fk.Dahl(Fc=1.0, sigma0=1e5, sigma2=0.1), "lugre"),
    (fk.LuGre(LAW, sigma0=1e5, sigma1=63.2), "lugre"),
    (fk.LuGre(fk.Directional(positive=LAW, negative=NEG), sigma0=1e5), "lugre"),
    (fk.Directional(positive=fk.LuGre(LAW, sigma0=1e5, sigma1=1.0),
                    negative=fk.LuGre(NEG, sigma0=2e5, sigma1=2.0)), "lugre"),
    (fk.GMS(LAW, k=[1e4, 1e5, 1e6], xi=[0.5, 0.3, 0.2], C=20.0), "gms"),
    (fk.Directional(positive=fk.GMS(LAW, k=[1e4, 1e5], xi=[0.6, 0.4], C=20.0),
                    negative=fk.GMS(NEG, k=[2e4, 3e5], xi=[0.7, 0.3], C=15.0)), "gms"),
]
IDS = [f"{type(m).__name__}-{i}" for i, (m, _) in enumerate(CASES)]


def test_every_registered_law_is_covered():
    assert sorted(registered_laws()) == ["CoulombViscous", "Dahl", "Directional", "GMS", "LuGre", "Stribeck",
                                         "TDMSSC"]
    assert {type(m).__name__ for m, _ in CASES} == set(registered_laws())


@pytest.mark.parametrize("law, family", CASES, ids=IDS)
def test_json_round_trip_is_exact(law, family):
    d = law_to_dict(law)
    assert d["law"] == type(law).__name__
    text = json.dumps(d)
    back = law_from_dict(json.loads(text))
    assert type(back) is type(law)
    assert back == law
    assert json.dumps(law_to_dict(back)) == text
    v = np.linspace(-0.02, 0.02, 9)
    kw = {"schedule": 1e-3} if isinstance(law, fk.TDMSSC) else {}  # a scheduled law needs its input
    np.testing.assert_array_equal(back.steady_state(v, **kw), law.steady_state(v, **kw))


@pytest.mark.parametrize("law, family", CASES, ids=IDS)
def test_kernel_family(law, family):
    assert isinstance(law, FrictionLaw)
    assert kernel_family(law) == family
    if family == "static":
        with pytest.raises(ParameterError, match=r"simulate\(\) needs a dynamic law"):
            kind_of(law)
    else:
        assert kind_of(law) == family


def test_nested_laws_are_nested_json_objects():
    d = law_to_dict(CASES[-1][0])
    assert d["positive"]["law"] == "GMS" and d["positive"]["static"]["law"] == "Stribeck"
    assert d["negative"]["k"] == [2e4, 3e5]


def test_unknown_law_name_is_one_line_naming_it():
    with pytest.raises(DataError) as err:
        law_from_dict({"law": "Magic", "Fc": 1.0})
    msg = str(err.value)
    assert "\n" not in msg
    assert "'Magic'" in msg and "is not registered" in msg and "'LuGre'" in msg  # lists the known names
    with pytest.raises(DataError, match=r"without a 'law' key"):
        law_from_dict({"Fc": 1.0})
    with pytest.raises(DataError, match=r"got list"):
        law_from_dict([1, 2])


def test_missing_and_unknown_fields_are_one_line_naming_them():
    d = law_to_dict(fk.LuGre(LAW, sigma0=1e5, sigma1=63.2))
    del d["static"]["vs"]
    with pytest.raises(DataError) as err:
        law_from_dict(d)
    assert "\n" not in str(err.value)
    assert str(err.value).startswith("law 'Stribeck': field 'vs' missing; Stribeck takes ['Fc', 'Fs', 'vs'")
    d = law_to_dict(fk.GMS(LAW, k=[1e4], xi=[1.0], C=20.0))
    d["mu"] = 0.3
    with pytest.raises(DataError, match=r"^law 'GMS': unknown field 'mu'; GMS takes \['static', 'k', 'xi', 'C'\]$"):
        law_from_dict(d)
    # a value breaking the law's rule is the law's own ParameterError
    d = law_to_dict(LAW)
    d["vs"] = -1.0
    with pytest.raises(ParameterError, match=r"Stribeck.vs = -1.0"):
        law_from_dict(d)


def test_non_laws_are_refused():
    for bad in (fk.Mass(1.0), 3.0, fk.RigidBody(M=1.0, friction=LAW)):
        with pytest.raises(ParameterError, match=r"is not a registered friction law; known laws: \["):
            kernel_family(bad)
        with pytest.raises(ParameterError, match=r"needs a dynamic law"):
            kind_of(bad)
        assert not isinstance(bad, FrictionLaw)
    with pytest.raises(ParameterError, match=r"pass a law object"):
        kernel_family(fk.LuGre)
    assert law_entry("GMS").cls is fk.GMS and law_entry(fk.GMS).name == "GMS"
    with pytest.raises(ParameterError, match=r"'Nope' is not registered"):
        law_entry("Nope")


def test_identification_files_spell_the_discriminator_type():
    """Result files (format frictionkit.identification/1) keep ``"type"`` at every level, as
    written before the registry; reading takes either spelling, and plants nest laws."""
    from frictionkit.identify.result import model_from_dict, model_to_dict

    law = CASES[-1][0]
    d = model_to_dict(law)
    assert d["type"] == "Directional" and d["positive"]["static"]["type"] == "Stribeck"
    assert "law" not in json.dumps(d)
    assert model_from_dict(d) == law and model_from_dict(law_to_dict(law)) == law
    body = fk.RigidBody(M=95.0, friction=fk.Directional(positive=fk.CoulombViscous(Fc=20.0, sigma2=200.0),
                                                       negative=fk.CoulombViscous(Fc=19.0, sigma2=210.0)), offset=-3.0)
    d = model_to_dict(body)
    assert d["type"] == "RigidBody" and d["friction"]["negative"]["type"] == "CoulombViscous"
    assert model_from_dict(json.loads(json.dumps(d))) == body
    with pytest.raises(DataError, match=r"^model type 'Magic' unknown; known: \['CoulombViscous'"):
        model_from_dict({"type": "Magic"})
    with pytest.raises(DataError, match=r"^model 'RigidBody': field 'M' missing"):
        model_from_dict({"type": "RigidBody", "friction": d["friction"]})
    with pytest.raises(DataError, match=r"cannot serialise model of type Mass"):
        model_to_dict(fk.Mass(1.0))


# --------------------------------------------------------------------------- registering a law
@dataclasses.dataclass(frozen=True, kw_only=True)
class _Tanh:
    """A dummy static law ``F = Fc tanh(v / v0)``."""

    Fc: float
    v0: float = 1e-3

    def steady_state(self, v):
        return self.Fc * np.tanh(np.asarray(v, dtype=float) / self.v0)


@pytest.fixture
def tanh_law():
    register_law("Tanh", _Tanh, "static")
    yield _Tanh
    unregister_law("Tanh")


def test_a_registered_law_joins_everything(tanh_law):
    assert "Tanh" in registered_laws()
    law = tanh_law(Fc=2.0, v0=0.5)
    assert kernel_family(law) == "static"
    assert law_to_dict(law) == {"law": "Tanh", "Fc": 2.0, "v0": 0.5}
    assert law_from_dict(json.loads(json.dumps(law_to_dict(law)))) == law
    # a wrapper of registered laws takes it too
    d = fk.Directional(positive=law, negative=tanh_law(Fc=1.0))
    assert law_from_dict(law_to_dict(d)) == d and kernel_family(d) == "static"
    # and identification results store it
    from frictionkit.identify.result import model_from_dict, model_to_dict

    assert model_to_dict(law) == {"type": "Tanh", "Fc": 2.0, "v0": 0.5}
    assert model_from_dict(model_to_dict(law)) == law


def test_dummy_law_is_gone_after_the_fixture():
    assert "Tanh" not in registered_laws()


def test_register_law_rejects_bad_entries(tanh_law):
    with pytest.raises(ParameterError, match=r"family = 'wave'"):
        register_law("Wave", _Tanh, "wave")
    with pytest.raises(ParameterError, match=r"'LuGre'\): the name is already registered"):
        register_law("LuGre", _Tanh, "lugre")
    with pytest.raises(ParameterError, match=r"not a dataclass; pass to_dict and from_dict"):
        register_law("Plain", object, "static")
    register_law("Tanh", _Tanh, "static")  # the same class again: allowed (module reload)
    with pytest.raises(ParameterError, match=r"'Nope' is not registered"):
        unregister_law("Nope")


def test_custom_codec():
    class Scaled:
        def __init__(self, gain):
            self.gain = gain

        def steady_state(self, v):
            return self.gain * np.sign(v)

        def __eq__(self, other):
            return type(other) is Scaled and other.gain == self.gain

    register_law("Scaled", Scaled, "static", to_dict=lambda m: {"gain": m.gain},
                 from_dict=lambda d: Scaled(d["gain"]))
    try:
        assert law_to_dict(Scaled(3.0)) == {"law": "Scaled", "gain": 3.0}
        assert law_from_dict({"law": "Scaled", "gain": 3.0}) == Scaled(3.0)
    finally:
        unregister_law("Scaled")
