"""Issue 13 (round 4): lightly damped or stiff contacts far faster than the samples were accepted
at the default tolerance — right or flagged now (``simulation.core`` accuracy check).

The cases are the round-4 campaign's (random legal parameters, drawn by rob's kernel fuzzer,
seed 1 cases 64 and 72, seed 2 case 28) and the sigma0 x mass sweep's LuGre on 1e-6 kg. Truth is
the ``solve_ivp`` twin (LSODA, rtol 1e-9); the unchecked run is the kernel's own result at the
default options (``_force_run``), which must be wrong by more than the check's bound — otherwise
the case would not test the check.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import frictionkit as fk
from frictionkit.simulation import core
from frictionkit.simulation.reference import reference_force_driven


def _sine(amp, freq, phase, N, dt):
    return amp * np.sin(2 * np.pi * freq * np.arange(N) * dt + phase)


LAW = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4)
CASES = {
    # Dahl, undamped (sigma2 = 0), omega dt = 77: x 5.8 % of its range off the twin at status 0
    "dahl_s1_64": (fk.Dahl(Fc=0.0816102614143952, sigma0=36966473.91499552, sigma2=0.0), 0.0004619386592617871,
                   0.0002720338194147775, (0.08033674496541879, 35.34390364725337, 0.9856407059323568, 50)),
    # LuGre, damping ratio 0.035, omega dt = 4.1: x 0.86 %
    "lugre_s1_72": (fk.LuGre(fk.Stribeck(Fc=8.621342395400388, Fs=8.63310661560658, vs=0.0008434823207230736,
                                         delta=0.9649928521547697, sigma2=175.7924812033364),
                             sigma0=6580029.962066138, sigma1=141.19771191453438), 3.12067125150132,
                    0.002821659492833872, (7.923689989865438, 1.3593304353855917, 0.9590819260938425, 326)),
    # Dahl, damping ratio 3.6e-6, omega dt = 35: x 1.6 %
    "dahl_s2_28": (fk.Dahl(Fc=7.721584721706575, sigma0=41136221.7014153, sigma2=0.028075715573151493),
                   0.3653012029747439, 0.0033203458481256853,
                   (5.855063138788048, 6.141311561522002, 0.8270687653581447, 62)),
    # LuGre (the README's) on 1e-6 kg, overdamped (ratio 101, (c/m) dt = 6e4): a one-sample velocity
    # spike of -95 m/s against the twin's -0.65 (x right)
    "lugre_1e-6kg": (fk.LuGre(LAW, sigma0=1e5, sigma1=63.2), 1e-6, 1e-3, (2.0, 0.5, 0.0, 1500)),
}


@pytest.fixture(scope="module")
def twins():
    out = {}
    for name, (model, m, dt, sine) in CASES.items():
        u = _sine(*sine[:3], sine[3], dt)
        out[name] = (u, reference_force_driven(model, m, u, dt, rtol=1e-9, atol=1e-14))
    return out


def _rel(a, ref):
    return float(np.max(np.abs(a - ref)) / np.ptp(ref))


@pytest.mark.parametrize("name", list(CASES))
def test_round4_silent_wrong_answers_are_flagged(twins, name):
    model, m, dt, _ = CASES[name]
    u, ref = twins[name]
    kind, pk = core._pack(model)
    raw = core._force_run(kind, pk, u, dt, m, 0.0, 0.0, None, fk.SimOptions(), core._f_scale(pk.static), model,
                          warn=False)
    raw_err = (_rel(raw.x, ref["x"]), _rel(raw.v, ref["v"]), _rel(raw.friction, ref["friction"]))
    print(name, "unchecked run vs twin (x, v, friction) / range:", raw_err)
    # measured first: the unchecked run is wrong beyond the error contract (10 rtol of the ranges of x and
    # the friction) or the check's v bound (1e-2). lugre_s1_72 was 0.86 % in x until its spanning steps
    # were checked between the samples (kernels/lugre.py RING_RESOLVE, 2026-11-24): 2.2e-4 now, still
    # 22 rtol, flagged since CHECK_BOUND is 5 (was 100)
    assert raw.status == 0 and (raw_err[0] > 1e-4 or raw_err[2] > 1e-4 or raw_err[1] > 1e-2), raw_err
    with pytest.warns(RuntimeWarning, match="accuracy check"):
        res = fk.simulate(model, plant=fk.Mass(m), force=u, dt=dt)
    assert res.status == 2 and not res.success
    for word in ("sigma0", "mass", "omega·dt", "damping ratio", "rtol"):
        assert word in res.message, (word, res.message)
    k = res.failed_at
    assert k is not None and np.isnan(res.x[k + 1:]).all()
    # the samples kept agree with the twin (x within 1e-3 of its range)
    assert _rel(res.x[:k + 1], ref["x"][:k + 1]) * np.ptp(ref["x"][:k + 1]) <= 1e-3 * np.ptp(ref["x"]), name


def test_a_tighter_tolerance_shrinks_the_error_of_a_flagged_run(twins):
    """The LuGre case flagged at the default and at rtol 1e-7, the kept samples agree with the twin, and
    the unchecked run's error falls with rtol. Measured 2026-11-24 against the twin (x / range):
    2.2e-4, 2.0e-5, 1.8e-6 at rtol 1e-5, 1e-6, 1e-7 (~20 rtol each: beyond the contract's 10, so flagged
    at every rtol; before the spanning steps were checked between the samples, RING_RESOLVE, it was
    0.86 %, 0.23 %, 0.011 % and a tighter rtol kept more samples)."""
    model, m, dt, _ = CASES["lugre_s1_72"]
    u, ref = twins["lugre_s1_72"]
    kind, pk = core._pack(model)
    errs = []
    for rtol in (1e-5, 1e-7):
        raw = core._force_run(kind, pk, u, dt, m, 0.0, 0.0, None, fk.SimOptions(rtol=rtol, atol_F=rtol),
                              core._f_scale(pk.static), model, warn=False)
        errs.append(_rel(raw.x, ref["x"]))
    assert errs[1] < errs[0] / 50, errs
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        loose = fk.simulate(model, plant=fk.Mass(m), force=u, dt=dt)
        tight = fk.simulate(model, plant=fk.Mass(m), force=u, dt=dt, options=fk.SimOptions(rtol=1e-7, atol_F=1e-7))
    assert loose.status == tight.status == 2
    k = tight.failed_at + 1
    assert np.max(np.abs(tight.x[:k] - ref["x"][:k])) <= 1e-4 * np.ptp(ref["x"])
    assert "falls more slowly than rtol" in tight.message


def test_runs_that_do_not_follow_fast_motion_are_not_checked():
    """The README's LuGre and GMS on 1 kg at 4 kHz (omega dt 0.08 / 0.26): untouched, message 'ok'."""
    u = 2.0 * np.sin(np.pi * np.arange(2001) * 2.5e-4)
    for model in (fk.LuGre(LAW, sigma0=1e5, sigma1=63.2), fk.GMS(LAW, k=[1e4, 1e5, 1e6], xi=[0.5, 0.3, 0.2], C=20.0)):
        res = fk.simulate(model, plant=fk.Mass(1.0), force=u, dt=2.5e-4)
        assert res.status == 0 and res.message == "ok"


