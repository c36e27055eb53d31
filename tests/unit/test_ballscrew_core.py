"""The seed 001 ball-screw stage on the machine core (``presets/ballscrew.py``).

It replaced the private kernel ``kernels/ballscrew.py`` (deleted, issue 8 part 6). Until the
deletion the core was checked here against that kernel run in the same test: ideal sensors,
every nut model, the §5 cosine and the Fig. 10 fast/slow reversals, each compensator: x_t
within 1.2 nm, drive force within 0.22 N, current within 5 mA; with the paper's sensors x_t
within 29-38 nm (< half a scale count). What remains of that comparison is the regression the
issue asks for: Table 3 of each nut model within one count of the 100 nm scale of the old
kernel's numbers, recorded below (``OLD_KERNEL_TABLE3_UM``, from the last run of the old kernel,
commit 46f338e, seed 0).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import frictionkit as fk
import frictionkit.reproduce.zhu_fujimoto as rz
from frictionkit.control.trajectories import cosine_reference
from frictionkit.errors import ParameterError
from frictionkit.machines import discretise, simulate_machine
from frictionkit.plants.ballscrew import DAHL_SPAN, RigidBallScrew
from frictionkit.presets import zhu_fujimoto as zf
from frictionkit.presets.ballscrew import ballscrew_machine, dob_block, simulate_stage

SCALE = zf.SCALE_RESOLUTION  # one count of the linear scale, 100 nm


@pytest.fixture(scope="module")
def plant():
    return rz.paper_plant()


@pytest.fixture(scope="module")
def ctrl():
    return rz.paper_controller()


# --------------------------------------------------------------------------- mechanics
@pytest.mark.parametrize("which", ["sliding", "flank", "hertz", "rigid"])
def test_machine_matrices_equal_the_linear_chain(which, ctrl):
    p = RigidBallScrew(friction=50.0, B=0.1) if which == "rigid" else rz.paper_plant(which)
    ch = p.linear_chain()
    m = ballscrew_machine(p, ctrl, rz.paper_sensors())
    parts = discretise(m, 5e-5)[4]
    for name, a in (("M", ch.M), ("D", ch.D), ("K", ch.K)):
        np.testing.assert_allclose(parts[name], a, rtol=0, atol=1e-14 * np.abs(a).max(), err_msg=name)
    np.testing.assert_allclose(parts["Bw"][:, 0], ch.b, rtol=1e-15)
    # sites: the same rows as the chain's (guide on x_t, nut and flanks on R theta_s, the
    # Hertz contact on R theta_s + x_m - x_t)
    names = [s.name for s in m.sites]
    old = {"guide": 0, "nut": 1, "flank_pos": 2, "flank_neg": 3, "nut_contact": 4}
    if which == "rigid":
        old = {"nut": 0}
    for j, name in enumerate(names):
        np.testing.assert_allclose(parts["Cq"][j], ch.C[old[name]], rtol=1e-15, err_msg=name)


def test_default_sites_are_the_kernels_dahl_laws(plant):
    m = ballscrew_machine(plant)
    laws = {s.name: s.law for s in m.sites}
    assert laws["guide"] == fk.Dahl(Fc=plant.guide_friction,
                                    sigma0=DAHL_SPAN * plant.guide_friction / plant.presliding_length)
    assert laws["nut"] == fk.Dahl(Fc=plant.nut_friction,
                                  sigma0=DAHL_SPAN * plant.nut_friction / plant.presliding_length)


def test_any_law_can_sit_on_the_nut_and_the_guide(plant, ctrl):
    """Issue 8: "a user can put the GMS they just identified on the nut"."""
    nut = fk.GMS(fk.Stribeck(Fc=plant.nut_friction, Fs=1.2 * plant.nut_friction, vs=1e-3),
                 k=[2e8, 5e8, 1e9, 2e9], xi=[0.4, 0.3, 0.2, 0.1], C=20.0)
    guide = fk.LuGre(fk.Stribeck(Fc=100.0, Fs=120.0, vs=1e-3, sigma2=50.0), sigma0=3e7, sigma1=2e4)
    m = ballscrew_machine(plant, nut_law=nut, guide_law=guide)
    assert {s.name: s.law for s in m.sites} == {"guide": guide, "nut": nut}
    ref = cosine_reference(duration=0.2)
    res = simulate_stage(plant, ctrl, ref, nut_law=nut, guide_law=guide, raise_on_failure=True)
    assert res.success and np.abs(res.error).max() < 20e-6


def test_flank_sites_carry_the_flank_load_of_the_contact():
    p = rz.paper_plant("flank")
    m = ballscrew_machine(p)
    s = {x.name: x for x in m.sites}
    mu, P = p.flank_friction_coefficient, p.nut_preload
    assert s["nut"].law.Fc == pytest.approx(p.nut_friction - 2 * mu * P)
    assert s["flank_pos"].law.Fc == pytest.approx(mu * P)
    assert (s["flank_pos"].load.preload, s["flank_pos"].load.gain, s["flank_pos"].load.floor_gain) == (P, 0.5, 1.0)
    assert (s["flank_neg"].load.gain, s["flank_neg"].load.floor_gain) == (-0.5, -1.0)
    h = {x.name: x for x in ballscrew_machine(rz.paper_plant("hertz")).sites}
    assert h["nut_contact"].role == "compliance" and h["flank_neg"].load.hertz_set == -1


def test_misplaced_laws_are_refused():
    with pytest.raises(ParameterError, match="one friction site, 'nut'"):
        ballscrew_machine(RigidBallScrew(), guide_law=fk.CoulombViscous(Fc=1.0))
    with pytest.raises(ParameterError, match="flank_law needs nut_model 'flank' or 'hertz'"):
        ballscrew_machine(rz.paper_plant(), flank_law=fk.CoulombViscous(Fc=1.0))


def test_dob_block_is_the_observer_recursion():
    """The StateSpace DOB against the observer written out (seed 001 §2.2)."""
    K, J, B, T, a = 0.715, 0.01, 0.1, 0.5e-3, math.exp(-2 * math.pi * 80 * 0.5e-3)
    m = ballscrew_machine(RigidBallScrew())  # open loop: the block reads inputs only
    m.add(dob_block(K_tau=K, J=J, B=B, a=a, T=T, encoder="enc", applied="iapp", u_f="uf"))
    rng = np.random.default_rng(3)
    N = 300
    enc, iapp, uf = np.cumsum(rng.standard_normal(N)) * 1e-3, rng.standard_normal(N), rng.standard_normal(N)
    res = simulate_machine(m, dt=T, inputs={"enc": enc, "iapp": iapp, "uf": uf, "i": np.zeros(N)})
    d = np.zeros(N)
    th_p = om_p = d_p = uf_p = 0.0
    for k in range(N):
        om = (enc[k] - th_p) / T
        raw = K * (iapp[k] - uf_p) - B * om - J * (om - om_p) / T
        d[k] = a * d_p + (1 - a) * raw
        th_p, om_p, d_p, uf_p = enc[k], om, d[k], uf[k]
    np.testing.assert_allclose(res.signal("d_hat"), d, rtol=1e-9, atol=1e-9 * np.abs(d).max())


# --------------------------------------------------------------------------- regression against the old kernel
#: Table 3 [µm] of the deleted private kernel (``control.loop.simulate_closed_loop`` at commit
#: 46f338e, preset Table 1 stage, seed 0, 10 sub-steps), quick (0.65 s) and full (2.15 s).
OLD_KERNEL_TABLE3_UM = {
    ("sliding", True): {"sinc": 2.3631839852628067, "coulomb": 3.1531259507416864, "sigmoid": 2.9466414364909266},
    ("flank", True): {"sinc": 2.3631839852628067, "coulomb": 3.1531259507416864, "sigmoid": 2.9466414364909266},
    ("hertz", True): {"sinc": 2.3631839852628067, "coulomb": 3.1531259507416864, "sigmoid": 2.9466414364909266},
    ("sliding", False): {"sinc": 2.3631839852698846, "coulomb": 3.253125950752412, "sigmoid": 2.94664143649773},
    ("flank", False): {"sinc": 2.3631839852698846, "coulomb": 3.1531259507524134, "sigmoid": 2.94664143649773},
    ("hertz", False): {"sinc": 2.3631839852698846, "coulomb": 3.253125950752412, "sigmoid": 2.94664143649773},
}


@pytest.mark.parametrize("quick", [True, False], ids=["quick", "full"])
@pytest.mark.parametrize("nut_model", ["sliding", "flank", "hertz"])
def test_table3_maxima_within_one_scale_count_of_the_old_kernel(nut_model, quick):
    """Issue 8 part 6: seed-001 Table 3 of each nut model within 0.1 µm (one count of the
    scale) of the old kernel's numbers (the maximum of a quantised error hops between two
    adjacent counts: the old kernel's own full run gives Coulomb 3.15 or 3.25 µm depending on
    the nut model, i.e. on round-off)."""
    plant = rz.paper_plant(nut_model, stage="table1")
    new = rz.table3(plant=plant, quick=quick).max_error_um
    old = OLD_KERNEL_TABLE3_UM[(nut_model, quick)]
    for law in rz.LAWS3:
        assert abs(new[law] - old[law]) <= 0.1 + 1e-9, (law, old[law], new[law])


@pytest.mark.parametrize("which", ["elastic", "rigid"])
def test_site_forces_converge_in_the_substep(which, plant, ctrl):
    """Against the core at 160 sub-steps (its converged limit): the core at the preset's 10
    sub-steps is within 2 N in the site forces (of a 1.27 kN nut level) and 1 nm in x_t. (The
    old kernel at 10 sub-steps was 18 N off its own limit at the nut.)"""
    p = plant if which == "elastic" else RigidBallScrew(friction=1200.0)
    ref = cosine_reference(duration=0.65)
    u_f = rz.paper_compensator().signal(ref, "sinc", rz._classify(ref, plant))
    lim = simulate_stage(p, ctrl, ref, compensation=u_f, substeps=160, raise_on_failure=True)
    new = simulate_stage(p, ctrl, ref, compensation=u_f, raise_on_failure=True)
    d_new = np.abs(new.friction - lim.friction).max(axis=1)
    assert np.all(d_new < 2.0), d_new
    assert np.abs(new.x_t - lim.x_t).max() < 1e-9


def test_reproduction_runs_on_the_core(monkeypatch):
    """``reproduce.zhu_fujimoto`` and ``control.loop.simulate_closed_loop`` both go through
    ``simulate_stage``; the private kernel is gone."""
    import importlib.util

    assert importlib.util.find_spec("frictionkit.kernels.ballscrew") is None
    calls = []
    real = rz.simulate_stage

    def spy(*a, **k):
        calls.append(k.get("substeps"))
        return real(*a, **k)

    monkeypatch.setattr(rz, "simulate_stage", spy)
    ref = cosine_reference(duration=0.05)
    rz._run(rz.paper_plant(), ref, np.zeros(len(ref)), 0)
    assert calls == [zf.N_SUBSTEPS]
    import frictionkit.presets.ballscrew as pb
    from frictionkit.control.loop import simulate_closed_loop

    monkeypatch.setattr(pb, "simulate_stage", spy)
    simulate_closed_loop(RigidBallScrew(), rz.paper_controller(), ref, n_substeps=3)
    assert calls[-1] == 3
