"""Adapters: a saved result file -> report sections.

:func:`sections_from_file` reads one file and dispatches on what the file says it is:

* JSON with ``"format": "frictionkit.identification/1"`` (``identify ... --json``,
  ``IdentificationResult.save_json``) -> data overview, parameter table with intervals and
  identifiability flags, the fit's own plot (static curves over the data per direction,
  measured vs predicted / simulated, reversal fit);
* JSON with ``"format": "frictionkit.model/1"`` or a bare law (``fk.save_model``) -> the
  parameters with units and provenance, the steady-state map;
* the JSON of ``reproduce zhu-fujimoto | sdss | zhang2023`` (their ``"paper"`` field names
  the seed) -> the findings beside the paper's numbers, holds / does not hold;
  ``reproduce zhang2023 --robustness`` (``holds_fraction``);
* the JSON of ``compensate`` (``"preset"`` + ``"compensators"``) -> the error table;
* the JSON of ``study --json`` (per-compensator summary);
* Parquet of ``study`` (its ``study_sha256`` column) -> per-compensator tracking-error
  statistics, box/strip plot;
* Parquet of ``fleet identify`` (``axis``, ``period``, ``ok`` columns) -> the fleet in
  numbers, parameter distributions, flagged axes, failed files;
* CSV / Parquet traces of ``simulate --out`` (a ``t [s]`` column) -> time histories and
  the hysteresis loop F(x).

The reproductions, robustness sweeps, ``compensate --json`` and ``study --json`` carry
``"format"`` (``frictionkit.reproduction/1``, ``frictionkit.robustness/1``,
``frictionkit.compensation/1``, ``frictionkit.study/1``) and are dispatched on it; older files
without it are recognised by their fixed top-level keys (the ``paper`` string, ``preset`` +
``compensators``, ``compensators`` + ``runs``), tables by their Parquet/CSV columns.
A file that is none of these, or is broken, raises ONE :class:`~frictionkit.DataError`
naming the file and why.
"""

from __future__ import annotations

import json
import math
import os
import re
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import DataError, FrictionKitError, ParameterError
from .builder import Section, figure_png

__all__ = ["KINDS", "sections_from_file", "sections_from_result", "zhu_fujimoto_findings"]

#: What :func:`sections_from_file` reads, by kind (the ``kind`` it reports).
KINDS = ("identification", "model", "reproduce-zhu-fujimoto", "reproduce-sdss", "reproduce-zhang2023",
         "robustness", "compensation", "study", "study-summary", "fleet", "traces")


# --------------------------------------------------------------------------- formatting
def fmt(x: Any, digits: int = 4) -> str:
    """A number for a table: ``digits`` significant digits, ``–`` for None / NaN."""
    if x is None:
        return "–"
    if isinstance(x, (bool, np.bool_)):
        return "yes" if x else "no"
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    try:
        v = float(x)
    except (TypeError, ValueError):
        return str(x)
    if not math.isfinite(v):
        return "–" if math.isnan(v) else ("∞" if v > 0 else "−∞")
    return f"{v:.{digits}g}"


def _holds(flag: Any) -> str:
    return "holds" if flag else "does not hold"


def _um(x: Any, digits: int = 4) -> str:
    return "–" if x is None else fmt(1e6 * float(x), digits)


def _plt():
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt


# --------------------------------------------------------------------------- dispatch
def sections_from_file(path: str | os.PathLike) -> tuple[str, list[Section]]:
    """``(kind, sections)`` for one result file (see the module docstring for the kinds).

    Raises
    ------
    DataError
        One line naming the file and why it cannot be reported: missing, a folder, an
        unknown type, broken, or a JSON / table of no kind frictionkit writes.
    """
    p = Path(path)
    where = f"result file '{p}'"
    if not p.exists():
        raise DataError(f"{where}: no such file")
    if p.is_dir():
        raise DataError(f"{where}: is a folder; give a result file (JSON, Parquet or CSV)")
    suffix = p.suffix.lower()
    try:
        if suffix == ".json":
            kind, secs = _json_file(p, where)
        elif suffix in (".parquet", ".pq"):
            kind, secs = _parquet_file(p, where)
        elif suffix == ".csv":
            kind, secs = _csv_file(p, where)
        else:
            raise DataError(f"{where}: unknown file type {suffix or '(no extension)'!r}; frictionkit report reads "
                            "result JSON (identify, save_model, reproduce, compensate, study --json), Parquet "
                            "(fleet identify, study, simulate --out) and trace CSV (simulate --out)")
    except DataError as exc:
        msg = " ".join(str(exc).split())
        if str(p) not in msg:
            msg = f"{where}: {msg}"
        raise DataError(msg) from None
    except (KeyError, TypeError, ValueError, AttributeError, IndexError, OverflowError) as exc:
        detail = f"missing key {exc.args[0]!r}" if isinstance(exc, KeyError) else " ".join(str(exc).split())
        raise DataError(f"{where}: malformed content ({type(exc).__name__}: {detail})") from None
    for s in secs:
        s.source = s.source or p.name
        s.kind = s.kind or kind
    return kind, secs


def sections_from_result(result: Any, *, name: str | None = None) -> tuple[str, list[Section]]:
    """``(kind, sections)`` for a result object in memory.

    Takes an :class:`~frictionkit.identify.IdentificationResult`, a friction law or
    :class:`~frictionkit.models.ModelFile`, a result with ``to_dict()`` (compensation,
    reproductions) or its dict, a :class:`~frictionkit.study.StudyResult` /
    :class:`~frictionkit.fleet.FleetRun` (their ``table``) or a pandas DataFrame (study, fleet,
    traces), a :class:`~frictionkit.SimulationResult` (its traces), a
    :class:`~frictionkit.machines.MachineResult` (its summary and ``plot()``, actuators included).

    Raises
    ------
    ParameterError
        An object of no kind the report knows, named by its type.
    DataError
        A document or table of no kind the report reads.
    """
    import pandas as pd

    from ..identify import IdentificationResult
    from ..models.base import law_entry
    from ..models.files import ModelFile

    label = name or type(result).__name__
    where = f"result {label}"
    if isinstance(result, IdentificationResult):
        return "identification", _named(identification_sections(result, name=label), label)
    if isinstance(result, ModelFile):
        return "model", _named(model_sections(result, name=label), label)
    try:
        law_entry(result)
    except (ParameterError, FrictionKitError, TypeError, AttributeError):
        pass
    else:
        return "model", _named(model_sections(ModelFile(model=result), name=label), label)
    if hasattr(result, "table") and isinstance(getattr(result, "table"), pd.DataFrame):
        result = result.table
    if isinstance(result, pd.DataFrame):
        kind, secs = _table_kind(result, where)
        return kind, _named(secs, label, kind)
    if hasattr(result, "states") and hasattr(result, "friction") and hasattr(result, "t"):  # a SimulationResult
        from ..simulation.traces import trace_table

        return "traces", _named(traces_sections(pd.DataFrame(trace_table(result))), label, "traces")
    if hasattr(result, "dof_names") and hasattr(result, "machine") and hasattr(result, "site_forces"):
        return "machine-run", _named(machine_run_sections(result), label, "machine-run")
    doc = result.to_dict() if callable(getattr(result, "to_dict", None)) else result
    if isinstance(doc, Mapping):
        kind, secs = _json_doc(doc, where, name=label)
        return kind, _named(secs, label, kind)
    raise ParameterError(f"Report.add_result: a {type(result).__name__} is not a result the report knows (an "
                         "IdentificationResult, a friction law or ModelFile, a result with to_dict(), a study or "
                         "fleet table, a SimulationResult or MachineResult)")


