"""Issue 13: the unstable-closed-loop check measured on a grid (a script, not a test: ~1 h on a
loaded 2-core machine).

    python tests/robustness/loop_check_grid.py [emps|ballscrew|twoshaft ...] > grid.jsonl

Machines: the EMPS axis (published M, CoulombViscous, 3 s smooth 0.1 m move and back), the seed
001 ball screw (fig2 stage, paper controller and sensors, 0.3 s cosine), the two-shaft benchmark
of benchmarks/machines.py (0.06 s of its reference). Every inertia x1e-3..1e3 and every actuator
gain (the loop gain) x0.1..10. Per case: the status of the default run (10 sub-steps) and the
truth, measured apart from the check: the plain run against 640 sub-steps (two-shaft: 320),
positions 1 %, velocities and actuator commands 10 % of their range ("truth_frac" > 1: not
converged). Measured 2026-11-23: EMPS 11 flagged / 24 converged, ball screw 13 / 22, two-shaft
12 / 23 (4 of them by the sub-step check); 0 missed, 0 false alarms; 40 converged runs carry the
"unstable loop" note (limit cycles that converge, e.g. the two-shaft benchmark's nut loop).
The two-shaft counts are of the benchmark's first layout (motor rotors on couplings; its nut loop
was linearly unstable); benchmarks/machines.py builds it like the zhang2023 preset since fc16060
(rigid axes, loop radius 0.965), so a rerun gives other two-shaft counts.
The hunting (Stribeck-slope) and barely-damped triggers (ring, f0e192b) came after that
measurement: the grid prints their fields ("stribeck_rho", "zeta", "hunting", "borderline").
Rerun with them (ring, 2026-11-23 13:20 UTC, `emps ballscrew`): ball screw 13 flagged, 0 missed,
0 false alarms, 1 barely damped loop checked (gain x3: truth 0.83 of the bound at 10 sub-steps,
converged, noted); EMPS 11 flagged, 0 missed, 0 false alarms (its 6 barely damped loops, all
inertia x1e2-1e3, run on the exact one-DOF axis kernel, where sub-steps do not apply); no grid
machine can hunt (flat friction). The two-shaft part was not rerun.
"""
import json
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
import frictionkit as fk  # noqa: E402
from frictionkit.control.trajectories import cosine_reference  # noqa: E402
from frictionkit.machines import Machine, simulate_machine  # noqa: E402
from frictionkit.machines.simulate import _run_machine  # noqa: E402
from frictionkit.machines.stability import _at_limit, _disagreement, loop_stability  # noqa: E402
from frictionkit.presets.ballscrew import ballscrew_machine  # noqa: E402
from frictionkit.presets.emps import PUBLISHED, emps_machine  # noqa: E402
from frictionkit.reproduce.zhu_fujimoto import paper_controller, paper_plant, paper_sensors  # noqa: E402


def emps_case():
    m = emps_machine(M=PUBLISHED["M"], friction=fk.CoulombViscous(Fc=PUBLISHED["Fc"], sigma2=PUBLISHED["Fv"]),
                     offset=PUBLISHED["offset"])
    t = np.arange(3001) * 1e-3
    s, r = np.clip(t - 0.1, 0, 1), np.clip(t - 1.6, 0, 1)
    return m, 1e-3, {"qg": 0.1 * s * s * (3 - 2 * s) - 0.1 * r * r * (3 - 2 * r)}, 640


def ballscrew_case():
    ctrl = paper_controller()
    m = ballscrew_machine(paper_plant(), ctrl, paper_sensors())
    ref = cosine_reference(duration=0.3)
    u_ff, th = ctrl.ptc.feedforward(ref.x / ctrl.R, ref.v / ctrl.R)
    return m, ctrl.T, {"theta_d": th, "u_ff": u_ff, "u_f": np.zeros(len(ref))}, 640


def twoshaft_case():
    from machines import two_shaft_machine, two_shaft_reference

    return two_shaft_machine(250e-6), 250e-6, two_shaft_reference(0.06, 250e-6), 320


def scaled(m, f, g):
    d = m.to_dict()
    for x in d["dofs"] + d.get("inertias", []):
        x["inertia"] *= f
    for a in d["actuators"]:
        a["gain"] *= g
    return Machine.from_dict(d)


CASES = {"emps": emps_case, "ballscrew": ballscrew_case, "twoshaft": twoshaft_case}

if __name__ == "__main__":
    for name in sys.argv[1:] or list(CASES):
        m0, dt, inp, truth_n = CASES[name]()
        N = len(next(iter(inp.values())))
        for f in (1e-3, 1e-2, 1e-1, 1.0, 10.0, 1e2, 1e3):
            for g in (0.1, 0.3, 1.0, 3.0, 10.0):
                m = scaled(m0, f, g)
                res = simulate_machine(m, dt=dt, inputs=inp)
                raw = _run_machine(m, dt, inp, N, 10, 0, False)
                ref = _run_machine(m, dt, inp, N, truth_n, 0, False)
                frac = _disagreement(raw, ref)[0] if raw.status == 0 and ref.status == 0 else math.inf
                st = loop_stability(m, dt)
                print(json.dumps({"case": name, "inertia_x": f, "gain_x": g, "rho": st.radius,
                                  "stribeck_rho": st.stribeck_radius, "zeta": st.zeta, "hunting": st.stribeck_unstable,
                                  "borderline": st.borderline,
                                  "status": res.status, "truth_frac": frac,
                                  "at_limit": max(_at_limit(m, raw).values(), default=0.0),
                                  "message": res.message}), flush=True)
