"""Exact Jacobians (forward sensitivities, issue 11 part 6) inside the output-error fitters.

The fit with exact Jacobians must end at an equal or lower cost than the same fit with
forward differences (``FitOptions.jacobian="fd"``), from the same start on the same noisy
record; the Jacobian itself must match central differences of the fitter's own residuals
(tight integration). The truth is a known simulated law.
"""

from __future__ import annotations

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.identify import fit_motion_error
from frictionkit.identify.output_error import fit_output_error

LAW = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4)
TRUE = fk.LuGre(LAW, sigma0=1e5, sigma1=63.2)


def _cost(res):
    r = (res.data["y_pred"] - res.data["y"])[1:]
    return 0.5 * float(r @ r)


@pytest.fixture(scope="module")
def force_fits():
    dt = 1e-3
    t = np.arange(2001) * dt
    u = 2.0 * np.sin(np.pi * t)
    v = fk.simulate(TRUE, plant=fk.Mass(1.0), force=u, dt=dt).v
    v = v + 1e-3 * np.abs(v).max() * np.random.default_rng(7).standard_normal(v.size)
    start = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.6, vs=1.3e-3, delta=2.0, sigma2=0.4), sigma0=5e4, sigma1=100.0)
    free = ("sigma0", "sigma1", "Fs", "vs")
    data = {"t": t, "F": u, "v": v}
    return {jac: fit_output_error(data, start, free=free, inertia=1.0, jacobian=jac) for jac in ("auto", "fd")}


def test_force_drive_exact_jacobian_is_used_and_ends_at_equal_or_lower_cost(force_fits):
    ex, fd = force_fits["auto"], force_fits["fd"]
    assert ex.success and fd.success
    assert ex.diagnostics["sensitivity_runs"] >= 1 and fd.diagnostics["sensitivity_runs"] == 0
    assert "exact Jacobian" in ex.provenance["procedure"]["optimiser"]
    assert "forward-difference" in fd.provenance["procedure"]["optimiser"]
    assert _cost(ex) <= _cost(fd) * (1 + 1e-6)
    # fewer simulations: one augmented run per Jacobian instead of four
    assert ex.diagnostics["simulations"] < 0.5 * fd.diagnostics["simulations"]


def test_force_drive_jacobian_matches_central_differences_of_the_residuals():
    """At the start point of a 6-parameter problem, with tight integration so that the
    differences are accurate (step 1e-4 of the transformed parameters)."""
    from frictionkit.identify._oe_params import _Template
    from frictionkit.identify._oe_problem import _Problem

    dt = 1e-3
    t = np.arange(1501) * dt
    u = 2.0 * np.sin(np.pi * t)
    v = fk.simulate(TRUE, plant=fk.Mass(1.0), force=u, dt=dt).v
    start = fk.LuGre(fk.Stribeck(Fc=0.9, Fs=1.6, vs=1.3e-3, delta=2.0, sigma2=0.45), sigma0=5e4, sigma1=100.0)
    tmpl = _Template.of(start, 1.2, 0.05)
    names = ["sigma0", "sigma1", "Fc", "vs", "m", "offset"]
    theta0 = np.array([tmpl.get(n) for n in names])
    w = np.ones(u.size)
    w[0] = 0.0
    prob = _Problem(tmpl, names, u, dt, v, "v", w, fk.SimOptions(rtol=1e-9, atol_F=1e-9), theta0, 1)
    p0 = prob.to_tr(theta0)
    J = prob.jac_exact(p0)
    assert J is not None
    for j in range(p0.size):
        h = 1e-4 * max(1.0, abs(p0[j]))
        a, b = p0.copy(), p0.copy()
        a[j] += h
        b[j] -= h
        fd = (prob.fun(a) - prob.fun(b)) / (2 * h)
        assert np.linalg.norm(J[:, j] - fd) / np.linalg.norm(fd) < 1e-2, names[j]