def _named(secs: list[Section], source: str, kind: str = "") -> list[Section]:
    for s_ in secs:
        s_.source = s_.source or source
        s_.kind = s_.kind or kind
    return secs


def _json_file(p: Path, where: str) -> tuple[str, list[Section]]:
    from ..identify.result import read_json_object

    doc = read_json_object(p, where)
    if _is_run_summary(doc):  # the --json of 'simulate': report the traces it names
        traces = doc.get("outputs", {}).get("traces") if isinstance(doc.get("outputs"), Mapping) else None
        if doc.get("kind") != "machine" and isinstance(traces, str):
            for cand in (p.parent / traces, Path(traces)):
                if cand.is_file():
                    reader = _parquet_file if cand.suffix.lower() in (".parquet", ".pq") else _csv_file
                    kind, secs = reader(cand, f"traces '{cand}' (named by {where})")
                    status = doc.get("status", 0)
                    if status != 0 and secs:  # the traces do not carry it: a flagged run read as a good one
                        secs[0].text.insert(0, f"Run status {status} (from the summary, {where}): "
                                               f"{' '.join(str(doc.get('message', '')).split())}")
                    return kind, secs
        raise DataError(_run_summary_message(doc, where, traces))
    return _json_doc(doc, where, name=p.name)


def _is_run_summary(doc: Mapping[str, Any]) -> bool:
    from ..simulation.traces import RUN_FORMAT

    # files written before the summary carried a format (2026-11-23): by their keys
    return doc.get("format") == RUN_FORMAT or (doc.get("format") is None and "drive" in doc and "samples" in doc and (
        "peak_friction" in doc or "peak_F" in doc))


def _run_summary_message(doc: Mapping[str, Any], where: str, traces: Any) -> str:
    if doc.get("kind") == "machine":
        return (f"{where}: the summary of a machine simulation; the report does not read machine traces yet "
                "(plot them with --plot, or MachineResult.plot())")
    if isinstance(traces, str):
        return f"{where}: the summary of a simulate run; its traces '{traces}' are not there — pass the traces file"
    return (f"{where}: the summary of a simulate run without traces; run simulate with --out TRACES.csv "
            "and report that file")


def _json_doc(doc: Mapping[str, Any], where: str, *, name: str) -> tuple[str, list[Section]]:
    """Dispatch a parsed JSON document (a file's, or a result object's ``to_dict()``)."""
    from ..identify.result import JSON_FORMAT
    from ..models.files import MODEL_FORMAT, ModelFile

    fmt_ = doc.get("format")
    if _is_run_summary(doc):
        raise DataError(_run_summary_message(doc, where, None))
    if fmt_ == JSON_FORMAT:
        from ..identify import IdentificationResult

        try:
            res = IdentificationResult.from_dict(doc)
        except DataError as exc:
            raise DataError(f"{where}: {exc}") from None
        written = doc.get("written_by") if isinstance(doc.get("written_by"), Mapping) else None
        return "identification", identification_sections(res, name=name, written=written)
    if doc.get("kind") == "machine" and (fmt_ == MODEL_FORMAT or (isinstance(fmt_, str) and
                                                                   fmt_.startswith("frictionkit.model/"))):
        raise DataError(f"{where}: a machine model file; the report reads friction-law model files and "
                        "results — simulate the machine (frictionkit simulate MACHINE.json --input ... --out "
                        "traces.csv) and report the traces")
    if fmt_ == MODEL_FORMAT or (fmt_ is None and ("law" in doc or "type" in doc)) or (
            isinstance(fmt_, str) and fmt_.startswith("frictionkit.model/")):
        try:
            mf = ModelFile.from_dict(doc)
        except (DataError, FrictionKitError) as exc:
            raise DataError(f"{where}: {' '.join(str(exc).split())}") from None
        return "model", model_sections(mf, name=name)
    from ..reproduce import REPRODUCTION_FORMAT, ROBUSTNESS_FORMAT

    readers = {"zhu-fujimoto": zhu_fujimoto_sections, "sdss": sdss_sections, "zhang2023": zhang2023_sections}
    if fmt_ == REPRODUCTION_FORMAT:
        which = doc.get("reproduction")
        if which not in readers:
            raise DataError(f"{where}: a reproduction of {which!r}; frictionkit report reads {sorted(readers)}")
        return f"reproduce-{which}", readers[which](doc)
    if fmt_ == ROBUSTNESS_FORMAT:
        return "robustness", robustness_sections(doc)
    from ..compensate import RESULT_FORMAT as COMPENSATION_FORMAT
    from ..study import STUDY_FORMAT

    if fmt_ == COMPENSATION_FORMAT:
        return "compensation", compensation_sections(doc)
    if fmt_ == STUDY_FORMAT:
        return "study-summary", study_summary_sections(doc)
    if fmt_ is not None:
        known = (JSON_FORMAT, MODEL_FORMAT, REPRODUCTION_FORMAT, ROBUSTNESS_FORMAT, COMPENSATION_FORMAT, STUDY_FORMAT)
        raise DataError(f"{where}: \"format\" is {fmt_!r}, not one frictionkit report reads "
                        f"({', '.join(map(repr, known))})")
    paper = doc.get("paper")   # files written before the reproductions carried a format (2026-11-23)
    if isinstance(paper, str):
        if "seed 001" in paper and "table3" in doc:
            return "reproduce-zhu-fujimoto", zhu_fujimoto_sections(doc)
        if "seed 002" in paper and "axes" in doc:
            return "reproduce-sdss", sdss_sections(doc)
        if "seed 000" in paper and "table7" in doc:
            return "reproduce-zhang2023", zhang2023_sections(doc)
    if "holds_fraction" in doc:
        return "robustness", robustness_sections(doc)
    # compensate / study --json written before they carried a format (2026-11-23): by their keys
    if "preset" in doc and isinstance(doc.get("compensators"), Mapping):
        return "compensation", compensation_sections(doc)
    if isinstance(doc.get("compensators"), Mapping) and "runs" in doc:
        return "study-summary", study_summary_sections(doc)
    keys = ", ".join(sorted(map(str, doc))[:8])
    raise DataError(f"{where}: a JSON object of no kind frictionkit report reads (keys: {keys}); expected an "
                    "identification result, a model file, or the --json of reproduce, compensate or study")


def _parquet_file(p: Path, where: str) -> tuple[str, list[Section]]:
    import pandas as pd

    try:
        df = pd.read_parquet(p)
    except Exception as exc:  # noqa: BLE001 - pyarrow raises many types for a broken file
        raise DataError(f"{where}: not a readable Parquet file ({type(exc).__name__}: "
                        f"{' '.join(str(exc).split())[:200]})") from None
    return _table_kind(df, where)


def _csv_file(p: Path, where: str) -> tuple[str, list[Section]]:
    import pandas as pd

    try:
        df = pd.read_csv(p)
    except UnicodeDecodeError as exc:
        raise DataError(f"{where}: not UTF-8 text (byte {exc.start})") from None
    except Exception as exc:  # noqa: BLE001 - pandas parser errors
        raise DataError(f"{where}: not a readable CSV file ({' '.join(str(exc).split())[:200]})") from None
    return _table_kind(df, where)


