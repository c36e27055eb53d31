"""Perfect tracking control (seed 001 §2.2, ref. 15: Fujimoto, Hori, Kawamura 2001).

Multirate feed-forward: the reference state is given every frame ``T_r`` (1 ms), the input
changes ``n`` times per frame (``T_u = T_r / n`` = 0.5 ms), ``n`` = plant order = 2. With the
zero-order-hold model ``x[j+1] = A x[j] + B u[j]`` at ``T_u``, the lifted frame model is
``x[k+1] = A^n x[k] + [A^{n-1} B, ..., B] u_vec[k]``; its input matrix is invertible, so
``u_vec[k] = B_l^{-1} (x_d[k+1] - A^n x_d[k])`` — a *stable* inverse that makes the nominal
plant state equal the reference state at every frame instant.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate as val
from ..errors import DataError
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from numpy.typing import ArrayLike


@dataclass(frozen=True, kw_only=True)
class PerfectTrackingControl:
    """PTC for the nominal rigid plant ``K_tau / (J s^2 + B s)`` (state ``[theta, omega]``).

    Parameters
    ----------
    K_tau : float — torque constant [N·m/A].
    J : float — nominal inertia [kg·m²].
    B : float — nominal viscosity [N·m·s/rad].
    T_frame : float — reference frame period ``T_r`` [s] (1 ms).
    n : int — inputs per frame (2 for a second-order plant).

    Examples
    --------
    >>> import numpy as np
    >>> from frictionkit.control.ptc import PerfectTrackingControl
    >>> ptc = PerfectTrackingControl(K_tau=0.715, J=0.01, B=0.1)
    >>> t = np.arange(0, 0.02 + 1e-12, 0.5e-3)
    >>> u, th = ptc.feedforward(np.sin(t), np.cos(t))
    >>> bool(np.allclose(th[::2], np.sin(t[::2])))
    True
    """

    K_tau: float
    J: float
    B: float
    T_frame: float = 1.0e-3
    n: int = 2

    def __post_init__(self) -> None:
        o = "PerfectTrackingControl"
        for name in ("K_tau", "J", "T_frame"):
            object.__setattr__(self, name, val.positive(o, name, getattr(self, name)))
        object.__setattr__(self, "B", val.nonnegative(o, "B", self.B))
        if int(self.n) != self.n or self.n < 2:
            from ..errors import ParameterError

            raise ParameterError(f"{o}.n = {self.n!r}: must be an integer >= 2 (plant order)")

    @property
    def T_input(self) -> float:
        return self.T_frame / self.n

    def discrete_model(self) -> tuple[np.ndarray, np.ndarray]:
        """ZOH ``(A, B)`` of the nominal plant at the input period ``T_frame / n``."""
        from scipy.linalg import expm

        Ac = np.array([[0.0, 1.0], [0.0, -self.B / self.J]])
        Bc = np.array([0.0, self.K_tau / self.J])
        aug = np.zeros((3, 3))
        aug[:2, :2] = Ac * self.T_input
        aug[:2, 2] = Bc * self.T_input
        E = expm(aug)
        return E[:2, :2], E[:2, 2]

    def feedforward(self, theta_ref: ArrayLike, omega_ref: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Feed-forward current and nominal output at the input rate.

        Parameters
        ----------
        theta_ref, omega_ref : array_like
            Reference angle [rad] and angular velocity [rad/s] sampled at ``T_frame / n``
            (frames are every ``n``-th sample, starting at sample 0; samples after the last
            complete frame repeat that frame's inputs).

        Returns
        -------
        u : ndarray — feed-forward current [A], one per sample.
        theta_d : ndarray — nominal plant angle under ``u`` [rad] (equals ``theta_ref`` at
            every frame instant).
        """
        th = val.signal("theta_ref", theta_ref)
        om = val.signal("omega_ref", omega_ref)
        if th.size != om.size:
            raise DataError(f"omega_ref has {om.size} samples: must match theta_ref ({th.size})")
        n = int(self.n)
        N = th.size
        A, Bv = self.discrete_model()
        An = np.linalg.matrix_power(A, n)
        Bl = np.column_stack([np.linalg.matrix_power(A, n - 1 - m) @ Bv for m in range(n)])
        Bl_inv = np.linalg.inv(Bl)
        K = (N - 1) // n  # complete frames: target sample (k+1) n <= N - 1
        if K < 1:
            raise DataError(f"theta_ref has {N} samples: need at least {n + 1} (one PTC frame)")
        idx = np.arange(K + 1) * n
        xd = np.stack([th[idx], om[idx]], axis=1)
        U = (xd[1:] - xd[:-1] @ An.T) @ Bl_inv.T  # (K, n)
        u = np.empty(N)
        u[: K * n] = U.reshape(-1)
        # samples after the last complete frame repeat that frame's inputs
        tail = N - K * n
        u[K * n:] = np.resize(U[-1], tail)
        # nominal response: A is upper triangular [[1, a12], [0, a22]]
        from scipy.signal import lfilter

        a12, a22 = A[0, 1], A[1, 1]
        w_next, _ = lfilter([Bv[1]], [1.0, -a22], u, zi=[a22 * xd[0, 1]])
        omega = np.concatenate(([xd[0, 1]], w_next[:-1]))  # omega[j]
        steps = a12 * omega + Bv[0] * u
        theta_d = xd[0, 0] + np.concatenate(([0.0], np.cumsum(steps[:-1])))
        return u, theta_d