# ------------------------------------------------------------------ property: this class, random
@st.composite
def light_fast_contacts(draw):
    """Dahl / lightly damped LuGre below breakaway, omega dt 2 ... 60, a short run (the twin pays per period)."""
    Fc = draw(st.floats(0.1, 10.0))
    m = draw(st.floats(1e-4, 1.0))
    s0 = Fc * draw(st.floats(1e5, 1e7))
    dt = draw(st.floats(2.0, 60.0)) / np.sqrt(s0 / m)
    if draw(st.booleans()):
        model = fk.Dahl(Fc=Fc, sigma0=s0, sigma2=draw(st.floats(0.0, 1e-2)))
    else:
        zeta = draw(st.floats(0.0, 0.1))
        model = fk.LuGre(fk.Stribeck(Fc=Fc, Fs=1.2 * Fc, vs=1e-3), sigma0=s0, sigma1=2 * zeta * np.sqrt(s0 * m))
    N = draw(st.integers(40, 70))
    u = _sine(Fc * draw(st.floats(0.3, 0.95)), draw(st.floats(0.2, 2.0)) / (N * dt), draw(st.floats(0.0, 1.0)), N, dt)
    return model, m, dt, u


@settings(deadline=None, derandomize=True, suppress_health_check=list(HealthCheck), max_examples=6)
@given(case=light_fast_contacts())
def test_light_fast_contacts_agree_with_the_twin_or_are_flagged(case):
    model, m, dt, u = case
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        res = fk.simulate(model, plant=fk.Mass(m), force=u, dt=dt)
    if res.status != 0:
        assert res.message and np.isnan(res.x[res.failed_at + 1:]).all()
        return
    ref = reference_force_driven(model, m, u, dt, rtol=1e-9, atol=1e-14)
    # bounds: the check's own (1e-3 of the range of x, 1e-2 of v and friction) doubled, since it
    # compares with a run at rtol/10 that carries an error of its own
    assert _rel(res.x, ref["x"]) <= 2e-3, (model, m, dt)
    assert max(_rel(res.v, ref["v"]), _rel(res.friction, ref["friction"])) <= 2e-2, (model, m, dt)


