"""Reproduction JSON documents carry ``status`` and ``message`` (README conventions), the worst
status of their parts and a message naming them (README walk leftovers, item 2)."""
from types import SimpleNamespace as NS

from frictionkit.reproduce import sdss as S
from frictionkit.reproduce import zhu_fujimoto as ZF


def _run(status=0, message="ok"):
    return NS(status=status, message=message)


def _zf(table3_runs):
    lead = {"motor_input": 50.0, "drive_force": 40.0}
    t3 = NS(max_error_um={"sinc": 1.0}, leads_ms={"sinc": lead}, runs=table3_runs)
    f10 = NS(min_ratio={}, max_ratio={}, true_min_ratio={}, true_max_ratio={}, runs={"fast_reverse": _run()})
    f10.min_ratio = f10.max_ratio = dict.fromkeys(ZF.LD_CASES, 1.0)
    sel = ZF.SelectorResult(selected=[], mixed_max_error_um=1.0, fixed_max_error_um={"sinc": 1.0}, per_crossing_um={})
    return ZF.ReproductionResult(table3=t3, fig10=f10, selector=sel, quick=True, seed=0)


def test_zhu_fujimoto_document_status():
    doc = _zf({"sinc": _run(), "coulomb": _run()}).to_dict()
    assert (doc["status"], doc["message"]) == (0, "ok")
    doc = _zf({"sinc": _run(), "coulomb": _run(2, "sub-steps too coarse")}).to_dict()
    assert doc["status"] == 2
    assert doc["message"] == "table3 coulomb: status 2 (sub-steps too coarse)"


def test_sdss_document_status():
    az = NS(fit=_run(), extra={})
    alt = NS(fit=_run(1, "did not converge"), extra={})
    rot = NS(fit=None, extra={"static_result": _run(), "hd_result": _run(2, "at a bound"), "bearing_result": _run()})
    status, message = S.worst_status(S._parts({"azimuth": az, "altitude": alt, "rotator": rot}))
    assert status == 2
    assert message == "altitude: status 1 (did not converge); rotator hd: status 2 (at a bound)"
    doc = S.SdssReproduction(axes={}, tracking={}, quick=True, seed=0, status=status, message=message).to_dict()
    assert (doc["status"], doc["message"]) == (2, message)