def _table_kind(df, where: str) -> tuple[str, list[Section]]:
    cols = set(df.columns)
    if {"study_sha256", "compensator", "max_error", "ok"} <= cols:
        return "study", study_sections(df)
    if {"axis", "period", "ok"} <= cols:
        return "fleet", fleet_sections(df)
    if "t [s]" in cols and any(str(c).startswith(("friction [", "F [")) for c in cols):  # "F [": older files
        return "traces", traces_sections(df)
    if "t [s]" in cols and any(str(c).startswith("x.") for c in cols):  # a machine's run (simulate MACHINE.json)
        return "machine-traces", machine_traces_sections(df)
    shown = ", ".join(map(str, list(df.columns)[:8]))
    raise DataError(f"{where}: a table of no kind frictionkit report reads (columns: {shown}); expected the "
                    "Parquet of 'fleet identify' or 'study', or the traces of 'simulate --out' (a 't [s]' column "
                    "beside 'friction [N]' or, of a machine, 'x.<dof> [m]')")


# --------------------------------------------------------------------------- identification
_KIND_TITLES = {"static_map": "Static friction map", "rigid_body": "Rigid-body inverse dynamics",
                "output_error": "Output-error fit", "presliding": "Pre-sliding (GMS) fit",
                "reversal": "Reversal compensator fit"}


def _flags(res) -> dict[str, list[str]]:
    """Warnings that name a parameter (as a word), by parameter."""
    out: dict[str, list[str]] = {}
    sides = {"_pos": "positive:", "_neg": "negative:"}  # a directional fit's warnings name side and base name
    for w in res.warnings:
        for n in res.names:
            base, side = (n[:-4], sides[n[-4:]]) if n[-4:] in sides else (n, None)
            if re.search(rf"(?<![\w.]){re.escape(n)}(?!\w)", w) or (
                    side and w.startswith(side) and re.search(rf"(?<![\w.]){re.escape(base)}(?!\w)", w[len(side):])):
                out.setdefault(n, []).append(w)
    return out


def identification_sections(res, *, name: str = "result", written: Mapping[str, Any] | None = None) -> list[Section]:
    """Data overview, parameters with intervals and flags, the fit's plot, of an
    :class:`~frictionkit.identify.IdentificationResult` (``written``: its file's ``written_by``)."""
    prov = res.provenance
    units = prov.get("units", {}) if isinstance(prov.get("units"), Mapping) else {}
    sec = Section(f"{_KIND_TITLES.get(res.kind, res.kind)}: {res.model_name}")
    status = "converged" if res.success else f"did NOT converge: {res.message}"
    sec.text.append(f"{res.n_obs} observations, {res.dof} residual degrees of freedom; RMS residual "
                    f"{fmt(res.rms)} {units.get('F', '')}".rstrip() + f", relative error "
                    f"{fmt(res.relative_error_percent)} %; {status}.")
    # data overview
    over = [["item", "value"]]
    for key, label in (("file", "data file"), ("data_file", "data file"), ("sha256", "SHA-256"),
                       ("data_sha256", "SHA-256"), ("procedure", "procedure"), ("method", "method")):
        if key in prov and not isinstance(prov[key], (Mapping, list)):
            over.append([label, str(prov[key])])
    if isinstance(prov.get("columns"), Mapping):
        over.append(["columns", ", ".join(f"{k}: {v}" for k, v in prov["columns"].items())])
    if isinstance(prov.get("records"), list):
        over.append(["records", str(len(prov["records"]))])
    if res.diagnostics.get("data_scale_text"):
        over.append(["data scale", str(res.diagnostics["data_scale_text"])])
    from ..plotting.identify import fitted_signal

    quantity, unit = fitted_signal(res)
    labels = {"v": f"velocity [{units.get('v', 'm/s')}]", "F": f"force [{units.get('F', 'N')}]",
              "x": f"position [{units.get('x', 'm')}]", "t": "time [s]", "y": f"measured {quantity} [{unit}]",
              "xi": f"displacement from reversal [{units.get('x', 'm')}]"}
    for key, arr in res.data.items():
        if key in labels and arr.size:
            fin = arr[np.isfinite(arr)]
            if fin.size:
                over.append([labels[key], f"{fmt(fin.min())} … {fmt(fin.max())} ({arr.size} samples)"])
    if written:
        over.append(["written by", f"frictionkit {written.get('frictionkit_version', '?')}, {written.get('date', '?')}"])
    sec.tables.append(("Data overview", over))
    # parameters (after the data overview)
    flags = _flags(res)
    rows = [["parameter", "value", "std. error", "95 % interval", "unit", "identifiable"]]
    for i, n in enumerate(res.names):
        lo, hi = res.ci95[i]
        rows.append([n, fmt(res.values[i], 6), fmt(res.stderr[i], 3), f"[{fmt(lo, 5)}, {fmt(hi, 5)}]", res.units[i],
                     "flagged" if n in flags else "ok"])
    sec.tables.append(("Parameters", rows))
    for side, part in res.parts.items():
        sec.text.append(f"{side} direction: {part.model_name}, {part.n_obs} points, RMS residual {fmt(part.rms)}"
                        + (f"; {len(part.warnings)} warning(s)" if part.warnings else "") + ".")
    for w in res.warnings:
        sec.text.append(f"Flag: {w}")
    if not any(np.asarray(a).size for a in res.data.values()):
        sec.text.append("The file holds no fitted data (saved with include_data=False, or by identify rigid-body, "
                        "presliding or force-driven output-error before 2026-11-24): no plot of the fit here; "
                        "the verb's --plot draws it.")
        return [sec]
    plt = _plt()
    try:
        ax = res.plot()
        fig = ax.figure
        # fit over its residual: two panels; a pre-sliding fit's force–displacement loop beside them
        fig.set_size_inches(*{1: (8, 4.2), 2: (8, 5.6)}.get(len(fig.axes), (11, 5.2)))
        if fig.get_layout_engine() is None:
            fig.tight_layout()
        sec.figures.append((f"{Path(name).stem}.png", figure_png(fig)))
    except Exception as exc:  # noqa: BLE001 - a plot must not hide the numbers
        plt.close("all")
        sec.text.append(f"(plot failed: {type(exc).__name__}: {' '.join(str(exc).split())})")
    return [sec]


# --------------------------------------------------------------------------- model files
def model_sections(mf, *, name: str = "model") -> list[Section]:
    """Parameters with units, provenance, steady-state map and, for a dynamic law, its hysteresis
    loop, of a :class:`~frictionkit.models.ModelFile`."""
    from ..models.base import law_entry, law_to_dict
    from ..models.files import _flatten, parameter_units

    law_name = law_entry(mf.model).name
    sec = Section(f"Friction model: {law_name}")
    units = parameter_units(mf.model, mf.units)
    rows = [["parameter", "value", "unit"]]
    for key, val in _flatten(law_to_dict(mf.model)).items():
        if isinstance(val, list):
            rows.append([key, "[" + ", ".join(fmt(v, 6) for v in val) + "]", units.get(key, "")])
        else:
            rows.append([key, fmt(val, 6) if not isinstance(val, str) else val, units.get(key, "")])
    sec.table = rows
    prov = [["provenance", "value"]] + [[k, str(v)] for k, v in mf.provenance.items()
                                         if not isinstance(v, (Mapping, list))]
    prov.append(["file format", mf.format])
    sec.tables.append(("Provenance", prov))
    plt = _plt()
    loop = _hysteresis_run(mf.model)
    fig, axs = plt.subplots(1, 2 if loop else 1, figsize=(12 if loop else 7, 3.8), layout="constrained", squeeze=False)
    mf.plot(ax=axs[0, 0])
    if loop:
        x, F, amp = loop
        um = mf.units["x"] == "m"  # the loop's x axis and its amplitude in µm (was: axis in µm, title in m)
        amp_txt = f"{fmt(1e6 * amp, 3)} µm" if um else f"{fmt(amp, 3)} {mf.units['x']}"
        axs[0, 1].plot(1e6 * x if um else x, F, lw=1)
        axs[0, 1].set(xlabel=f"x [{'µm' if um else mf.units['x']}]", ylabel=f"friction [{mf.units['F']}]",
                      title=f"{law_name}: hysteresis, ±{amp_txt} sine, two cycles")
        axs[0, 1].grid(alpha=0.3)
        sec.text.append(f"Hysteresis loop: the law driven along a slow sine of ±{amp_txt} "
                        "(5 × its pre-sliding distance, level / stiffness) from the unloaded state.")
    sec.figures.append((f"{Path(name).stem}_model.png", figure_png(fig)))
    return [sec]