def test_simulate_batch_flags_the_same_sets(twins):
    """simulate_batch (adaptive) returned status 0 for these sets with RMS errors of 0.82 % (x, LuGre
    omega dt 4.1) and 0.34 % (v, 1e-6 kg) of the target's range against the twin; a README LuGre on
    1 kg in the same batch (omega dt 0.3 at this dt) is untouched."""
    for name, cmp in (("lugre_s1_72", "x"), ("lugre_1e-6kg", "v")):
        model, m, dt, _ = CASES[name]
        u, ref = twins[name]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            res = fk.simulate_batch([model, fk.LuGre(LAW, sigma0=1e5, sigma1=63.2)], masses=[m, 1.0], force=u, dt=dt,
                                    target=ref[cmp], compare=cmp)
        assert res.status.tolist() == [2, 0] and np.isinf(res.sse[0]) and np.isfinite(res.sse[1])
        assert "Set 0: tolerance not met (accuracy check of the set run alone" in res.message
        assert "omega·dt" in res.message


def test_gms_batch_sets_are_checked_without_false_alarms(monkeypatch):
    """A GMS on 0.1 g (omega dt 33) is checked in the batch (run alone by simulate()) and passes, as
    simulate() passes it; the same GMS on 1 kg is not fast and not run again."""
    calls = []
    orig = core.simulate

    def spy(model, **k):
        calls.append(k["plant"].m)
        return orig(model, **k)

    g = fk.GMS(LAW, k=[1e4, 1e5], xi=[0.5, 0.5], C=20.0)
    u = 2 * np.sin(np.pi * np.arange(1500) * 1e-3)
    ref = fk.simulate(g, plant=fk.Mass(1e-4), force=u, dt=1e-3)
    assert ref.status == 0 and "accuracy check passed" in ref.message
    monkeypatch.setattr(core, "simulate", spy)
    b = fk.simulate_batch([g, g], masses=[1e-4, 1.0], force=u, dt=1e-3, target=ref.x, compare="x")
    assert calls == [1e-4] and b.status.tolist() == [0, 0]


def test_batch_verifies_what_simulate_verifies():
    """Rob's seed-5 LuGre on 3.3e-4 kg (x within 2.3e-7 of the twin's range; simulate verifies it)
    was flagged by the batch's former RMS check (its check run failed, no retry)."""
    model, m, dt, n, (amp, freq, ph) = _UNVERIFIED["right_3e-4kg"]
    u = amp * np.sin(2 * np.pi * freq * np.arange(n) * dt + ph)
    b = fk.simulate_batch([model], masses=[m], force=u, dt=dt, target=np.zeros(n), compare="x")
    assert b.status.tolist() == [0], b.message


def test_gms_batch_one_sample_error_is_flagged():
    """Round 4's GMS-4 on 7e-5 kg (rob's generator, seed 1 case 6): its run is off the solve_ivp twin
    (rtol 1e-9) by 4.7 % of the friction range at one sample (measured 2026-11-23, ring), which left
    the batch's RMS within 10 %; a fast set is now also run alone by simulate(), whose per-sample
    check flags it. A GMS on 1 kg in the same batch is untouched."""
    g = fk.GMS(fk.Stribeck(Fc=9.164996071111988, Fs=9.224214211472159, vs=0.011859544133209384,
                           delta=1.0291868565187763, sigma2=0.002179916298899491),
               k=[993.29866956, 10803.47701216, 34442.96732197, 218609.61350453],
               xi=[0.13835056, 0.24408417, 0.21476502, 0.40280025], C=168.15071789436314)
    m, dt = 7.036713898325898e-05, 0.0007933774237972438
    u = _sine(12.163283556271027, 3.008325159881946, 0.6538660110683944, 504, dt)
    g2 = fk.GMS(LAW, k=[1e4, 1e5, 1e6, 1e6], xi=[0.4, 0.3, 0.2, 0.1], C=20.0)
    b = fk.simulate_batch([g, g2], masses=[m, 1.0], force=u, dt=dt, target=np.zeros(u.size), compare="F")
    assert b.status.tolist() == [2, 0] and np.isinf(b.sse[0]) and np.isfinite(b.sse[1])
    assert "Set 0: tolerance not met (accuracy check of the set run alone by simulate()" in b.message


