"""Reproductions of the source papers on simulated machines (``frictionkit reproduce ...``).

Their JSON documents (``to_dict()`` / ``--json``) carry ``"format"`` and ``"reproduction"`` so
that readers such as ``frictionkit report`` dispatch on what a file says it is.
"""

#: ``"format"`` of a reproduction's JSON document (``reproduce NAME --json``).
REPRODUCTION_FORMAT = "frictionkit.reproduction/1"
#: ``"format"`` of a robustness sweep's JSON document (``reproduce NAME --robustness --json``).
ROBUSTNESS_FORMAT = "frictionkit.robustness/1"


def worst_status(parts: dict) -> tuple[int, str]:
    """``(status, message)`` of a reproduction from its parts ``{name: (status, message)}``: the
    worst part's status, and a message naming every part that is not ok (``"ok"`` when none)."""
    bad = {name: (int(s), m) for name, (s, m) in parts.items() if s}
    if not bad:
        return 0, "ok"
    return max(s for s, _ in bad.values()), "; ".join(f"{name}: status {s} ({m})" for name, (s, m) in bad.items())