def _hysteresis_run(law) -> tuple[np.ndarray, np.ndarray, float] | None:
    """``(x, F, amplitude)`` of a dynamic law driven along a slow sine of 5 pre-sliding distances,
    or None for laws without one (static maps, scheduled laws, no stiffness in the parameters).

    The pre-sliding distance is the largest friction level (``Fc``/``Fs`` fields) over the smallest
    stiffness (``sigma0``/``k``); the peak speed is a tenth of the smallest ``vs`` (1e-3 of the
    amplitude per second without one), so the loop shows pre-sliding, not the Stribeck dip.
    """
    from ..models.base import kernel_family, law_to_dict
    from ..models.files import _flatten

    try:
        if kernel_family(law) == "static":
            return None
    except Exception:  # noqa: BLE001 - a law the kernels do not know
        return None
    flat = _flatten(law_to_dict(law))
    levels, stiff, vs = [], [], []
    for key, val in flat.items():
        leaf = key.split(".")[-1]
        vals = [float(v) for v in (val if isinstance(val, list) else [val]) if isinstance(v, (int, float))]
        if leaf in ("Fc", "Fs"):
            levels += [abs(v) for v in vals]
        elif leaf in ("sigma0", "k"):
            stiff += [v for v in vals if v > 0]
        elif leaf == "vs":
            vs += [abs(v) for v in vals if v != 0]
    if not levels or not stiff or max(levels) <= 0:
        return None
    amp = 5.0 * max(levels) / min(stiff)
    vmax = 0.1 * min(vs) if vs else 1e-3 * amp
    period = 2 * np.pi * amp / vmax
    t = np.linspace(0.0, 2 * period, 4001)
    try:
        from ..simulation import simulate

        res = simulate(law, position=amp * np.sin(2 * np.pi * t / period), dt=float(t[1] - t[0]))
    except Exception:  # noqa: BLE001 - the loop is an extra; the parameters are the section
        return None
    if not res.success:
        return None
    return res.x, res.friction, amp


# --------------------------------------------------------------------------- reproductions
def _legend_right(ax) -> None:
    """The legend outside the axes, on the right: over no bar or line (bar charts' 'best' place
    still covered the tallest bar when it stood at the right)."""
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)


def zhu_fujimoto_findings(docs: Mapping[str, Mapping[str, Any]]) -> list[list[str]]:
    """The seed-001 findings table, one column per stage: ``{stage: reproduce zhu-fujimoto JSON}``.

    Each row is a claim of the paper and what this run gives; the demo and the report both
    use this table.
    """
    sm = dict(docs)
    paper = {"sinc": 4.24, "coulomb": 5.44, "sigmoid": 1.65}  # seed 001 Table 3 [µm]

    def ms(x):
        return "never" if x is None else f"{x:.1f} ms before"

    def order(d):
        e = {k: d["table3"][k]["max_error_um"] for k in paper}
        return " < ".join(sorted(e, key=e.get))

    rows = [["finding (paper)"] + [f"{st} stage" for st in sm]]
    if all("fig2" in d for d in sm.values()):
        rows.append(["Fig. 2 level vs the eq. 1 fit, 5–50 Hz"]
                    + ["{:+.2f} to {:+.2f} dB".format(*d["fig2"]["gain_offset_vs_eq1_db"]) for d in sm.values()])
    rows.append(["Fig. 5(b): motor input turns to braking before zero speed (§5 reversal)"]
                + [ms(d["fig5b"]["motor_input_reverses_before_zero_ms"]) for d in sm.values()])
    if all("fig5" in d for d in sm.values()):
        rows.append(["Fig. 5: sinc compensation, max error slow / fast deceleration [µm] (paper: fast much worse)"]
                    + [f"{d['fig5']['slow_reverse']['max_error_um']:.2f} / {d['fig5']['fast_reverse']['max_error_um']:.2f}"
                       for d in sm.values()])
    for law in ("sinc", "coulomb", "sigmoid"):
        rows.append([f"Table 3 {law} [µm] (paper {paper[law]:.2f})"]
                    + [f"{d['table3'][law]['max_error_um']:.2f}" for d in sm.values()])
    rows.append(["Table 3 order (paper: sigmoid < sinc < coulomb)"] + [order(d) for d in sm.values()])
    rows.append(["sigmoid without its pre-zero reduction (post-only) [µm] (paper: the reduction helps)"]
                + [f"{d['table3']['sigmoid_post_only']['max_error_um']:.2f}" for d in sm.values()])
    rows.append(["Fig. 10: l_d/R before zero speed, slow / fast (min–max; paper: fast drops)"]
                + ["{:.4f}–{:.4f} / {:.4f}–{:.4f}".format(
                    d["ld"]["slow_reverse"]["min_ratio_before_zero"], d["ld"]["slow_reverse"]["max_ratio_before_zero"],
                    d["ld"]["fast_reverse"]["min_ratio_before_zero"], d["ld"]["fast_reverse"]["max_ratio_before_zero"])
                   for d in sm.values()])
    rows.append(["Table 2 selector vs best fixed law, mixed run [µm]"]
                + [f"{d['selector']['mixed_max_error_um']:.2f} vs {d['selector']['best_fixed_max_error_um']:.2f}"
                   for d in sm.values()])
    if all("table2_fast_non_reverse" in d for d in sm.values()):
        rows.append(["Table 2 fast non-reverse: original vs redesigned stop [µm]"]
                    + ["{:.2f} vs {:.2f}".format(d["table2_fast_non_reverse"]["original"]["max_error_um"],
                                                 d["table2_fast_non_reverse"]["redesigned"]["max_error_um"])
                       for d in sm.values()])
    return rows