def test_motion_drive_exact_jacobian_equal_or_lower_cost():
    dt = 1e-4
    t = np.arange(4001) * dt
    x = 20e-6 * np.sin(2 * np.pi * 4.0 * t) * (1 + 4 * (t > t[-1] / 2))
    law = fk.LuGre(LAW, sigma0=1e5, sigma1=30.0)
    F = fk.simulate(law, position=x, dt=dt).friction
    F = F + 0.01 * np.random.default_rng(3).standard_normal(F.size)
    start = fk.LuGre(LAW, sigma0=3e4, sigma1=60.0)
    out = {}
    for jac in ("auto", "fd"):
        out[jac] = fit_motion_error({"t": t, "x": x, "F": F}, start, free=("sigma0", "sigma1"), starts=1,
                                    refine=1, profile=False, jacobian=jac)
    ex, fd = out["auto"], out["fd"]
    assert ex.success and fd.success
    assert "exact Jacobian" in ex.provenance["procedure"]["optimiser"]
    assert "forward-difference" in fd.provenance["procedure"]["optimiser"]
    assert ex.rms <= fd.rms * (1 + 1e-9)
    assert ex["sigma0"] == pytest.approx(1e5, rel=0.05)
    np.testing.assert_allclose(ex.stderr, fd.stderr, rtol=0.05)


@pytest.mark.parametrize("cond", [1e2, 1e9], ids=["cholesky", "qr"])
def test_reduced_problem_keeps_cost_gradient_and_gauss_newton_matrix(cond):
    """What trf reads from (f, J) is unchanged by the (p + 1)-row reduction (issue 11 part 6,
    goal 2): 0.5 |f|^2, J^T f and J^T J, checked against numpy on the full problem; the
    second case is conditioned beyond the Gram/Cholesky limit and takes the QR path."""
    from frictionkit.identify._jacobian import reduce_lsq

    rng = np.random.default_rng(5)
    U, _ = np.linalg.qr(rng.standard_normal((3000, 5)))
    V, _ = np.linalg.qr(rng.standard_normal((5, 5)))
    J = U @ np.diag(np.geomspace(1.0, 1.0 / cond, 5)) @ V * 40.0
    r = rng.standard_normal(3000)
    sc = np.array([1.0, 2.0, 0.5, 3.0, 1e-3])
    f, Jr = reduce_lsq(np.column_stack([J, r]), sc)
    Js = J * sc
    assert f.shape == (6,) and Jr.shape == (6, 5)
    assert f @ f == pytest.approx(r @ r, rel=1e-12)
    np.testing.assert_allclose(Jr.T @ f, Js.T @ r, rtol=1e-6, atol=1e-9 * np.abs(Js.T @ r).max())
    np.testing.assert_allclose(Jr.T @ Jr, Js.T @ Js, rtol=1e-9, atol=1e-12 * np.abs(Js.T @ Js).max())


def test_cli_jacobian_flag(tmp_path):
    """``identify output-error --jacobian auto|fd`` reaches the fitter (the JSON names the
    Jacobian used) and a wrong value is one line, exit 2."""
    import json

    from typer.testing import CliRunner

    import frictionkit.cli.identify  # noqa: F401  (registers the identify group)
    from frictionkit.cli import app

    dt = 1e-3
    t = np.arange(2001) * dt
    u = 2.0 * np.sin(np.pi * t)
    v = fk.simulate(TRUE, plant=fk.Mass(1.0), force=u, dt=dt).v
    csv = tmp_path / "d.csv"
    np.savetxt(csv, np.column_stack([t, u, v]), delimiter=",", header="t,F,v", comments="", fmt="%.17g")
    base = ["identify", "output-error", str(csv), "--time", "t", "--velocity", "v", "--force", "F", "--mass", "1",
            "--Fc", "1", "--Fs", "1.5", "--vs", "1e-3", "--sigma2", "0.4", "--sigma0", "5e4", "--sigma1", "100"]
    runner = CliRunner()
    got = {}
    for jac in ("auto", "fd"):
        res = runner.invoke(app, [*base, "--jacobian", jac, "--json", str(tmp_path / f"{jac}.json")])
        assert res.exit_code == 0, res.output
        got[jac] = json.loads((tmp_path / f"{jac}.json").read_text(encoding="utf-8"))
    assert "exact Jacobian" in got["auto"]["provenance"]["procedure"]["optimiser"]
    assert "forward-difference" in got["fd"]["provenance"]["procedure"]["optimiser"]
    for name in ("sigma0", "sigma1"):
        a, b = (got[j]["parameters"][name]["value"] for j in ("auto", "fd"))
        assert a == pytest.approx(b, rel=1e-3), name
    res = runner.invoke(app, [*base, "--jacobian", "exact"])
    assert res.exit_code == 2
    assert "--jacobian" in res.output and "exact" in res.output


