"""Reproductions of the source papers on simulated machines (``frictionkit reproduce ...``).

Their JSON documents (``to_dict()`` / ``--json``) carry ``"format"`` and ``"reproduction"`` so
that readers such as ``frictionkit report`` dispatch on what a file says it is.
"""

#: ``"format"`` of a reproduction's JSON document (``reproduce NAME --json``).
REPRODUCTION_FORMAT = "frictionkit.reproduction/1"
#: ``"format"`` of a robustness sweep's JSON document (``reproduce NAME --robustness --json``).
ROBUSTNESS_FORMAT = "frictionkit.robustness/1"