def _zf_claims(d: Mapping[str, Any]) -> list[list[str]]:
    """The paper's qualitative claims, each judged on this run's numbers."""
    t3 = {k: v["max_error_um"] for k, v in d["table3"].items()}
    rows = [["claim (seed 001)", "this run", "verdict"]]
    rows.append(["Table 3 order: sigmoid < sinc < Coulomb",
                 f"{t3['sigmoid']:.2f} / {t3['sinc']:.2f} / {t3['coulomb']:.2f} µm",
                 _holds(t3["sigmoid"] < t3["sinc"] < t3["coulomb"])])
    rows.append(["the sigmoid's pre-zero reduction helps (sigmoid < post-only)",
                 f"{t3['sigmoid']:.2f} vs {t3['sigmoid_post_only']:.2f} µm",
                 _holds(t3["sigmoid"] < t3["sigmoid_post_only"])])
    lead = d["fig5b"]["motor_input_reverses_before_zero_ms"]
    rows.append(["Fig. 5(b): the motor input brakes before zero speed", "never" if lead is None else f"{lead:.1f} ms",
                 _holds(lead is not None and lead > 0)])
    if "fig5" in d:
        s, f = d["fig5"]["slow_reverse"]["max_error_um"], d["fig5"]["fast_reverse"]["max_error_um"]
        rows.append(["Fig. 5: sinc worse after a fast deceleration", f"slow {s:.2f} / fast {f:.2f} µm", _holds(f > s)])
    ld = d["ld"]
    rows.append(["Fig. 10: l_d/R drops before zero speed in fast deceleration",
                 f"min {ld['fast_reverse']['min_ratio_before_zero']:.4f} (slow {ld['slow_reverse']['min_ratio_before_zero']:.4f})",
                 _holds(ld["fast_reverse"]["min_ratio_before_zero"] < ld["slow_reverse"]["min_ratio_before_zero"])])
    sel = d["selector"]
    rows.append(["Table 2: the selector beats every fixed law",
                 f"{sel['mixed_max_error_um']:.2f} vs {sel['best_fixed_max_error_um']:.2f} µm",
                 _holds(sel["mixed_max_error_um"] < sel["best_fixed_max_error_um"])])
    return rows


def zhu_fujimoto_sections(d: Mapping[str, Any]) -> list[Section]:
    """Findings with verdicts, the numbers beside the paper's, a Table 3 bar chart."""
    sec = Section(f"Reproduction: seed 001 ball-screw stage (stage {d.get('stage')}, nut {d.get('nut_model')}, "
                  f"seed {d.get('seed')}{', quick' if d.get('quick') else ''})")
    sec.text.append(str(d["paper"]) + ". Each claim judged on this run's numbers (verdict: strict comparison).")
    sec.table = _zf_claims(d)
    sec.tables.append(("Numbers beside the paper", zhu_fujimoto_findings({str(d.get("stage", "this")): d})))
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7, 3.4), layout="constrained")
    laws = [k for k in ("coulomb", "sinc", "sigmoid", "sigmoid_post_only") if k in d["table3"]]
    x = np.arange(len(laws))
    ax.bar(x - 0.2, [d["table3"][k]["max_error_um"] for k in laws], 0.4, label="simulated")
    pap = [d["table3"][k].get("paper_um") for k in laws]
    ax.bar(x + 0.2, [np.nan if v is None else v for v in pap], 0.4, label="paper")
    ax.set_xticks(x, laws)
    ax.set(ylabel="max error in the reverse motion [µm]", title="Table 3")
    _legend_right(ax)
    ax.grid(alpha=0.3, axis="y")
    sec.figures.append(("zhu_fujimoto_table3.png", figure_png(fig)))
    return [sec]


def sdss_sections(d: Mapping[str, Any]) -> list[Section]:
    """Per axis: truth, identified with interval, error, truth inside the interval; NRMSE; tracking."""
    sec = Section(f"Reproduction: seed 002 SDSS telescope axes (seed {d.get('seed')}{', quick' if d.get('quick') else ''})")
    sec.text.append(str(d["paper"]) + ". The simulated axes' true parameters are known: each identified one is "
                    "shown with its error and whether its 95 % interval holds the truth.")
    errs: dict[str, dict[str, float]] = {}
    for axis, a in d["axes"].items():
        rows = [["parameter", "truth", "identified", "95 % interval", "error %", "interval holds truth"]]
        for k, p in a["identified"].items():
            tv = a["truth"].get(k)
            lo, hi = p.get("ci95", [None, None])
            err = None if not tv else 100 * (p["value"] / tv - 1)
            if err is not None:
                errs.setdefault(axis, {})[k] = err
            inside = tv is not None and lo is not None and hi is not None and lo <= tv <= hi
            rows.append([k, fmt(tv, 5), fmt(p["value"], 5), f"[{fmt(lo, 5)}, {fmt(hi, 5)}]",
                         "–" if err is None else f"{err:+.2f}", _holds(inside) if tv is not None else "–"])
        # the rotator (static map only, no output-error fit) carries no status: its title printed "(status ?: )"
        state = f" (status {a['status']}: {a.get('message', '')})" if "status" in a else ""
        sec.tables.append((f"{axis}{state}", rows))
        nr = a.get("nrmse_by_figure_percent") or {}
        if nr:
            tr = a.get("nrmse_true_model_percent") or {}
            sec.text.append(f"{axis}: velocity NRMSE identified / true model on the same data: "
                            + ", ".join(f"{k} {fmt(v, 3)} / {fmt(tr.get(k), 3)} %" for k, v in nr.items()) + ".")
    trk = d.get("sidereal_tracking_rms_arcsec") or {}
    if trk:
        sec.text.append(f"Sidereal tracking RMS (ours): no compensation {fmt(trk.get('no_compensation'))} arcsec, "
                        f"LuGre feed-forward {fmt(trk.get('lugre_feedforward'))} arcsec.")
    if errs:
        plt = _plt()
        fig, axs = plt.subplots(1, len(errs), figsize=(3.6 * len(errs), 3.2), layout="constrained", squeeze=False)
        for ax, (axis, e) in zip(axs[0], errs.items()):
            ax.barh(list(e), list(e.values()), color="C0")
            ax.axvline(0, color="0.5", lw=0.8)
            ax.set(title=axis, xlabel="identified / truth − 1 [%]")
            ax.tick_params(labelsize=8)
            ax.grid(alpha=0.3, axis="x")
        sec.figures.append(("sdss_errors.png", figure_png(fig)))
    return [sec]


_ZH_TITLES = {"t7_diff0_wsim_better": "Table 7, different speeds, base 0: WSIM better than ACIM",
              "t7_diff6_wsim_better": "Table 7, different speeds, base 6 mm/s: WSIM better than ACIM",
              "t7_same0_acim_better": "Table 7, same speeds, base 0: ACIM better than WSIM",
              "t7_same6_acim_better": "Table 7, same speeds, base 6 mm/s: ACIM better than WSIM",
              "fig16_reciprocating_gms_better": "Fig. 16, reciprocating: GMS closer than LuGre",
              "fig16_unidirectional_lugre_better": "Fig. 16, unidirectional: LuGre closer than GMS",
              "fig16_reciprocating_m7_better": "GMS with 7 elements closer than with 3 (ref. [30])",
              "crawling_tdms_smoother": "crawling: TDMS ripple under half of CDFS's (ours)"}


def _zh_numbers(v: Mapping[str, Any]) -> str:
    parts = []
    for k, x in v.items():
        if k == "holds":
            continue
        if k == "rows":
            parts.append("; ".join(f"{r[0]:g} µm/s: {r[1]:.0f} vs {r[2]:.0f} %" for r in x))
        elif isinstance(x, list) and len(x) == 2:
            parts.append(f"{k} |mean| {fmt(x[0], 3)}, std {fmt(x[1], 3)} µm")
        elif isinstance(x, (int, float)):
            parts.append(f"{k} {fmt(x, 3)}")
    return "; ".join(parts)


#: Longest status message shown in a reproduction's section [characters]; the rest is in its JSON. WSIM's
#: identifiability flags run to ~3,000 characters on the quick run; 400 keeps the section readable.
MESSAGE_CHARS = 400


