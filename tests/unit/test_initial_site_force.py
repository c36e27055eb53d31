"""The t = 0 force of a static friction site held at rest (README walk leftovers, item 1)."""
import numpy as np
import pytest

import frictionkit as fk
from frictionkit.presets.emps import emps_machine

# the EMPS published model (Janot et al., EMPS benchmark): M = 95.1089 kg, Fc = 20.3935 N,
# Fv = 203.5034 N s/m, offset -3.1648 N
M, FC, FV, OFFSET = 95.1089, 20.3935, 203.5034, -3.1648


@pytest.mark.parametrize("fast_path", [True, False])
def test_emps_held_against_offset_from_t0(fast_path):
    m = emps_machine(M=M, friction=fk.CoulombViscous(Fc=FC, sigma2=FV), offset=OFFSET)
    qg = np.zeros(20)  # at rest: the friction holds the offset from the first sample on
    res = fk.simulate_machine(m, dt=1e-3, inputs={"qg": qg}, fast_path=fast_path)
    assert res.path.startswith("axis" if fast_path else "general loop")
    assert np.all(res.velocity("q") == 0.0)
    np.testing.assert_allclose(np.abs(res.force("friction")), abs(OFFSET), rtol=1e-12)


def test_site_moving_at_t0_keeps_its_sliding_force():
    m = fk.Machine("slider")
    x = m.dof("x", inertia=1.0, v0=0.5)
    m.friction("contact", x, law=fk.CoulombViscous(Fc=2.0, sigma2=0.0))
    m.actuator("push", x, gain=1.0, command="u")
    res = fk.simulate_machine(m, dt=1e-3, inputs={"u": np.zeros(10)})
    assert res.force("contact")[0] == pytest.approx(2.0)  # sliding at +0.5 m/s: +Fc
