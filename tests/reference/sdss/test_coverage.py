"""95 % intervals contain the truth 85-99 % of the time (issue 10), over all identified
parameters together. Affordable version (say so): the azimuth static map (eq. 10, 8 parameters)
over 20 noise seeds; the azimuth sigma0/sigma1 (eq. 12) on the first 5 of them; the altitude's
ten parameters (all from torque-driven data) on 2 seeds."""

from __future__ import annotations

from frictionkit.identify.static_map import fit_static_map
from frictionkit.identify.two_step import fit_two_step
from frictionkit.presets import sdss
from frictionkit.reproduce import sdss as rep


def _hits(truth, identified):
    return [(n, identified[n]["ci95"][0] <= truth[n] <= identified[n]["ci95"][1]) for n in identified]


def test_interval_coverage_over_noise_seeds(altitude):
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
            res = fit_static_map(steady["v"], steady["F"], model="exponential", delta=2.0, direction="both")
            hits += _hits(truth, {n: res.parameter(n) for n in res.names})
    alt2 = rep.run_altitude(quick=True, seed=100)
    for o in (altitude, alt2):
        hits += _hits(o.truth, o.identified)
    n = len(hits)
    rate = sum(h for _, h in hits) / n
    missed = sorted({name for name, h in hits if not h})
    assert n == 20 * 8 + 5 * 2 + 2 * 10
    assert 0.85 <= rate <= 0.99, f"coverage {100 * rate:.1f} % of {n}; missed: {missed}"