def _clip(message: str, limit: int = MESSAGE_CHARS) -> str:
    """``message`` up to ``limit`` characters, cut after a whole ``;``-separated item (was cut mid-word:
    '... delta not identifiable:'), saying how much is left out and where it is."""
    if len(message) <= limit:
        return message
    cut = message.rfind("; ", 0, limit)
    cut = cut if cut > 0 else limit
    return f"{message[:cut]}; … ({len(message) - cut} more characters: the JSON's \"message\")"


def zhang2023_sections(d: Mapping[str, Any]) -> list[Section]:
    """Findings (holds / does not hold), Tables 7 and 8 worktable rows beside the paper, a figure."""
    sec = Section(f"Reproduction: seed 000 TDMS, WSIM vs ACIM, GMS vs LuGre (seed {d.get('seed')}"
                  f"{', quick' if d.get('quick') else ''})")
    sec.text.append(str(d["paper"]) + f". Status {d.get('status', '?')}: {_clip(str(d.get('message', '')))}")
    findings = d.get("findings")
    if findings is None:
        from ..reproduce.zhang2023 import findings as compute

        findings = compute(dict(d))
    rows = [["finding", "numbers (worktable, µm; Fig. 16 RMS N)", "verdict"]]
    for k, v in findings.items():
        title = _ZH_TITLES.get(k) or (f"Table 8, {k.split('_')[1]}: GMS no worse than LuGre" if k.startswith("t8_")
                                      else k)
        rows.append([title, _zh_numbers(v), _holds(v.get("holds"))])
    sec.table = rows
    for key, col in (("table7", "method"), ("table8", "model")):
        tab = [["speeds", "base [mm/s]", col, "mean (std) simulated [µm]", "mean (std) paper [µm]"]]
        for r in d[key]:
            if r.get("structure") == "worktable":
                tab.append([r["speeds"], str(r["base_speed_mm_s"]), r[col],
                            f"{r['mean_um']:+.4f} ({r['std_um']:.4f})", f"{fmt(r['paper_mean_um'])} ({fmt(r['paper_std_um'])})"])
        sec.tables.append((f"{'Table 7: ACIM vs WSIM' if key == 'table7' else 'Table 8: LuGre vs GMS'}, worktable "
                           "tracking error", tab))
    plt = _plt()
    fig, axs = plt.subplots(1, 2, figsize=(11, 3.6), layout="constrained")
    for ax, (key, col) in zip(axs, (("table7", "method"), ("table8", "model"))):
        rows_ = [r for r in d[key] if r.get("structure") == "worktable"]
        labels = [f"{r['speeds'][:4]} {r['base_speed_mm_s']}\n{r[col]}" for r in rows_]
        x = np.arange(len(rows_))
        ax.bar(x - 0.2, [r["std_um"] for r in rows_], 0.4, label="simulated std")
        ax.bar(x + 0.2, [r["paper_std_um"] for r in rows_], 0.4, label="paper std")
        ax.set_yscale("log")
        ax.set_xticks(x, labels, fontsize=7)
        ax.set(ylabel="worktable error std [µm]", title=f"{key[:5].title()} {key[5:]}: {col}")
    _legend_right(axs[-1])  # one legend for both panels, beside them
    sec.figures.append(("zhang2023_tables.png", figure_png(fig)))
    sec.text.append("The simulated errors are nm where the paper's are µm (the assumed 40 Hz loops; nothing tuned "
                    "toward µm): compare the orderings, not the levels.")
    return [sec]


def robustness_sections(d: Mapping[str, Any]) -> list[Section]:
    """The fraction of variants in which each finding holds, and the sensitivity ranking."""
    sec = Section(f"Robustness sweep ({d.get('computed', '?')} variant(s) run, {d.get('skipped', 0)} done before)")
    sec.table = [["finding", "holds in (fraction of variants)"]] + [[k, fmt(v, 3)] for k, v in d["holds_fraction"].items()]
    if d.get("ranking"):
        sec.text.append("Sensitivity ranking (most sensitive first): " + ", ".join(map(str, d["ranking"])) + ".")
    if d.get("failed"):
        sec.text.append("Failed variants: " + ", ".join(map(str, d["failed"])) + ".")
    return [sec]


# --------------------------------------------------------------------------- compensation
#: How a tracking error in SI is shown: unit -> (label, factor).
_SHOWN = {"m": ("µm", 1e6), "rad": ("arcsec", 648000.0 / math.pi)}


def compensation_sections(d: Mapping[str, Any]) -> list[Section]:
    """The error table (µm for a linear axis, arcsec for a rotary one) and a bar chart."""
    comp = d["compensators"]
    if not isinstance(comp, Mapping) or not comp or not all(isinstance(r, Mapping) for r in comp.values()):
        # a hand-edited list read "malformed content (AttributeError ...)", an empty object an empty table
        raise DataError(f"\"compensators\" = {str(comp)[:80]}: expected an object {{name: {{max_error, rms_error, "
                        "...}} with at least one compensator")
    units = d.get("units") or {}
    unit = units.get("error", "m") if isinstance(units, Mapping) else None
    if unit not in _SHOWN:  # 'x' labelled SI metres as x; a hand edit is named instead (round 6)
        raise DataError(f"\"units\" = {json.dumps(d.get('units'), default=str)[:80]}: expected {{\"error\": \"m\"}} "
                        "or {\"error\": \"rad\"}")
    label, k = _SHOWN[unit]
    for name, r in comp.items():  # "max_error": "1" was shown as 1e6 µm, true as 1 m, -1 as a negative error
        for key in ("max_error", "rms_error", "reversal_error"):
            x = r.get(key)
            if x is not None and (isinstance(x, bool) or not isinstance(x, (int, float)) or not x >= 0
                                  or not math.isfinite(x)):
                raise DataError(f"compensator {name!r}: {key} = {json.dumps(x, default=str)[:40]}: expected a "
                                "finite error >= 0 [m or rad] or null")
        if not isinstance(r.get("ok", False), bool):
            raise DataError(f"compensator {name!r}: ok = {json.dumps(r.get('ok'), default=str)[:40]}: expected "
                            "true or false")

    def shown(x: Any) -> str:
        return "–" if x is None else fmt(k * float(x))

    from ..compensate import PRESETS

    preset = d["preset"]
    if not isinstance(preset, str) or not preset.strip():
        raise DataError(f"\"preset\" = {json.dumps(preset, default=str)[:80]}: expected a preset name ({', '.join(PRESETS)}) or the "
                        "machine file compensate ran")
    # a machine file's path was titled "the /path/emps.json preset" (round 6)
    what = f"the {preset} preset" if preset in PRESETS else f"the machine file '{preset}'"
    short = preset if preset in PRESETS else Path(preset).stem
    sec = Section(f"Compensation on {what} ({fmt(d.get('duration_s'))} s, "
                  f"{len(d.get('reversals_s') or [])} reversal(s){', quick' if d.get('quick') else ''})")
    w = d.get("reversal_window_s") or [None, None]
    sec.text.append(f"Error of the true position r − x: max and RMS once the loop has settled, and the max "
                    f"within {fmt(w[0])} … +{fmt(w[1])} s of each reversal of the reference."
                    + (f" Model: {d['model']}." if d.get("model") else "")
                    + f" Status {d.get('status', 0)}: {d.get('message', '')}.")
    rows = [["compensator", f"max [{label}]", f"RMS [{label}]", f"at reversals [{label}]", "status"]]
    for name, r in comp.items():
        rows.append([name, shown(r.get("max_error")), shown(r.get("rms_error")), shown(r.get("reversal_error")),
                     "ok" if r.get("ok") else "failed"])
        if not r.get("ok"):
            sec.text.append(f"Compensator {name} failed: {r.get('message', '')}")
    sec.table = rows
    sec.text.append("The --json of compensate keeps the error numbers, not the traces: for the error over time "
                    "use 'frictionkit compensate ... --plot'.")
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7, 3.4), layout="constrained")
    names = list(comp)
    x = np.arange(len(names))
    for off, key, what in ((-0.2, "max_error", "max"), (0.2, "reversal_error", "at reversals")):
        ax.bar(x + off, [np.nan if comp[n].get(key) is None else k * comp[n][key] for n in names], 0.4, label=what)
    ax.set_xticks(x, names)
    ax.set(ylabel=f"tracking error [{label}]", title=f"{short}: friction compensators")
    ax.grid(alpha=0.3, axis="y")
    _legend_right(ax)
    sec.figures.append((f"compensate_{short}.png", figure_png(fig)))
    return [sec]


