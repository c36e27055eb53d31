"""Filters and derivatives checked against closed-form signals."""

from __future__ import annotations

import numpy as np
import pytest

from frictionkit.data import decimate, derivative, lowpass
from frictionkit.errors import DataError, ParameterError

FS = 1000.0
T = np.arange(2000) / FS


def test_lowpass_passes_low_frequency_without_phase_lag():
    slow = np.sin(2 * np.pi * 3.0 * T)
    y = lowpass(slow + 0.2 * np.sin(2 * np.pi * 400.0 * T), FS, 100.0)
    inner = slice(200, -200)
    # zero phase: no lag, amplitude ~1 at 3 Hz; 400 Hz suppressed by > 40 dB
    assert np.max(np.abs(y[inner] - slow[inner])) < 2e-3


def test_lowpass_gain_at_cutoff_is_half_power_squared():
    f = 100.0
    x = np.sin(2 * np.pi * f * T)
    y = lowpass(x, FS, f, order=4)
    # Butterworth |H(fc)| = 1/sqrt(2); forward-backward squares it -> 0.5
    amp = np.sqrt(2.0 * np.mean(y[500:-500] ** 2))  # amplitude from RMS
    assert amp == pytest.approx(0.5, abs=0.02)


def test_lowpass_rejects_cutoff_above_nyquist():
    with pytest.raises(ParameterError, match=r"must be below the Nyquist frequency 500 Hz"):
        lowpass(np.zeros(100), FS, 600.0)


def test_lowpass_leaves_no_end_transient_on_a_constant_velocity_ramp():
    # an axis moving at 0.042 m/s (the EMPS record's slow plateau) has zero acceleration; scipy's default
    # padding (15 samples) left the filter's start-up transient at each end, and twice differentiated it
    # read -0.48 m/s² at the last sample (the -22 N spike of the EMPS rigid-body residual)
    t = np.arange(2000) * 1e-3
    x = 1e-3 + 0.042 * t
    xf = lowpass(x, 1000.0, 100.0)
    a = derivative(derivative(xf, 1e-3), 1e-3)
    assert np.abs(xf - x).max() < 1e-9  # m; the ramp passes unchanged, ends included
    assert np.abs(a).max() < 1e-3  # m/s²


def test_lowpass_needs_enough_samples():
    with pytest.raises(DataError, match=r"filtfilt needs more than 15"):
        lowpass(np.zeros(10), FS, 100.0)


def test_central_difference_of_quadratic_is_exact_inside():
    x = 3.0 * T**2
    v = derivative(x, 1 / FS)
    a = derivative(x, 1 / FS, order=2)
    assert np.allclose(v[1:-1], 6.0 * T[1:-1], atol=1e-12)
    assert np.allclose(a[2:-2], 6.0, atol=1e-6)


def test_savgol_derivative_of_noisy_sine():
    rng = np.random.default_rng(3)
    x = np.sin(2 * np.pi * T) + 1e-6 * rng.standard_normal(T.size)
    v = derivative(x, 1 / FS, method="savgol", window=31, polyorder=3)
    assert np.max(np.abs(v[50:-50] - 2 * np.pi * np.cos(2 * np.pi * T[50:-50]))) < 5e-3


def test_derivative_rejects_bad_arguments():
    with pytest.raises(ParameterError, match=r"method = 'spline'"):
        derivative(np.zeros(10), 0.1, method="spline")
    with pytest.raises(ParameterError, match=r"window = 4: must be odd"):
        derivative(np.zeros(10), 0.1, method="savgol", window=4)
    with pytest.raises(DataError, match=r"y\[2\] = nan"):
        derivative([0.0, 1.0, np.nan, 2.0], 0.1)


def test_decimate_keeps_slow_signal_and_length():
    x = np.sin(2 * np.pi * 2.0 * T)
    y = decimate(x, 10)
    assert y.size == 200
    # Chebyshev I passband ripple 0.05 dB, applied twice: amplitude within ~1.2 %
    assert np.max(np.abs(y[10:-10] - x[::10][10:-10])) < 0.015
    with pytest.raises(ParameterError, match=r"q = 0"):
        decimate(x, 0)