def test_motion_drive_reduced_problem_keeps_cost_gradient_and_gauss_newton_matrix():
    """The motion drive's (p + 1)-row problem (one augmented run per evaluation, force and its derivatives)
    gives the plain problem's cost, gradient and J^T J — plain residuals from fk.simulate, Jacobian by
    central differences of them — with the inertia and offset free over two segments (a rest between)."""
    from frictionkit.identify._jacobian import MotionReducedProblem
    from frictionkit.identify._law_params import LawTemplate
    from frictionkit.identify.motion_data import motion_data
    from frictionkit.identify.motion_error import _Problem

    dt = 1e-4
    t = np.arange(3001) * dt
    x = 20e-6 * np.sin(2 * np.pi * 4.0 * t) + 2e-3 * t
    law = fk.LuGre(LAW, sigma0=1e5, sigma1=30.0)
    F = fk.simulate(law, position=x, dt=dt).friction + 2e-4 * np.gradient(np.gradient(x, dt), dt) + 0.05
    F[1400:1420] = 0.0  # the drive disabled: a rest, state reset after it
    md = motion_data({"t": t, "x": x, "F": F}, drive="position")
    assert len(md.segments) == 2
    start = fk.LuGre(LAW, sigma0=4e4, sigma1=50.0)
    tmpl = LawTemplate.of(start)
    names = ["sigma0", "sigma1", "J", "offset"]
    theta = np.array([4e4, 50.0, 1e-4, 0.02])
    prob = _Problem(tmpl, names, md, {"J": 0.0, "offset": 0.0}, theta, 1.0)
    prob.exact = True
    p = prob.to_tr(theta) + np.array([0.1, -0.2, 0.3, 0.5])
    red = MotionReducedProblem(prob)
    f = red.fun(p)
    Jr = red.jac(p)
    r = prob.resid_nat(prob.to_nat(p))
    J = np.empty((r.size, p.size))
    for j in range(p.size):
        h = 1e-5 * max(1.0, abs(p[j]))
        a, b = p.copy(), p.copy()
        a[j] += h
        b[j] -= h
        J[:, j] = (prob.resid_nat(prob.to_nat(a)) - prob.resid_nat(prob.to_nat(b))) / (2 * h)
    assert f.shape == (5,) and Jr.shape == (5, 4)
    assert f @ f == pytest.approx(r @ r, rel=1e-12)
    np.testing.assert_allclose(Jr.T @ f, J.T @ r, rtol=1e-4)
    np.testing.assert_allclose(Jr.T @ Jr, J.T @ J, rtol=1e-4, atol=1e-6 * np.abs(J.T @ J).max())
    rr, JJ = red.full(p)
    np.testing.assert_allclose(rr, r, rtol=0, atol=1e-12 * np.abs(r).max())
    assert prob.nsens == 1 and prob.nsim == 2 * (1 + 2 * p.size)  # the fit's evaluation: no plain simulation


def test_motion_drive_fit_uses_the_reduced_problem():
    dt = 1e-4
    t = np.arange(4001) * dt
    x = 20e-6 * np.sin(2 * np.pi * 4.0 * t) * (1 + 4 * (t > t[-1] / 2))
    F = fk.simulate(fk.LuGre(LAW, sigma0=1e5, sigma1=30.0), position=x, dt=dt).friction
    res = fit_motion_error({"t": t, "x": x, "F": F}, fk.LuGre(LAW, sigma0=3e4, sigma1=60.0), free=("sigma0", "sigma1"),
                           starts=1, refine=1, profile=False)
    d = res.diagnostics
    assert res.success and res["sigma0"] == pytest.approx(1e5, rel=1e-6)
    # every evaluation of the search is one augmented run; plain simulations only outside it
    # (the result's final residual and the prediction)
    assert d["sensitivity_runs"] >= d["nfev"] and d["simulations"] <= 3