# --------------------------------------------------------------------------- studies
def _compensators(df) -> list[str]:
    """The study's compensators, best first (:func:`frictionkit.study.rank_compensators`)."""
    from ..study import rank_compensators

    return rank_compensators(df)


def study_table(df) -> list[list[str]]:
    """Per compensator: runs, failed, max tracking error median / p95 / worst, RMS median [µm]."""
    rows = [["compensator", "runs", "failed", "max error median [µm]", "max error 95th pct [µm]",
             "max error worst [µm]", "RMS error median [µm]", "peak force median [N]"]]
    for comp in _compensators(df):
        g = df[df["compensator"].astype(str) == comp]
        ok = g[g["ok"].astype(bool)]
        q = ok["max_error"]
        rows.append([str(comp), str(len(g)), str(int((~g["ok"].astype(bool)).sum())),
                     _um(q.median() if len(ok) else None), _um(q.quantile(0.95) if len(ok) else None),
                     _um(q.max() if len(ok) else None), _um(ok["rms_error"].median() if len(ok) else None),
                     fmt(ok["max_force"].median() if len(ok) and "max_force" in ok else None)])
    return rows


def study_figure(df) -> bytes:
    """Box plot with the runs as points (jittered), per compensator: max and RMS tracking error [µm]."""
    plt = _plt()
    comps = _compensators(df)
    ok = df[df["ok"].astype(bool)]
    fig, axs = plt.subplots(1, 2, figsize=(10, 3.8), layout="constrained")
    rng = np.random.default_rng(0)  # jitter only
    for ax, col, label in zip(axs, ("max_error", "rms_error"), ("max", "RMS")):
        data = [1e6 * ok.loc[ok["compensator"].astype(str) == c, col].to_numpy(float) for c in comps]
        ax.boxplot(data, showfliers=False, widths=0.5)
        ax.set_xticks(np.arange(1, len(comps) + 1), comps)
        for i, y in enumerate(data, 1):
            ax.plot(i + rng.uniform(-0.12, 0.12, y.size), y, "o", ms=3, alpha=0.6, color=f"C{i - 1}")
        ax.set(ylabel=f"{label} tracking error [µm]", title=f"{label} error per run")
        ax.grid(alpha=0.3, axis="y")
    return figure_png(fig)


#: Study columns that are results or bookkeeping, not drawn parameters.
_NOT_DRAWN = {"draw", "noise_seed", "max_error", "rms_error", "max_error_measured", "max_force", "reversal_error",
              "run_seconds", "task_seconds", "ok"}  # reversal_error (ball-screw studies) was listed as drawn


def study_sections(df) -> list[Section]:
    """A study's runs as per-compensator statistics (table, box/strip plot), spreads, failures."""
    n = len(df)
    sec = Section(f"Monte-Carlo study: {n} run(s), {df['compensator'].nunique()} compensator(s)")
    draws = df["draw"].nunique() if "draw" in df else "?"
    seeds = df["noise_seed"].nunique() if "noise_seed" in df else "?"
    sha = df["study_sha256"].dropna().astype(str)
    sec.text.append(f"{draws} parameter draw(s) × {df['compensator'].nunique()} compensator(s) × {seeds} noise seed(s)"
                    + (f"; study {sha.iloc[0][:12]}" if len(sha) else "")
                    + (f"; frictionkit {', '.join(sorted(df['frictionkit_version'].dropna().astype(str).unique()))}"
                       if "frictionkit_version" in df else "") + ". Errors of the true position, after the first 10 % "
                    "of each run. Compensators best first, by the median of the runs' max tracking error.")
    sec.table = study_table(df)
    from pandas.api.types import is_bool_dtype, is_numeric_dtype

    spread = [["parameter", "min", "max", "half range / median"]]
    for c in df.columns:  # the drawn plant parameters: numeric columns other than results and bookkeeping
        if c in _NOT_DRAWN or not is_numeric_dtype(df[c]) or is_bool_dtype(df[c]):
            continue
        if df[c].notna().any():
            lo, hi, med = float(df[c].min()), float(df[c].max()), float(df[c].median())
            rel = f"±{100 * (hi - lo) / 2 / abs(med):.0f} %" if med and hi > lo else "fixed"
            spread.append([str(c), fmt(lo), fmt(hi), rel])
    if len(spread) > 1:
        sec.tables.append(("Drawn plant parameters (SI)", spread))
    bad = df[~df["ok"].astype(bool)]
    if len(bad):
        sec.tables.append((f"Failed runs ({len(bad)})", [["run", "error"]] + [[str(r.get("run", "")), str(r["error"])]
                                                                           for _, r in bad.head(20).iterrows()]))
    if df["ok"].astype(bool).any():
        sec.figures.append(("study_errors.png", study_figure(df)))
    return [sec]


def study_summary_sections(d: Mapping[str, Any]) -> list[Section]:
    """The --json of ``frictionkit study``: the per-compensator summary (no runs: no plot)."""
    sec = Section(f"Monte-Carlo study summary ({d.get('runs', '?')} runs)")
    sec.table = [["compensator", "runs", "failed", "max error median [µm]", "max error 95th pct [µm]",
                  "RMS error median [µm]"]]
    from ..study import rank_summaries

    sec.text.append("Compensators best first, by the median of the runs' max tracking error.")
    for comp in rank_summaries(d["compensators"]):
        s = d["compensators"][comp]
        sec.table.append([comp, str(s.get("runs")), str(s.get("failed")), _um(s.get("max_error_median_m")),
                          _um(s.get("max_error_p95_m")), _um(s.get("rms_error_median_m"))])
    if d.get("out"):
        sec.text.append(f"Runs in {d['out']}: give that Parquet file for the distribution plot.")
    return [sec]