# rob's random cases (seed 5, cases 26 and 0): both check runs (rtol/10, rtol/3) failed from rest
# (step-size underflow in the first interval) and both runs came back "could not be verified";
# the third check run with a fixed velocity tolerance (core.CHECK_ATOL_V) verifies the right one
# and still flags the wrong one. Truth: the solve_ivp twin at rtol 1e-9.
_UNVERIFIED = {
    "right_3e-4kg": (fk.LuGre(fk.Stribeck(Fc=2.0188631432000532, Fs=2.7668987816539286, vs=0.0016859996145714086,
                                          delta=1.7965835979224938, sigma2=0.0),
                              sigma0=2408110.1085072192, sigma1=760.0548495579768),
                     0.00032963809466894135, 2.367503148248821e-05, 407,
                     (2.532640311301652, 59.78769319126749, 0.4530394946991454)),
    "wrong_2.5e-5kg": (fk.LuGre(fk.Stribeck(Fc=67.61102849869387, Fs=98.95991710136697, vs=0.0011516015590759927,
                                            delta=1.214503450220354, sigma2=0.0),
                                sigma0=4890237.823912955, sigma1=0.1384792621174003),
                       2.455057599553435e-05, 0.009943249686656018, 260,
                       (139.37314435676439, 0.18841109264782427, 0.43494755222514203)),
}


@pytest.mark.parametrize("name", sorted(_UNVERIFIED))
def test_check_runs_failing_from_rest_get_a_fixed_velocity_tolerance(name):
    model, m, dt, n, (amp, freq, ph) = _UNVERIFIED[name]
    u = amp * np.sin(2 * np.pi * freq * np.arange(n) * dt + ph)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fk.simulate(model, plant=fk.Mass(m), force=u, dt=dt)
    if name.startswith("right"):
        ref = reference_force_driven(model, m, u, dt, rtol=1e-9, atol=1e-14)
        assert res.status == 0 and "accuracy check passed" in res.message, res.message
        assert float(np.abs(res.x - ref["x"]).max() / np.ptp(ref["x"])) < 1e-5  # measured 2.3e-7 of its range
    else:  # the plain run is 5.1 % off in x, 37 % in the friction (twin, 7.7 s CPU: not rerun here);
        # with CHECK_ATOL_V = 1 the third check run agreed with it (a false pass, status 0)
        # (with the LuGre kernel of 13:50 UTC its plain run itself stops at sample 1: status 3, flagged too)
        assert res.status in (2, 3), res.message
        assert res.status == 3 or "also with a fixed velocity tolerance" in res.message, res.message


def test_check_false_returns_the_unchecked_run_and_check_must_be_a_bool():
    """SimOptions(check=False) skips the accuracy check (the output-error fit's inner loop): an undamped
    GMS on 1 kg at omega dt 1.05 is flagged with the check and returned whole (status 0) without it,
    the same samples as the checked run kept; check must be a bool (not 1 or 'no')."""
    law = fk.GMS(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), k=[1e4, 1e5, 1e6], xi=[0.5, 0.3, 0.2], C=20.0)
    u = 2.0 * np.sin(np.pi * np.arange(801) * 1e-3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        checked = fk.simulate(law, plant=fk.Mass(1.0), force=u, dt=1e-3)
    plain = fk.simulate(law, plant=fk.Mass(1.0), force=u, dt=1e-3, options=fk.SimOptions(check=False))
    assert checked.status == 2 and "accuracy check" in checked.message, checked.message
    assert plain.status == 0 and np.all(np.isfinite(plain.x)) and "accuracy check" not in plain.message
    k = checked.failed_at
    np.testing.assert_array_equal(plain.x[:k + 1], checked.x[:k + 1])
    for bad in (1, "no", None):
        with pytest.raises(fk.ParameterError, match="SimOptions.check"):
            fk.SimOptions(check=bad)
