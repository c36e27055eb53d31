"""95 % intervals contain the truth 85-99 % of the time (issue 10), over all identified
parameters together. Affordable version (say so): the azimuth static map (eq. 10, 8 parameters)
over 20 noise seeds; the azimuth sigma0/sigma1 (eq. 12) on the first 5 of them; the altitude's
ten parameters (all from torque-driven data) on 2 seeds; the rotator's combined map (8) on the
quick grid for 3 seeds. Static maps as the reproduction computes them: screened runs, intervals
``covariance="run_robust"`` (each run mean carries its own error). The full version (20 seeds, all
28 parameters of the three axes) is ``benchmarks/sdss_coverage.py``: 509 of 560 = 90.9 % before the
constant-velocity screen (the rotator's vs biased -5.25 % on every seed), 470 of 560 = 83.9 % with
it and residual intervals, 552 of 560 = 98.6 % with it and run-robust intervals (README); its
counting is tested here on the session's quick runs."""

from __future__ import annotations

from frictionkit.identify.static_map import fit_static_map
from frictionkit.identify.two_step import fit_two_step, screen_constant_velocity
from frictionkit.presets import sdss
from frictionkit.reproduce import sdss as rep


def _hits(truth, identified):
    return [(n, identified[n]["ci95"][0] <= truth[n] <= identified[n]["ci95"][1]) for n in identified]


def _static_hits(truth, steady):
    used = screen_constant_velocity(steady).steady()
    res = fit_static_map(used["v"], used["F"], model="exponential", delta=2.0, direction="both",
                         covariance="run_robust")
    return _hits(truth, {n: res.parameter(n) for n in res.names})


def test_interval_coverage_over_noise_seeds(altitude, rotator):
    ax = sdss.AzimuthAxis()
    truth = ax.truth()
    hits = []
    for seed in range(20):
        steady = rep.constant_velocity_runs(ax, rep.speed_grid(True), seed=seed)
        if seed < 5:
            tri = rep.torque_run(ax, "triangle", 0.9 * 160.0, 2.0, 3, seed=seed + 11)
            fit = fit_two_step(inertia=ax.inertia, steady=steady, triangle=tri)
            assert fit.status == 0, fit.message
            hits += _hits(truth, fit.parameters())
        else:
            hits += _static_hits(truth, steady)
    alt2 = rep.run_altitude(quick=True, seed=100)
    for o in (altitude, alt2, rotator):
        hits += _hits(o.truth, o.identified)
    rot = sdss.RotatorAxis()
    for seed in (1, 2):
        hits += _static_hits(rot.truth(), rep.constant_velocity_runs(rot, rep.speed_grid(True), seed=seed))
    n = len(hits)
    rate = sum(h for _, h in hits) / n
    missed = sorted({name for name, h in hits if not h})
    assert n == 20 * 8 + 5 * 2 + 2 * 10 + 3 * 8
    # The floor of the finding. Its ceiling (99 %) is checked by the full run only (98.6 %, README):
    # on the quick grid (8 speeds per direction: 4 residual dof for 4 parameters) the run-robust
    # intervals over-cover (measured 212 of 214 = 99.1 %: t(4) = 2.78 and the larger of two noisy
    # variances), so a ceiling here would test the reduced design, not the reproduction.
    assert 0.85 <= rate, f"coverage {100 * rate:.1f} % of {n}; missed: {missed}"


def test_coverage_counts_every_identified_parameter_of_the_three_axes(monkeypatch, azimuth, altitude, rotator):
    """The full-run tool (benchmarks/sdss_coverage.py) on the study engine in this process, the
    axes' runs replaced by the session's quick ones (two 'seeds' of the same outcomes)."""
    outcomes = {"azimuth": azimuth, "altitude": altitude, "rotator": rotator}
    monkeypatch.setattr(rep, "run_azimuth", lambda **kw: azimuth)
    monkeypatch.setattr(rep, "run_altitude", lambda **kw: altitude)
    monkeypatch.setattr(rep, "run_rotator", lambda **kw: rotator)
    r = rep.coverage(seeds=[0, 1], quick=True, workers=0, progress=False)
    assert r["failed"] == {}
    for name, o in outcomes.items():
        h = _hits(o.truth, o.identified)
        assert set(r["axes"][name]["parameters"]) == set(o.identified)
        assert r["axes"][name]["n"] == 2 * len(h)
        assert r["axes"][name]["hits"] == 2 * sum(x for _, x in h)
    assert r["n"] == 2 * (10 + 10 + 8)
    assert sorted(m[:2] for m in r["misses"]) == sorted(
        [name, k] for name, o in outcomes.items() for k, x in _hits(o.truth, o.identified) if not x for _ in range(2))
