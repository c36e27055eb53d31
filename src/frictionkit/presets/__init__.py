"""Presets: published machines and their parameters, each module with its provenance.

* :mod:`~frictionkit.presets.zhu_fujimoto` — seed 001 ball-screw stage (paper values and
  recorded assumptions).
* :mod:`~frictionkit.presets.emps` — the EMPS benchmark axis (Janot, Gautier, Brunot 2019)
  in its position loop on the machine core: :func:`emps_machine`.
* :mod:`~frictionkit.presets.sdss` — seed 002, the SDSS 2.5 m telescope's azimuth, altitude
  and instrument rotator (every value a named assumption: the paper gives none).
* :mod:`~frictionkit.presets.zhang2023` — seed 000, the two-axis differential micro-feed system
  (TDMS) and its single-drive counterpart: Tables 2-8 in SI with corrections, the true friction,
  named assumptions, the §5.2-5.4 virtual experiments and the full closed loop.
"""

from .emps import emps_machine

__all__ = ["emps_machine"]
