"""Presets: published machines and their parameters, each module with its provenance.

* :mod:`~frictionkit.presets.zhu_fujimoto` — seed 001 ball-screw stage (paper values and
  recorded assumptions).
* :mod:`~frictionkit.presets.emps` — the EMPS benchmark axis (Janot, Gautier, Brunot 2019)
  in its position loop on the machine core: :func:`emps_machine`.
* :mod:`~frictionkit.presets.sdss` — seed 002, the SDSS 2.5 m telescope's azimuth, altitude
  and instrument rotator (every value a named assumption: the paper gives none).
"""

from .emps import emps_machine

__all__ = ["emps_machine"]
