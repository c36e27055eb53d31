"""Fleets: identify and monitor friction across many axes, on Dask.

* :func:`simulate_fleet` — a simulated fleet (one log per axis-day, drift, temperature,
  noise, a few broken files) with its TOML configuration;
* :func:`identify_fleet` — one task per log on a ``dask.distributed`` cluster (a
  LocalCluster by default, any cluster by scheduler address, or a single process):
  segmentation, static map with intervals and model choice, LuGre through the reversals
  where the data allow, data hash and provenance;
  one row per axis-period in a Parquet table; resumable;
* :func:`monitor_drift` — per-axis trends with uncertainty, temperature regressed out,
  axes flagged with a controlled false-alarm rate;
* :func:`fleet_report` — the fleet page (HTML).
"""

from .config import FleetConfig, config_from_dict, load_config
from .dataset import LogFile, discover, parts_dir
from .drift import TRACKED, drift_summary, monitor_drift
from .identify import PIN_ENV, FleetRun, consolidate, identify_fleet, local_cluster
from .report import fleet_report
from .simulate import SimulatedFleet, daily_test_motion, simulate_fleet
from .task import PARAM_COLUMNS, identify_log, result_schema

__all__ = [
    "FleetConfig",
    "FleetRun",
    "LogFile",
    "PARAM_COLUMNS",
    "PIN_ENV",
    "SimulatedFleet",
    "TRACKED",
    "config_from_dict",
    "consolidate",
    "daily_test_motion",
    "discover",
    "drift_summary",
    "fleet_report",
    "identify_fleet",
    "identify_log",
    "load_config",
    "local_cluster",
    "monitor_drift",
    "parts_dir",
    "result_schema",
    "simulate_fleet",
]
