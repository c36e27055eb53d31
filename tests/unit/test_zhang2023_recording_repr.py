"""``print(rec)`` of a zhang2023 TDMSRecording is one short line (README walk leftovers, item 3)."""
import numpy as np

from frictionkit.presets.zhang2023.plant import Reference, TDMSRecording


def test_repr_is_short_and_names_sizes_duration_and_mode():
    t = np.arange(4001) * 250e-6  # the paper's 250 µs grid, 1 s
    z = np.zeros_like(t)
    ref = Reference(t=t, th1=z, th2=z, mode="different", segments=((0, 2000, 0.01), (2000, 4001, -0.01)))
    rec = TDMSRecording(reference=ref, drive="tdms", t=t, theta1=z, theta2=z, x_scale=z, torque1=z, torque2=z,
                        theta1_true=z, theta2_true=z, x_t_true=z, v_t_true=z, omega1=z, omega2=z, F_axial=z,
                        site_forces={"guide": z, "ball": z}, status=0, message="ok")
    text = repr(rec)
    assert len(text) < 200 and "\n" not in text
    assert text == ("TDMSRecording(drive='tdms', mode='different', n=4001, dt=0.00025 s, duration=1 s, plateaus=2, "
                    "sites=['ball', 'guide'], status=0)")
