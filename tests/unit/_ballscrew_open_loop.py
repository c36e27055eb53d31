"""Open-loop driver of the ball-screw stage on the machine core, shared by the ball-screw unit tests."""

from __future__ import annotations

import numpy as np

from frictionkit.machines import Sum, simulate_machine
from frictionkit.plants.ballscrew import ElasticBallScrew
from frictionkit.presets.ballscrew import ballscrew_machine, rayleigh_beta


def open_loop(plant, current, T=0.5e-3, nsub=10):
    """Run the stage of :func:`ballscrew_machine` open loop, ``current`` [A] held over each period.

    A block writes the motor command from the input array, so it is held over the sample (as
    the tests' twins assume) instead of interpolated. Returns ``(res, x_t, theta_m, fbn, fric)``:
    the :class:`MachineResult`, table position, motor angle, drive force through the nut
    (``F(d) + beta k_nut d'``; zeros for a rigid stage) and the friction-site forces in the
    order of :meth:`ElasticBallScrew.linear_chain` (guide, nut, flank_pos, flank_neg; a site
    without friction is a row of zeros).
    """
    m = ballscrew_machine(plant)
    m.add(Sum("i", {"i_in": 1.0}))
    res = simulate_machine(m, dt=T, inputs={"i_in": np.asarray(current, float)}, substeps=nsub)
    N = len(current)
    if isinstance(plant, ElasticBallScrew):
        x_t, th = res.position("x_t"), res.position("theta_m")
        g = plant.R * m.coord("theta_s") + m.coord("x_m") - m.coord("x_t")
        fbn = plant.contact_force(res.position(g)) + rayleigh_beta(plant) * plant.k_nut * res.velocity(g)
        names = ("guide", "nut") if plant.nut_model == "sliding" else ("guide", "nut", "flank_pos", "flank_neg")
    else:
        th = res.position("theta")
        x_t, fbn, names = plant.R * th, np.zeros(N), ("nut",)
    fric = np.zeros((len(names), N))
    for j, s in enumerate(names):
        if s in res.site_names:
            fric[j] = res.force(s)
    return res, x_t, th, fbn, fric
