"""Open-loop driver of the ball-screw kernel shared by the ball-screw unit tests."""

from __future__ import annotations

import numpy as np

from frictionkit.kernels import ballscrew as K


def open_loop(plant, current, T=0.5e-3, nsub=10, *, drive_force=True):
    """Run the closed-loop kernel with all gains zero, so ``current`` is the feed-forward.

    Returns ``(status, outs, fric)``: ``outs`` the kernel's six output traces (``outs[0]``
    table position, ``outs[1]`` motor angle, ``outs[5]`` drive force when ``drive_force``),
    ``fric`` the friction-site forces ``(n_sites, N)``. With ``drive_force=False`` the drive
    force rows are zero (as the sliding-nut model does not need them).
    """
    ch = plant.linear_chain()
    n = ch.M.shape[0]
    PhiN, GN, CvP, CvG = ch.lifted(T, nsub)
    N = current.size
    ctrl = np.zeros(K.N_CTRL)
    ctrl[K.C_T], ctrl[K.C_KTAU], ctrl[K.C_IMAX], ctrl[K.C_R] = T, 1.0, 1e9, plant.R
    outs = [np.zeros(N) for _ in range(6)]
    fric = np.zeros((ch.Fc.size, N))
    X, F = np.zeros(2 * n), np.zeros(ch.Fc.size)
    z = np.zeros(N)
    c_frc = np.concatenate((ch.drive_force_q, ch.drive_force_v)) if drive_force else np.zeros(2 * n)
    status, _ = K.closed_loop(PhiN, GN, CvP, CvG, T / nsub, ch.Fc, ch.sigma0, *ch.flank_arrays(), ch.hertz_array(),
                              F, X, np.concatenate((ch.motor, np.zeros(n))), np.concatenate((ch.table, np.zeros(n))),
                              c_frc, z, current, z, z, z, ctrl, *outs, fric)
    return status, outs, fric
