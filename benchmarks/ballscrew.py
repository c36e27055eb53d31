"""Real-time factor of the elastic ball-screw stage in closed loop (seed 001 controller).

Prints simulated seconds per wall-clock second for the 0.5 ms loop with 10 plant sub-steps on
the machine core (``presets.ballscrew.simulate_stage``; issue 8 goal: >= 1000x real time). Not a test. Run: ``.venv/bin/python benchmarks/ballscrew.py``.
"""

from __future__ import annotations

import time

from frictionkit.control.trajectories import cosine_reference
from frictionkit.presets.ballscrew import simulate_stage
from frictionkit.reproduce.zhu_fujimoto import paper_compensator, paper_controller, paper_plant, paper_sensors


def main(duration: float = 60.0, repeats: int = 3, nut_model: str = "sliding") -> None:
    plant, ctrl, sensors = paper_plant(nut_model), paper_controller(), paper_sensors()
    simulate_stage(plant, ctrl, cosine_reference(duration=0.1), sensors=sensors)  # JIT warm-up
    ref = cosine_reference(duration=duration)
    u_f = paper_compensator().signal(ref, "sinc")
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        res = simulate_stage(plant, ctrl, ref, compensation=u_f, sensors=sensors)
        best = min(best, time.perf_counter() - t0)
    assert res.success, res.message
    steps = len(ref)
    print(f"elastic stage ({nut_model} nut), closed loop, T = 0.5 ms, 10 sub-steps: {duration:.0f} s simulated in "
          f"{best:.3f} s wall -> {duration / best:.0f}x real time ({best / steps * 1e6:.2f} µs/step, "
          f"incl. PTC, compensation and setup)")


if __name__ == "__main__":
    main()
    main(nut_model="flank")
    main(nut_model="hertz")
