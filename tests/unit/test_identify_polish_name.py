"""One meaning per name (issue 11): WSIM's pre-sliding bool is ``polish`` (as fit_presliding's);
``refine`` — FitOptions' count of optimised starts — works there one release with a warning."""

import warnings

import pytest

from frictionkit.errors import DataError, FrictionKitDeprecationWarning, ParameterError
from frictionkit.identify import wsim as W
from frictionkit.reproduce.zhang2023 import Design


@pytest.mark.parametrize("call", [
    lambda **kw: W.cospeed_presliding({}, {}, **kw),
    lambda **kw: W.differential_presliding({}, None, **kw),
])
def test_wsim_steps_take_polish_and_warn_on_refine(call):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(DataError, match="no run given"):  # no deprecation warning for the new name
            call(polish=False)
    with pytest.warns(FrictionKitDeprecationWarning, match=r"\.refine is deprecated: use .*\.polish"):
        with pytest.raises(DataError, match="no run given"):
            call(refine=False)
    with pytest.raises(ParameterError, match="polish = 'yes': must be True or False"):
        call(polish="yes")


def test_acim_and_wsim_signatures_name_polish():
    with pytest.warns(FrictionKitDeprecationWarning, match="acim.refine is deprecated: use acim.polish"):
        res = W.acim({}, refine=True)
    assert res.status == 2  # nothing to identify
    import inspect

    assert inspect.signature(W.wsim).parameters["polish"].default is True
    assert inspect.signature(W.acim).parameters["polish"].default is False


def test_zhang2023_design_field_is_polish():
    assert Design(polish=False).polish is False
    with pytest.warns(FrictionKitDeprecationWarning, match="Design.refine is deprecated: use Design.polish"):
        d = Design(refine=False)
    assert d.polish is False
    assert "refine" not in {f.name for f in __import__("dataclasses").fields(Design)}
    with pytest.raises(ParameterError, match="Design: polish = 1"):
        Design(polish=1)
