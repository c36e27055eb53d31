"""``frictionkit models`` lists a package preset's builders (README walk, walk3).

Before: ``zhang2023`` is a package whose ``tdms_machine`` and ``cdfs_machine`` live in submodules, and
the catalog kept only functions defined in the preset module itself, so it listed no builder for the
TDMS (README "Machines": ``cdfs_machine``; the preset's docstring: ``tdms_machine``).
"""

from __future__ import annotations

from frictionkit.catalog import catalog


def test_package_preset_lists_its_builders():
    presets = {p.name: p for p in catalog().presets}
    assert {"tdms_machine", "cdfs_machine"} <= set(presets["zhang2023"].builders)
    assert presets["emps"].builders == ("emps_machine",)   # a one-module preset as before
