"""GMS breakaways placed at their threshold (issue 13, helper gms13): reproducers of the GMS campaign
(``benchmarks/robustness_gms.py``), each with its seed, against the ``solve_ivp`` twin.

The twin: ``reference_force_driven`` at rtol 1e-11 with steps of at most dt/8 (its default steps can miss a
grazing switch), as in the campaign. Errors: largest |run - twin| over the run, relative to the twin's range.
"""

from __future__ import annotations

import warnings

import numpy as np

import frictionkit as fk
from frictionkit.simulation.reference import reference_force_driven


def _campaign_run(law, m, dt, n, amp, cycles, options=None):
    """The campaign's sine force ``amp sin(2 pi cycles k / n)``; ``(result, errors against the twin)``."""
    u = amp * np.sin(2 * np.pi * cycles * np.arange(n) / n)
    res = fk.simulate(law, dt=dt, plant=fk.Mass(m), force=u, options=options or fk.SimOptions())
    tw = reference_force_driven(law, m, u, dt, rtol=1e-11, atol=1e-16, max_step=dt / 8)
    errs = {name: float(np.max(np.abs(getattr(res, name) - tw[name])) / np.ptp(tw[name]))
            for name in ("x", "v", "friction")}
    return res, errs


# Campaign seed 2092: 15 elements, sum k 1.7e8 N/m (above the contract's 1e8) on 6.6 g, undamped (omega dt 24.9),
# Fs < Fc, C = 0.14 N/s. A breakaway landed up to EVENT_TOL dt past its crossing kept the spring's overshoot
# (k v EVENT_TOL dt, 6.6e-5 N) as slip force, which with C / g = 0.06 /s never relaxes, and the later breakaway
# cascades carried it on: old kernel at status 0 with the friction 1.2e-3 of its range off the twin (121 rtol)
# at every rtol 1e-5 ... 1e-8, so no check run could see it.
GMS_2092 = fk.GMS(
    fk.Stribeck(Fc=2.517519219867341, Fs=1.3758927336627453, vs=0.0004102086052871788, sigma2=0.0),
    k=[4395026.375487513, 1771566.5081111647, 27702453.13220864, 7830757.268960508, 1412327.691115315,
       4615904.252249299, 15934026.826091256, 10082559.309270766, 11206582.049718894, 25996267.380887773,
       4257959.339907699, 4986924.0858817715, 3150267.285481025, 35674863.85027254, 7692357.021349676],
    xi=[0.0006992914807788061, 0.11927568765975066, 0.023357505688833193, 0.06607221990071412,
        0.008611226405090665, 0.002807726828831239, 0.15887369248203537, 0.08532468173105189,
        0.03326013756752602, 0.07249568348373815, 0.03813478696124849, 0.005222316152418772,
        0.10469298721936318, 0.05024075014457652, 0.23093130629404302],
    C=0.14180691458257408,
)


def test_gms_breakaway_leaves_stick_at_its_threshold():
    res, errs = _campaign_run(GMS_2092, 0.0066378808981783725, 0.000156991932276426, 284,
                              7.322186486743397, 2.9882972832713053)
    assert res.status == 0, res.message
    # measured 2026-11-24 (gms13): x 3.5e-8, friction 1.1e-6 of their ranges (one sample inside a breakaway
    # cascade); old kernel: x 5.2e-6, friction 1.2e-3
    assert max(errs["x"], errs["friction"]) <= 10 * fk.SimOptions().rtol, errs


# Campaign seed 2102: one element (k 1.5e3 N/m on 53 g, omega dt 9.1, damping ratio 0.14), Fs 3.93 < Fc 4.87 N.
# After a reversal re-sticks the element at ~4.05 N (above xi Fs), the contact rings and v turns positive
# again inside a sub-step: the element breaks away right there (g(0+) = Fs), but at the sub-step's end
# the mass is faster (g ~ 4.8 N) and the event function positive again, and the window of |v| < ~0.4 vs in
# between fell between the interior scan's grid points. Old kernel: x 2.7e-7 of its range off the twin at
# every rtol 1e-6 ... 1e-8 (26.6 rtol at 1e-8 unchecked), decided by whether a grid point hit the window;
# with breakaways set to their threshold alone, 3.3e-3 of the friction range at rtol 1e-7.
GMS_2102 = fk.GMS(
    fk.Stribeck(Fc=4.869642180759822, Fs=3.9289731318295855, vs=0.0016706477167887056,
                sigma2=2.506679069661523),
    k=[1484.565004862666], xi=[1.0], C=5.730163775417137,
)


