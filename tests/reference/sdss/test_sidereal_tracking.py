"""Extension (ours; seed 002 designs no controller): the identified LuGre map as feed-forward
lowers the azimuth's RMS tracking error at sidereal rate."""

from __future__ import annotations

from frictionkit.reproduce import sdss as rep


def test_lugre_feedforward_lowers_sidereal_rms(azimuth):
    trk = rep.sidereal_tracking(model=azimuth.fit.model, duration=15.0)
    assert 0 < trk["lugre_feedforward"] < trk["no_compensation"], trk