# --------------------------------------------------------------------------- fleets
def fleet_sections(df) -> list[Section]:
    """The fleet in numbers and parameter distributions; then, when there are any, a section of the
    flagged axes (drawn over time) and one of the failed files."""
    from ..fleet.drift import drift_summary
    from ..fleet.report import HISTORY, axes_word
    from ..plotting.fleet import plot_axis_histories, plot_parameter_distribution

    plt = _plt()
    ok = df["ok"].astype(bool)
    periods = sorted(df["period"].astype(str).unique())
    sec = Section(f"Fleet: {df['axis'].nunique()} axes, {len(df)} axis-periods")
    rows = [["item", "value"], ["axes", str(df["axis"].nunique())], ["axis-periods", str(len(df))],
            ["periods", f"{periods[0]} … {periods[-1]}" if periods else ""],
            ["identified", str(int(ok.sum()))], ["failed", str(int((~ok).sum()))]]
    monitored = "drift_flag" in df
    if monitored:
        axes = drift_summary(df)
        flagged = axes[axes["drift_flag"].astype(bool)]
        rows.append(["drift flagged", f"{len(flagged)} {axes_word(len(flagged))}"])
    else:
        flagged = None
        sec.text.append("Not monitored for drift (no drift_flag column): run 'frictionkit fleet monitor' first.")
    sec.table = rows
    params = [p for p in HISTORY if p in df and df[p].notna().any()]
    if params:
        fig, axs = plt.subplots(1, len(params), figsize=(3.4 * len(params), 3.0), layout="constrained", squeeze=False)
        for p, ax in zip(params, axs[0]):
            plot_parameter_distribution(df, p, ax=ax)
        sec.figures.append(("fleet_distribution.png", figure_png(fig, dpi=100)))
    # the fleet page's order (fleet.report): numbers and distributions, then the flagged axes
    # with their histories, then the failed files. A section shows its tables before its figures,
    # so in one section the histories came after the failed files' table, far from their axes.
    out = [sec]
    if flagged is not None and len(flagged):
        flagged = flagged.sort_values("drift_alarm_period", kind="stable")
        fl = Section(f"Fleet: flagged axes ({len(flagged)})")
        fl.tables.append((f"Flagged axes ({len(flagged)})", [["axis", "alarm", "why"]] + [
            [str(r["axis"]), str(r.get("drift_alarm_period", "")), str(r.get("drift_detail", ""))]
            for _, r in flagged.iterrows()]))
        for axis in flagged["axis"].head(5):
            fig = plot_axis_histories(df, axis, params)
            fl.figures.append((f"fleet_{axis}.png", figure_png(fig, dpi=100)))
        out.append(fl)
    bad = df[~ok]
    if len(bad):
        cols = [c for c in ("axis", "period", "file", "error") if c in df]
        out.append(Section(f"Fleet: files that failed ({len(bad)})", tables=[(
            f"Files that failed ({len(bad)})", [cols] + [[str(r[c]) for c in cols] for _, r in bad.head(50).iterrows()])]))
    return out


# --------------------------------------------------------------------------- simulated traces
def traces_sections(df) -> list[Section]:
    """Time histories (x, v, friction) and the hysteresis loop F(x) of ``simulate --out`` traces
    (older files name the friction column ``F [N]``: read too)."""
    plt = _plt()
    cols = list(map(str, df.columns))

    def col(prefix: str) -> str | None:
        return next((c for c in cols if c.startswith(prefix + " [")), None)

    t, x, v, F = col("t"), col("x"), col("v"), col("friction") or col("F")
    tt = df[t].to_numpy(float)
    sec = Section(f"Simulated traces: {len(df)} samples over {fmt(tt[-1] - tt[0] if tt.size else 0)} s")
    over = [["column", "min", "max"]] + [[c, fmt(df[c].min()), fmt(df[c].max())]
                                         for c in cols if not c.startswith("stick_")]
    sec.table = over
    n = 2 if x is not None else 1
    fig, axs = plt.subplots(1, n + 1, figsize=(5 * (n + 1), 3.5), layout="constrained")
    axs[0].plot(tt, df[F].to_numpy(float), lw=0.9)
    axs[0].set(xlabel=t, ylabel=F, title="friction force over time")
    if v is not None:
        axs[1].plot(tt, df[v].to_numpy(float), lw=0.9, color="C2")
        axs[1].set(xlabel=t, ylabel=v, title="velocity over time")
    if x is not None:
        xs, xl = df[x].to_numpy(float), x
        if x == "x [m]":  # µm up to 2 mm, else mm: '-0.00100' ... '0.00100' in m ran together
            from ..plotting.simulation import length_display

            scale, unit = length_display(xs)
            xs, xl = xs * scale, f"x [{unit}]"
        axs[-1].plot(xs, df[F].to_numpy(float), lw=0.9, color="C1")
        axs[-1].set(xlabel=xl, ylabel=F, title="hysteresis loop F(x)")
    for a in axs:
        a.grid(alpha=0.3)
        a.locator_params(axis="x", nbins=6)
    sec.figures.append(("traces.png", figure_png(fig)))
    return [sec]


def machine_traces_sections(df) -> list[Section]:
    """A machine's ``simulate --out`` traces: the column ranges and positions, velocities and site forces
    over time, one panel per quantity and unit (as ``MachineResult.plot``). Was: refused as "a table of no
    kind", while the refusal of a machine model file told the user to report exactly these traces."""
    from ..plotting.simulation import plot_panels, trace_groups

    plt = _plt()
    cols = list(map(str, df.columns))
    tt = df["t [s]"].to_numpy(float)
    groups = trace_groups(cols)
    sec = Section(f"Simulated machine traces: {len(df)} samples over {fmt(tt[-1] - tt[0] if tt.size else 0)} s, "
                  f"{sum(len(g[2]) for g in groups if g[0] == 'position')} degree(s) of freedom")
    sec.table = [["column", "min", "max"]] + [[c, fmt(df[c].min()), fmt(df[c].max())] for c in cols]
    axes = plot_panels(tt, [(q, u, [(lab, df[c].to_numpy(float)) for lab, c in lines]) for q, u, lines in groups],
                       title="positions, velocities and site forces")
    sec.figures.append(("machine_traces.png", figure_png(axes[0].figure)))
    return [sec]


def machine_run_sections(res) -> list[Section]:
    """A :class:`~frictionkit.machines.MachineResult` in memory (``Report.add_result``; was refused as "not a
    result the report knows"): its summary, the range of every trace column and ``res.plot()`` — positions,
    velocities, site forces and the actuators' commanded and applied forces, one panel per quantity and unit."""
    from ..simulation.traces import machine_trace_table

    plt = _plt()
    lines = res.summary().splitlines()
    sec = Section(f"Machine run: {res.machine.name}, {res.t.size} samples over {fmt(res.t[-1] - res.t[0])} s, "
                  f"status {res.status}")
    # the summary without its debug line (which kernel ran): the run, then each DOF's and site's extremes
    sec.text.extend(" ".join(ln.split()) for ln in lines if not ln.strip().startswith("kernel:"))
    sec.table = [["column", "min", "max"]] + [[c, fmt(np.nanmin(y)), fmt(np.nanmax(y))]
                                              for c, y in machine_trace_table(res).items() if np.size(y)]
    try:
        axes = res.plot()
        sec.figures.append(("machine_run.png", figure_png(axes[0].figure)))
    except Exception as exc:  # noqa: BLE001 - a plot must not hide the numbers
        plt.close("all")
        sec.text.append(f"(plot failed: {type(exc).__name__}: {' '.join(str(exc).split())})")
    return [sec]


#: Builders by kind, for code that has the parsed document (the demo).
BUILDERS: dict[str, Callable[..., list[Section]]] = {
    "reproduce-zhu-fujimoto": zhu_fujimoto_sections, "reproduce-sdss": sdss_sections,
    "reproduce-zhang2023": zhang2023_sections, "robustness": robustness_sections,
    "compensation": compensation_sections, "study": study_sections, "study-summary": study_summary_sections,
    "fleet": fleet_sections, "traces": traces_sections, "machine-traces": machine_traces_sections,
}