def test_gms_breakaway_at_a_reversal_below_the_speed_of_the_step_end_is_found():
    rtol = 1e-8
    res, errs = _campaign_run(GMS_2102, 0.05254806543366071, 0.0539080743583836, 136, 8.333342373951046,
                              2.5748099270076175, fk.SimOptions(rtol=rtol, check=False))
    assert res.status == 0, res.message
    # measured 2026-11-24 (gms13): x 4.2e-10, friction 1.0e-8 of their ranges (1.0 rtol); old: x 2.7e-7
    assert max(errs["x"], errs["friction"]) <= 10 * rtol, errs


# Campaign seed 5054, inside the error contract's ranges: nine elements (sum k 3.7e4 N/m on 83 kg, omega dt 1.0,
# damping ratio 0.0023), C = 880 N/s on Fc 0.038 N (slip relaxing at C / g ~ 2e4 /s). Every trial sub-step
# across a reversal while the elements slip was rejected by its error estimate (the slip targets and rates
# change sign at v = 0) down to H_MIN dt: old kernel status 3 (error control failed) at sample 90 of 239, as
# did seeds 5010 and 5011; 3 of 80 contract-range sets. Now the step lands at the reversal.
GMS_5054 = fk.GMS(
    fk.Stribeck(Fc=0.03771860148356558, Fs=0.04974449192656047, vs=1.3100610792709215e-05,
                sigma2=8.165769536229922),
    k=[8912.626907787491, 2507.280240773548, 2721.013918176228, 2090.8222467484165, 3823.9507854671665,
       406.0579402187663, 1326.153156943816, 1651.6838637601518, 13758.674768205217],
    xi=[0.07608404429083161, 0.03544612922499591, 0.2319494579455248, 0.09640949560808199,
        0.11473585057741947, 0.0028481627248094724, 0.3793082212415598, 0.010548675897756654,
        0.0526699624890204],
    C=879.6178830747314,
)


def test_gms_fast_slip_reversal_does_not_underflow_the_error_control():
    res, errs = _campaign_run(GMS_5054, 83.48464498633524, 0.04755476670777198, 239, 0.12569850416946104,
                              1.8171869243496888)
    assert res.status == 0, res.message
    # measured 2026-11-24 (gms13): x 6.3e-7, friction 2.9e-6 of their ranges
    assert max(errs["x"], errs["friction"]) <= 10 * fk.SimOptions().rtol, errs


# The accuracy check near its bound (simulation/core.py CHECK_NEAR, now for GMS too). Campaign seed 4141: two
# elements, sum k 4.2e7 N/m on 0.11 kg (omega dt 1.6), Fs < Fc: the run is 7.4 rtol of its position range off
# the twin (inside the contract), its check run at rtol/10 5.75 rtol away: flagged (status 2) before, now the
# run at rtol/100 (6.9 rtol away) judges it and it passes.
GMS_4141 = fk.GMS(
    fk.Stribeck(Fc=0.5253881281736537, Fs=0.38188912968028843, vs=3.020798269126799e-05,
                sigma2=24.487776824514807),
    k=[6397711.844840225, 35304712.70090677], xi=[0.19452280625849555, 0.8054771937415044],
    C=273.2276596568546,
)


def test_gms_run_within_the_contract_near_the_check_bound_passes():
    res, errs = _campaign_run(GMS_4141, 0.11211476010650032, 8.438734406740535e-05, 172, 0.5537395324241842,
                              1.7069401674178861)
    assert res.status == 0, res.message
    assert "accuracy check passed" in res.message, res.message
    # measured 2026-11-24 (gms13): x 7.4e-5, friction 6.4e-5 of their ranges
    assert max(errs["x"], errs["friction"]) <= 10 * fk.SimOptions().rtol, errs


def test_gms_run_beyond_the_contract_near_the_check_bound_stays_flagged():
    """Campaign seed 5006 (inside the contract's ranges: sum k 1.7e5 N/m on 13.7 kg, omega dt 11.7): the
    unchecked run is 11.5 rtol of its friction range off the twin (measured 2026-11-24, gms13), its check run
    9.7 rtol away (near the bound) and the run at rtol/100 11.2: it must stay flagged."""
    law = fk.GMS(
        fk.Stribeck(Fc=0.03071655076152405, Fs=0.02627228666619457, vs=2.6744017841182447e-05,
                    sigma2=28.36124972485245),
        k=[18044.19876537712, 44529.19450494079, 28670.95275066662, 22851.86683270298, 58431.18239651078],
        xi=[0.18928976250210502, 0.5870410428905598, 0.08624270792766425, 0.07388775204463253,
            0.06353873463503847],
        C=62.44007325556839,
    )
    n = 316
    u = 0.04277373995079046 * np.sin(2 * np.pi * 1.3811436379899322 * np.arange(n) / n)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fk.simulate(law, dt=0.10439061365033062, plant=fk.Mass(13.688880044930166), force=u)
    assert res.status == 2 and "accuracy check" in res.message, res.message
