"""Issue 13's command-line and library campaign, round 10 (helper r10): 961 cases of bad input and faults.

Families: A numeric option values on every verb (-1, 0, nan, inf, 1e308, 1e-320, '', 'abc', '1_000' ...);
B model-file JSON mutations (wrong types, NaN/inf/huge numbers, unicode, deep nesting, BOM, UTF-16,
truncation) through ``export`` and ``simulate``; C machine-file mutations (every part's fields, parts given
twice); D data files (BOM, UTF-16, separators, duplicate/empty headers, NUL bytes, huge cells, wrong
extensions, Parquet with text columns); E output paths (folders, trailing '/', missing folders, devices,
links, the input itself, names with spaces/newlines); F study TOML mutations; G odd options of every verb
(export, compensate, report, fleet, reproduce, demo, simulate machine files, identify); J identification
results mutated into report/export/simulate/--static-json; H library calls with bad arguments; I SIGINT at
start-up and mid-run (subprocesses).

Each case is run in this process (typer's CliRunner, an alarm after ``TIMEOUT`` s) and classed: ok / own-error
(one ``error:`` line naming the cause) / misleading? (the error names none of the case's cause words: read
it) / traceback / hang / silent-accepted (a library call that should fail returned) / file-fault (an input
changed, an output left after a failure). The classes are a first sort: read every row that is not
own-error or ok.

Round 11 (helper r11, :func:`cases11`): K unicode / very long / odd paths; L symbolic-link loops, FIFOs,
devices and files changing while read, as every kind of input (data, model, result, study, fleet config,
compensation test, --static-json) and output; N NaN / inf / 1e200 in every number of every law kind's file and
of a machine file; O huge but legal arrays; P empty and half-finished folders for the fleet verbs; Q locales
and encodings (LC_ALL=C, PYTHONIOENCODING=ascii, a decimal-comma CSV); R concurrent fleet writers; I11 Ctrl-C in
fleet simulate, then the same command; S --help / -h / no arguments of every verb; T every public Python entry
point with a wrong type in each argument. Subprocess cases (kind "sub") run the console script with their own
environment and a 4 GB address-space limit.

Usage::

    python benchmarks/robustness_campaign.py [OUT.json] [--only PREFIX] [--rounds 10,11]   # R10_W=DIR: work folder

Measured 2026-11-24 (helper r10), 961 cases, bdfa191 vs round 10's end: see the report of issue 13 round
10; the rows that changed are the fixed patterns (tests/robustness/test_campaign_round10.py).
Round 11 measured 2026-11-24 (helper r11), 1,228 cases, f22475c vs round 11's end (load 8-12: subprocess
cases took 7-15 s wall, so a "hang" at the 30 s limit of that run was rechecked singly): see the report of
issue 13 round 11; fixed patterns in tests/robustness/test_campaign_round11.py.
"""
from __future__ import annotations

import hashlib
import json
import os
import random
import shutil
import signal
import subprocess
import sys
import time
import traceback
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "robustness"))
from _robustness_helpers import DT, LAW, write_csv  # noqa: E402
from typer.testing import CliRunner  # noqa: E402

import frictionkit as fk  # noqa: E402
from frictionkit.cli import _register, app  # noqa: E402
from frictionkit.errors import FrictionKitError  # noqa: E402

_register()
W = Path(os.environ.get("R10_W", "/tmp/fk_campaign"))
FK = str(Path(sys.executable).with_name("frictionkit"))
TIMEOUT = 90


class Hang(BaseException):  # not an Exception: the CLI's error path must not catch it (round 11)
    pass


def _alarm(sig, frm):
    raise Hang()


signal.signal(signal.SIGALRM, _alarm)


def sha(p: Path):
    try:
        return hashlib.sha256(p.read_bytes()).hexdigest() if p.is_file() else None
    except OSError:
        return None


# ------------------------------------------------------------------ fixtures
def setup():
    if W.exists():
        os.system(f"chmod -R u+w {W}")
        shutil.rmtree(W)
    W.mkdir()
    rng = np.random.default_rng(0)
    speeds = np.geomspace(1e-3, 5e-2, 8)
    v = np.concatenate([np.full(150, s) for s in np.r_[speeds, -speeds]])
    F = LAW.steady_state(v) + 1e-3 * rng.standard_normal(v.size)
    t = np.arange(v.size) * DT
    write_csv(W / "stairs.csv", t_s=t, v_ms=v, F_N=F)
    x = np.r_[np.linspace(0, 50e-6, 501), np.linspace(50e-6, -50e-6, 1001)[1:]]
    tg = np.arange(x.size) * DT
    Fg = fk.simulate(fk.GMS(LAW, k=[4e5, 1e5, 2e4], xi=[0.2, 0.3, 0.5], C=20.0), position=x, dt=DT).friction
    write_csv(W / "gms.csv", t_s=tg, x_m=x, F_N=Fg)
    tm = np.arange(2001) * 1e-3
    write_csv(W / "motion.csv", t=tm, x=20e-6 * np.sin(2 * np.pi * 2 * tm))
    write_csv(W / "force.csv", t=tm, u=2.0 * np.sin(2 * np.pi * 2 * tm))
    write_csv(W / "ref.csv", t=tm[:501], qg=0.01 * np.sin(2 * np.pi * 1 * tm[:501]))
    from frictionkit.identify import fit_static_map
    vv = np.r_[np.geomspace(1e-4, 0.2, 12), -np.geomspace(1e-4, 0.2, 12)]
    fit_static_map(vv, LAW.steady_state(vv)).save_json(W / "static.json")
    fk.save_model(fk.LuGre(LAW, sigma0=1e5, sigma1=30.0), W / "lugre.json")
    fk.save_model(fk.GMS(LAW, k=[1e4, 1e5], xi=[0.5, 0.5], C=20.0), W / "gms_model.json")
    from frictionkit.presets.emps import PUBLISHED, emps_machine
    m = emps_machine(M=PUBLISHED["M"], friction=fk.CoulombViscous(Fc=PUBLISHED["Fc"], sigma2=PUBLISHED["Fv"]),
                     offset=PUBLISHED["offset"])
    fk.save_model(m, W / "emps.json")
    (W / "ro").mkdir()
    (W / "adir").mkdir()
    (W / "old.json").write_text('{"old": true}')
    st = (Path(__file__).resolve().parents[1] / "examples" / "study" / "ballscrew.toml").read_text()
    (W / "study.toml").write_text(st.replace("draws = 20", "draws = 2").replace("seeds = 2", "seeds = 1")
                                  .replace("duration = 2.15", "duration = 0.6"))


# ------------------------------------------------------------------ runner
RESULTS = []


def classify(case, code, err, exc=None, hung=False, elapsed=0.0):
    cls = None
    msg = ""
    if hung:
        cls = "hang"
    elif exc is not None:
        cls = "traceback"
        msg = f"{type(exc).__name__}: {exc}"[:300]
    else:
        lines = [ln for ln in err.strip().splitlines() if ln.strip()]
        errs = [ln for ln in lines if ln.startswith("error: ")]
        msg = errs[-1] if errs else (lines[-1] if lines else "")
        if ("Traceback" in err and "--debug" not in case.get("argv", [])) or "this is a bug" in err:
            cls = "traceback"
        elif code == 0:
            cls = "silent-accepted" if case.get("expect") == "error" else "ok"
        elif case.get("expect") == "ok":
            cls = "unexpected-error"
        elif not errs:
            cls = "no-error-line"
        else:
            keys = case.get("cause")
            if keys and not any(k.lower() in msg.lower() for k in keys):
                cls = "misleading?"
            else:
                cls = "own-error"
    return cls, msg


def check_files(case, before):
    bad = []
    for p, h in before.items():
        if sha(Path(p)) != h:
            bad.append(f"changed {p}")
    for p in case.get("outputs_absent", []):
        if Path(p).exists() and case.get("_code", 0) != 0:
            bad.append(f"left {p}")
    return bad


def run_cli(case):
    argv = case["argv"]
    watch = [W / n for n in ("stairs.csv", "gms.csv", "motion.csv", "force.csv", "ref.csv", "static.json",
                             "lugre.json", "emps.json", "old.json", "gms_model.json", "study.toml")]
    watch += [Path(p) for p in case.get("inputs", [])]
    if case["expect"] != "error":  # a result the user asked for may replace an old one
        watch = [p for p in watch if p.name != "old.json"]
    watch = [p for p in watch if p not in case.get("unwatch", [])]
    before = {str(p): sha(p) for p in watch if p.exists()}
    runner = CliRunner()
    t0 = time.perf_counter()
    signal.alarm(case.get("timeout", TIMEOUT))
    hung = False
    code, err, exc = None, "", None
    try:
        res = runner.invoke(app, [str(a) for a in argv], catch_exceptions=True)
        code = res.exit_code
        try:
            err = res.stderr
        except ValueError:
            err = res.output
        if res.exception is not None and not isinstance(res.exception, SystemExit):
            exc = res.exception
    except Hang:
        hung = True
    finally:
        signal.alarm(0)
    case["_code"] = code
    cls, msg = classify(case, code, err, exc, hung)
    files = check_files(case, before)
    if files:
        cls = "file-fault"
        msg += " | " + "; ".join(files)
    return cls, msg, code, time.perf_counter() - t0


def run_lib(case):
    t0 = time.perf_counter()
    signal.alarm(case.get("timeout", TIMEOUT))
    code, err, exc, hung = 0, "", None, False
    try:
        out = case["call"]()
        if case.get("check") is not None:
            bad = case["check"](out)
            if bad:
                code, err = 0, ""
                case["expect"] = "error"
    except Hang:
        hung = True
    except FrictionKitError as e:
        code, err = 2, f"error: {type(e).__name__}: {e}"
    except Exception as e:  # noqa: BLE001
        exc = e
    finally:
        signal.alarm(0)
    cls, msg = classify(case, code, err, exc, hung)
    return cls, msg, code, time.perf_counter() - t0


def run_sig(case):
    t0 = time.perf_counter()
    p = subprocess.Popen([FK] + [str(a) for a in case["argv"]], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True, cwd=W, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    time.sleep(case["after"])
    p.send_signal(signal.SIGINT)
    try:
        out, err = p.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        p.kill()
        return "hang", "no exit 60 s after SIGINT", None, time.perf_counter() - t0
    code = p.returncode
    lines = [ln for ln in err.strip().splitlines() if ln.strip()]
    if "Traceback" in err:
        cls = "traceback"
    elif code == 0:
        cls = "ok (finished before SIGINT)"
    elif code == 130 and lines and lines[-1].startswith("error: interrupted"):  # + what is left (round 11)
        cls = "own-error"
    else:
        cls = "misleading?"
    bad = [o for o in case.get("outputs_absent", []) if Path(o).exists()]
    leftovers = [str(q) for q in W.glob(".*tmp*")] + [str(q) for q in W.glob("*.tmp")]
    if bad or leftovers:
        cls = "file-fault"
    return cls, (lines[-1] if lines else "") + (f" | left {bad + leftovers}" if bad or leftovers else ""), code, \
        time.perf_counter() - t0


# ------------------------------------------------------------------ case families
def cases():
    C = []
    S = str(W / "stairs.csv")
    G = str(W / "gms.csv")
    static = ["identify", "static", S, "--time", "t_s", "--velocity", "v_ms", "--force", "F_N", "--model",
              "coulomb_viscous"]
    presl = ["identify", "presliding", G, "--time", "t_s", "--position", "x_m", "--force", "F_N", "--Fc", "1"]
    lug = str(W / "lugre.json")
    emps = str(W / "emps.json")
    mach = ["simulate", emps, "--input", "qg=" + str(W / "ref.csv") + ":qg"]

    def add(id_, argv, expect="error", cause=None, **kw):
        C.append({"id": id_, "kind": "cli", "argv": argv, "expect": expect, "cause": cause, **kw})

    # ---- A: numeric option values on every verb ---------------------------------------------
    bad_nums = ["-1", "0", "nan", "inf", "-inf", "1e308", "1e-320", "", "abc", "1e400", "0x10", "1_000", " 1"]
    num_opts = [
        (static, "--force-scale"), (static, "--velocity-scale"), (static, "--trim"), (static, "--min-speed"),
        (static[:-2] + ["--model", "exponential"], "--delta"),
        (presl + ["--elements", "2"], "--C"), (presl[:-2] + ["--elements", "2"], "--Fc"),
        (presl + ["--elements", "2"], "--Fs"), (presl + ["--elements", "2"], "--vs"),
        (presl + ["--elements", "2"], "--min-rest"), (presl, "--elements"),
        (["simulate", lug, "--force", str(W / "force.csv")], "--mass"),
        (["simulate", lug, "--position", str(W / "motion.csv")], "--scale"),
        (["simulate", emps, "--input", "qg=0", "--duration", "0.05"], "--dt"),
        (["simulate", emps, "--input", "qg=0", "--dt", "1e-3"], "--duration"),
        (mach, "--substeps"), (mach, "--seed"),
        (["export", lug, "--format", "csv", "--out", str(W / "o_tab.csv")], "--v-max"),
        (["export", lug, "--format", "csv", "--out", str(W / "o_tab.csv")], "--points"),
        (["compensate", "ballscrew", "--quick", "--compensator", "none"], "--seed"),
        (["fleet", "simulate", "--axes", "1", "--days", "1", "--out", str(W / "fl")], "--drifting"),
        (["fleet", "simulate", "--axes", "1", "--out", str(W / "fl")], "--days"),
        (["fleet", "simulate", "--days", "1", "--out", str(W / "fl")], "--axes"),
        (["reproduce", "sdss", "--quick", "--json", str(W / "o_sdss.json")], "--seed"),
        (["study", str(W / "study.toml"), "--out", str(W / "o_st.parquet")], "--workers"),
        (["identify", "reversal", G, "--time", "t_s", "--position", "x_m", "--force", "F_N"], "--window"),
        (["identify", "reversal", G, "--time", "t_s", "--position", "x_m", "--force", "F_N"], "--min-travel"),
        (["identify", "rigid-body", G, "--time", "t_s", "--position", "x_m", "--force", "F_N"], "--cutoff"),
        (["identify", "rigid-body", G, "--time", "t_s", "--position", "x_m", "--force", "F_N"], "--decimate"),
        (["identify", "rigid-body", G, "--time", "t_s", "--position", "x_m", "--force", "F_N"], "--skip"),
    ]
    rnd = random.Random(10)
    for base, opt in num_opts:
        for val in rnd.sample(bad_nums, 6):
            add(f"A{opt}={val!r}:{base[0]}-{base[1][:6]}", base + [opt, val], expect="either", cause=[opt])
    # ---- B: model JSON mutations (export and simulate) ---------------------------------------
    good = json.loads((W / "lugre.json").read_text())

    def mutants():
        out = []
        for key_path, val in [
            (("model", "sigma0"), "1e5"), (("model", "sigma0"), None), (("model", "sigma0"), [1e5]),
            (("model", "sigma0"), {"v": 1}), (("model", "sigma0"), 1e308), (("model", "sigma0"), -0.0),
            (("model", "sigma1"), float("nan")), (("model", "sigma1"), float("inf")), (("model", "sigma1"), True),
            (("model", "static", "Fc"), 1e-320), (("model", "static", "Fc"), 1e300), (("model", "static", "vs"), 0),
            (("model", "static", "delta"), 1e3), (("model", "static", "delta"), -2),
            (("model", "static", "law"), "Stríbeck"), (("model", "static"), None), (("model", "static"), []),
            (("model", "law"), "LuGre\u0000"), (("model", "law"), 7), (("model",), "lugre"),
            (("format",), "frictionkit.model/2"), (("format",), None), (("kind",), "machine"), (("kind",), 3),
            (("model", "ünïcode"), 1), (("model", "static", "shape"), "exponential2"),
            (("model", "static", "sigma2"), -1e-9), (("provenance",), "x" * 100000),
        ]:
            d = json.loads(json.dumps(good))
            node = d
            ok = True
            for k in key_path[:-1]:
                if not isinstance(node, dict) or k not in node:
                    ok = False
                    break
                node = node[k]
            if not ok:
                continue
            node[key_path[-1]] = val
            out.append((f"{'.'.join(key_path)}={str(val)[:20]!r}", json.dumps(d, allow_nan=True)))
        raw = (W / "lugre.json").read_text()
        deep = "[" * 5000 + "]" * 5000
        out += [("truncated-half", raw[: len(raw) // 2]), ("empty", ""), ("bom", "\ufeff" + raw),
                ("deep", deep), ("deep-in-model", raw.replace('"model": {', '"model": {"x": ' + deep + ',', 1)),
                ("list-top", "[1, 2]"), ("number-top", "3"), ("null", "null"), ("nan-literal", raw.replace("30.0", "NaN")),
                ("huge-int", raw.replace("30.0", "1" + "0" * 5000)), ("trailing-garbage", raw + "}}"),
                ("comments", "// c\n" + raw), ("single-quotes", raw.replace('"', "'")),
                ("crlf", raw.replace("\n", "\r\n"))]
        return out

    for i, (name, text) in enumerate(mutants()):
        p = W / f"m_{i}.json"
        for enc in (("utf-8",) if name != "crlf" else ("utf-16",)):
            p.write_bytes(text.encode(enc, errors="surrogatepass"))
        add(f"B-export:{name}", ["export", p, "--format", "csv", "--out", W / f"o_m{i}.csv"], expect="either",
            cause=[str(p)], outputs_absent=[W / f"o_m{i}.csv"])
        add(f"B-sim:{name}", ["simulate", p, "--position", W / "motion.csv", "--json", W / f"o_ms{i}.json"],
            expect="either", cause=[str(p)], outputs_absent=[W / f"o_ms{i}.json"])
    # ---- C: machine JSON mutations -----------------------------------------------------------
    mgood = json.loads((W / "emps.json").read_text())
    mm = []

    def mset(path, val, label=None):
        d = json.loads(json.dumps(mgood))
        node = d
        for k in path[:-1]:
            node = node[k]
        if isinstance(node, list) and path[-1] == "append":
            node.append(val)
        else:
            node[path[-1]] = val
        mm.append((label or f"{'.'.join(map(str, path))}={str(val)[:25]!r}", json.dumps(d)))

    mod = mgood["model"]
    for k in list(mod)[:8]:
        for val in (None, 1e308, "x", [], {}, float("nan")):
            mset(("model", k), val)
    if "dofs" in mod and mod["dofs"]:
        for k in list(mod["dofs"][0]):
            for val in (-1.0, 0.0, 1e308, "1", None, float("inf")):
                mset(("model", "dofs", 0, k), val)
        mset(("model", "dofs", "append"), dict(mod["dofs"][0]), "dof twice")
    for part in ("sites", "actuators", "sensors", "blocks", "controllers"):
        if part in mod and isinstance(mod[part], list) and mod[part]:
            first = mod[part][0]
            for k in list(first)[:6]:
                for val in (None, "ü", 1e200, [[[[[]]]]], -5):
                    mset(("model", part, 0, k), val)
            mset(("model", part, "append"), dict(first), f"{part} twice")
    for i, (name, text) in enumerate(mm):
        p = W / f"mach_{i}.json"
        p.write_text(text)
        add(f"C-mach:{name}", ["simulate", p, "--input", "qg=0", "--dt", "1e-3", "--duration", "0.05", "--json",
                               W / f"o_c{i}.json"], expect="either", cause=[str(p), "machine"],
            outputs_absent=[W / f"o_c{i}.json"])
    # ---- D: data files ----------------------------------------------------------------------
    raw = (W / "stairs.csv").read_text()
    lines = raw.splitlines()
    variants = {
        "bom": "\ufeff" + raw, "utf16": None, "latin1-header": "t_s,v_ms,F_N,é\n" + "\n".join(l + ",1" for l in lines[1:]),
        "semicolon": raw.replace(",", ";"), "mixed-sep": "\n".join(l.replace(",", ";") if i % 2 else l
                                                                   for i, l in enumerate(lines)),
        "tab": raw.replace(",", "\t"), "dup-header": raw.replace("F_N", "v_ms", 1), "empty-header": raw.replace("F_N", "", 1),
        "header-only": lines[0] + "\n", "one-row": "\n".join(lines[:2]), "quoted": "\n".join(
            [lines[0]] + ['"' + l.replace(",", '","') + '"' for l in lines[1:]]),
        "comma-decimal": lines[0].replace(",", ";") + "\n" + "\n".join(l.replace(",", ";").replace(".", ",")
                                                                          for l in lines[1:]),
        "crlf": raw.replace("\n", "\r\n"), "cr-only": raw.replace("\n", "\r"), "trailing-comma":
            "\n".join(l + "," for l in lines), "blank-lines": "\n\n".join(lines), "binary": None,
        "nul-bytes": raw[:500] + "\x00" * 50 + raw[500:], "nan-cells": raw.replace(lines[40], "0.039,nan,nan"),
        "inf-cell": raw.replace(lines[40], lines[40].split(",")[0] + ",inf,1"), "huge-cell":
            raw.replace(lines[40], lines[40].split(",")[0] + ",1e300,1"), "neg-time": raw.replace(lines[40], "-5,0.001,1"),
        "time-dup": raw.replace(lines[41], lines[40]), "unsorted": "\n".join([lines[0]] + lines[1:][::-1]),
        "long-line": raw.replace(lines[40], lines[40] + "," + "9" * 200000), "extra-col-row":
            raw.replace(lines[40], lines[40] + ",5,6"), "only-spaces-header": "   ,  ,  \n" + "\n".join(lines[1:]),
        "html": "<html><body>404</body></html>", "json-in-csv": (W / "lugre.json").read_text(),
        "true-false": raw.replace(lines[40], lines[40].split(",")[0] + ",True,False"),
        "units-header": raw.replace("t_s,", "t_s [ms],", 1), "gzip-fake": None, "empty": "",
        "space-sep-numbers": raw.replace(",", " , "), "exp-D": raw.replace("e-", "D-"),
    }
    for i, (name, text) in enumerate(variants.items()):
        suffix = ".csv"
        p = W / f"d_{i}{suffix}"
        if name == "utf16":
            p.write_bytes(raw.encode("utf-16"))
        elif name == "binary":
            p.write_bytes(bytes(random.Random(i).randrange(256) for _ in range(5000)))
        elif name == "gzip-fake":
            import gzip
            p.write_bytes(gzip.compress(raw.encode()))
        else:
            p.write_text(text, encoding="utf-8", newline="")
        argv = list(static)
        argv[2] = p
        col_keys = [str(p), "t_s", "v_ms", "F_N", "column", "row", "file"]
        add(f"D-static:{name}", argv + ["--json", W / f"o_d{i}.json"], expect="either", cause=col_keys,
            inputs=[p], outputs_absent=[W / f"o_d{i}.json"])
        add(f"D-sim-pos:{name}", ["simulate", lug, "--position", p, "--time", "t_s", "--column", "v_ms"],
            expect="either", cause=col_keys, inputs=[p])
    # other formats with wrong content
    for ext in (".parquet", ".h5", ".mat", ".tdms", ".xlsx", ".npz", ".txt", ""):
        p = W / f"fmt{ext or '_noext'}"
        p.write_text(raw)
        add(f"D-fmt:{ext or 'noext'}-csvtext", static[:2] + [p] + static[3:], expect="either",
            cause=[str(p), "format", "extension"], inputs=[p])
        q = W / f"fmt_empty{ext or '_noext'}"
        q.write_bytes(b"")
        add(f"D-fmt:{ext or 'noext'}-empty", static[:2] + [q] + static[3:], expect="error", cause=[str(q)])
    # real parquet/h5 with problems
    import pandas as pd
    df = pd.read_csv(W / "stairs.csv")
    df2 = df.copy()
    df2["v_ms"] = df2["v_ms"].astype(str)
    for name, frame in (("str-col", df2), ("empty-frame", df.iloc[:0]), ("int-col", df.assign(F_N=1)),
                        ("obj-mixed", df.assign(F_N=[1.0 if i % 2 else "x" for i in range(len(df))]))):
        p = W / f"pq_{name}.parquet"
        try:
            frame.to_parquet(p)
        except Exception:  # noqa: BLE001
            continue
        add(f"D-parquet:{name}", static[:2] + [p] + static[3:], expect="either", cause=[str(p), "F_N", "v_ms"])
    # ---- E: output paths --------------------------------------------------------------------
    os.chmod(W / "ro", 0o555)
    paths = {
        "folder": W / "adir", "trail-slash": str(W / "adir") + "/sub/", "ro-folder": W / "ro" / "x.json",
        "missing-folder": W / "nope" / "x.json", "space-name": W / "a b.json", "newline-name": W / "a\nb.json",
        "dev-null": "/dev/null", "dev-full": "/dev/full", "input": W / "stairs.csv", "old-file": W / "old.json",
        "dot": ".", "dotdot": "..", "link-to-dir": W / "ldir", "dangling-link": W / "dang.json",
        "tilde": "~nouser/x.json", "proc": "/proc/self/status",
    }
    (W / "ldir").symlink_to(W / "adir")
    (W / "dang.json").symlink_to(W / "gone" / "x.json")
    for name, pth in paths.items():
        exp = "ok" if name in ("space-name", "old-file", "newline-name") else "either"
        add(f"E-static-json:{name}", static + ["--json", pth], expect=exp, cause=["--json"])
        add(f"E-static-plot:{name}", static + ["--plot", str(pth) + ("" if str(pth).endswith("/") else ".png")
                                               if name not in ("dev-null", "dev-full", "input", "old-file") else pth],
            expect="either", cause=["--plot"])
        own = {"input": lug, "old-file": W / "o_old_export.json"}  # export's own input; a copy of old.json
        (W / "o_old_export.json").write_text('{"old": true}')
        add(f"E-export-out:{name}", ["export", lug, "--format", "c", "--out", own.get(name, pth)], expect="either",
            cause=["--out"], unwatch=[W / "o_old_export.json"])
        if name not in ("input", "old-file"):
            add(f"E-models-json:{name}", ["models", "--json", pth], expect="either", cause=["--json"])
        add(f"E-report-o:{name}", ["report", W / "static.json", "-o", W / "static.json" if name == "input" else pth],
            expect="either", cause=["--out", "-o"])
    # ---- F: study TOML mutations ------------------------------------------------------------
    st = (W / "study.toml").read_text()
    for i, (name, text) in enumerate([
        ("draws0", st.replace("draws = 2\n", "draws = 0\n")), ("draws-neg", st.replace("draws = 2\n", "draws = -3\n")),
        ("draws-huge", st.replace("draws = 2\n", "draws = 1000000000\n")), ("draws-float", st.replace("draws = 2\n", "draws = 2.5\n")),
        ("draws-str", st.replace("draws = 2\n", 'draws = "2"\n')), ("seeds0", st.replace("seeds = 1", "seeds = 0")),
        ("comp-empty", st.replace('compensators = ["none", "coulomb", "sinc", "sigmoid"]', "compensators = []")),
        ("comp-bogus", st.replace('"sigmoid"]', '"bogus"]')), ("comp-dup", st.replace('"sigmoid"]', '"none"]')),
        ("mass-nan", st.replace("mass = 273.0", "mass = nan")), ("mass-inf", st.replace("mass = 273.0", "mass = inf")),
        ("mass-neg", st.replace("mass = 273.0", "mass = -273.0")), ("spread-2", st.replace("guide_friction = 0.3", "guide_friction = 2.0")),
        ("spread-neg", st.replace("guide_friction = 0.3", "guide_friction = -0.3")), ("preset-bogus", st.replace('"ballscrew"', '"bogus"')),
        ("dup-key", st.replace("seed = 0", "seed = 0\nseed = 1")), ("bad-toml", st[:200] + "[[[\n"),
        ("unknown-key", st + "\n[extra]\nx = 1\n"), ("freq-0", st.replace("frequency = 1.0", "frequency = 0.0")),
        ("duration-1e308", st.replace("duration = 0.6", "duration = 1e308")), ("amp-0", st.replace("amplitude = 0.025", "amplitude = 0")),
        ("empty", ""), ("bom", "\ufeff" + st), ("latin1", None), ("seed-neg", st.replace("seed = 0", "seed = -1")),
        ("unicode-key", st.replace("[spread]", "[spread]\nmäss = 0.1")),
    ]):
        p = W / f"st_{i}.toml"
        if text is None:
            p.write_bytes(st.replace("#", "# é").encode("latin-1", errors="replace"))
        else:
            p.write_text(text)
        add(f"F-study:{name}", ["study", p, "--out", W / f"o_st{i}.parquet", "--workers", "0", "--no-progress"],
            expect="either", cause=[str(p), "draws", "seeds", "compensator", "mass", "spread", "preset", "seed",
                                    "frequency", "duration", "amplitude", "toml", "key"],
            outputs_absent=[W / f"o_st{i}.parquet"], timeout=120)
    # ---- G: odd verb options ------------------------------------------------------------------
    for name, argv in [
        ("export-format-bogus", ["export", lug, "--format", "xml", "--out", W / "o.xml"]),
        ("export-name-c-bad", ["export", lug, "--format", "c", "--out", W / "o.h", "--name", "1 bad-name"]),
        ("export-name-st-bad", ["export", lug, "--format", "st", "--out", W / "o.st", "--name", "FB;DROP"]),
        ("export-name-empty", ["export", lug, "--format", "c", "--out", W / "o.h", "--name", ""]),
        ("export-name-unicode", ["export", lug, "--format", "c", "--out", W / "o.h", "--name", "reibung_ä"]),
        ("export-machine", ["export", emps, "--format", "csv", "--out", W / "o.csv"]),
        ("export-points-even", ["export", lug, "--format", "csv", "--out", W / "o.csv", "--points", "200"]),
        ("export-points-huge", ["export", lug, "--format", "csv", "--out", W / "o.csv", "--points", "1000000001"]),
        ("compensate-bogus", ["compensate", "bogus"]),
        ("compensate-comp-bogus", ["compensate", "ballscrew", "--quick", "--compensator", "bogus"]),
        ("compensate-comp-dup", ["compensate", "ballscrew", "--quick", "--compensator", "none", "--compensator", "none"]),
        ("compensate-model-dir", ["compensate", "emps", "--quick", "--model", W / "adir"]),
        ("compensate-model-machine", ["compensate", "emps", "--quick", "--model", emps]),
        ("compensate-test-without-file", ["compensate", "ballscrew", "--test", W / "study.toml"]),
        ("compensate-machine-no-test", ["compensate", emps]),
        ("compensate-machine-test-missing", ["compensate", emps, "--test", W / "nope.toml"]),
        ("compensate-plot-xyz", ["compensate", "ballscrew", "--quick", "--plot", W / "o.xyz"]),
        ("report-no-out", ["report", W / "static.json"]),
        ("report-empty-title", ["report", W / "static.json", "-o", W / "rep1", "--title", ""]),
        ("report-html-title", ["report", W / "static.json", "-o", W / "rep2", "--title", "<script>alert(1)</script>"]),
        ("report-csv-input", ["report", W / "stairs.csv", "-o", W / "rep3"]),
        ("report-machine", ["report", emps, "-o", W / "rep4"]),
        ("report-toml", ["report", W / "study.toml", "-o", W / "rep5"]),
        ("report-binary", ["report", W / "d_16.csv", "-o", W / "rep6"]),
        ("report-out-is-file", ["report", W / "static.json", "-o", W / "old.json"]),
        ("report-out-is-input", ["report", W / "static.json", "-o", W / "static.json"]),
        ("fleet-identify-empty", ["fleet", "identify", W / "adir", "--out", W / "fi.parquet", "--workers", "0",
                                  "--no-progress"]),
        ("fleet-identify-glob-none", ["fleet", "identify", str(W / "*.nothing"), "--out", W / "fi.parquet",
                                      "--workers", "0"]),
        ("fleet-monitor-csv", ["fleet", "monitor", W / "stairs.csv"]),
        ("fleet-monitor-alpha-2", ["fleet", "monitor", W / "pq_int-col.parquet", "--alpha", "2"]),
        ("fleet-report-json", ["fleet", "report", W / "static.json", "--out", W / "fr.html"]),
        ("fleet-sim-format-bogus", ["fleet", "simulate", "--axes", "1", "--days", "1", "--out", W / "fs1",
                                    "--format", "xlsx"]),
        ("fleet-sim-broken-neg", ["fleet", "simulate", "--axes", "1", "--days", "1", "--out", W / "fs2", "--broken", "-1"]),
        ("fleet-sim-broken-many", ["fleet", "simulate", "--axes", "1", "--days", "1", "--out", W / "fs3", "--broken", "50"]),
        ("fleet-sim-out-file", ["fleet", "simulate", "--axes", "1", "--days", "1", "--out", W / "old.json"]),
        ("fleet-sim-seed-big", ["fleet", "simulate", "--axes", "1", "--days", "1", "--out", W / "fs4", "--seed",
                                str(2**32)]),
        ("reproduce-zf-nut-bogus", ["reproduce", "zhu-fujimoto", "--json", W / "o_zf.json", "--nut-model", "bogus"]),
        ("reproduce-zf-stage-bogus", ["reproduce", "zhu-fujimoto", "--json", W / "o_zf.json", "--stage", "x"]),
        ("reproduce-zf-workers-without-rob", ["reproduce", "zhu-fujimoto", "--json", W / "o_zf.json", "--workers", "2"]),
        ("reproduce-zf-seed-big", ["reproduce", "zhu-fujimoto", "--json", W / "o_zf.json", "--seed", str(2**32)]),
        ("reproduce-sdss-plot-bad", ["reproduce", "sdss", "--quick", "--json", W / "o_s.json", "--plot", W / "p.xyz"]),
        ("reproduce-sdss-seed-big", ["reproduce", "sdss", "--quick", "--json", W / "o_s.json", "--seed", "70000"]),
        ("reproduce-zhang-out-without-rob", ["reproduce", "zhang2023", "--json", W / "o_z.json", "--out", W / "zo"]),
        ("reproduce-zhang-scheduler-bogus", ["reproduce", "zhang2023", "--json", W / "o_z.json", "--robustness",
                                             "--scheduler", "tcp://127.0.0.1:1", "--out", W / "zo2"]),
        ("demo-out-file", ["demo", "--out", W / "old.json"]),
        ("demo-out-ro", ["demo", "--out", W / "ro" / "demo"]),
        ("models-json-dir", ["models", "--json", W / "adir"]),
        ("simulate-machine-input-twice", mach + ["--input", "qg=0", "--dt", "1e-3"]),
        ("simulate-machine-input-unknown", mach + ["--input", "zz=0"]),
        ("simulate-machine-input-huge", ["simulate", emps, "--input", "qg=1e200", "--dt", "1e-3", "--duration", "0.01"]),
        ("simulate-machine-input-col-missing", ["simulate", emps, "--input", "qg=" + str(W / "ref.csv") + ":nope"]),
        ("simulate-machine-input-nofile", ["simulate", emps, "--input", "qg=" + str(W / "nope.csv") + ":qg"]),
        ("simulate-machine-input-dir", ["simulate", emps, "--input", "qg=" + str(W / "adir") + ":qg"]),
        ("simulate-machine-dur-huge", ["simulate", emps, "--input", "qg=0", "--dt", "1e-9", "--duration", "1e3"]),
        ("simulate-law-with-input", ["simulate", lug, "--input", "qg=0"]),
        ("simulate-two-drives", ["simulate", lug, "--position", W / "motion.csv", "--velocity", W / "motion.csv"]),
        ("simulate-no-drive", ["simulate", lug]),
        ("simulate-vi-bogus", ["simulate", lug, "--velocity", W / "motion.csv", "--velocity-integration", "x"]),
        ("simulate-where-bad", ["simulate", lug, "--position", W / "motion.csv", "--where", "nocol"]),
        ("simulate-where-missing-col", ["simulate", lug, "--position", W / "motion.csv", "--where", "z=1"]),
        ("simulate-where-nothing", ["simulate", lug, "--position", W / "motion.csv", "--where", "t=0.5123"]),
        ("simulate-out-xlsx", ["simulate", lug, "--position", W / "motion.csv", "--out", W / "o.xlsx"]),
        ("simulate-out-same-as-json", ["simulate", lug, "--position", W / "motion.csv", "--out", W / "o.csv",
                                       "--json", W / "o.csv"]),
        ("simulate-static-model", ["simulate", W / "static.json", "--position", W / "motion.csv"]),
        ("simulate-mass-on-position", ["simulate", lug, "--position", W / "motion.csv", "--mass", "1"]),
        ("simulate-gms-force-tiny-mass", ["simulate", W / "gms_model.json", "--force", W / "force.csv", "--mass", "1e-12"]),
        ("identify-static-group-missing", static + ["--group", "nocol"]),
        ("identify-static-direction-bogus", static + ["--direction", "up"]),
        ("identify-static-loss-bogus", static + ["--loss", "l3"]),
        ("identify-static-criterion-bogus", static + ["--criterion", "x"]),
        ("identify-static-vel-and-pos", static + ["--position", "t_s"]),
        ("identify-static-units-weird", static + ["--force-unit", "\n", "--velocity-unit", ""]),
        ("identify-static-validate-self", static + ["--validate", S]),
        ("identify-static-validate-dir", static + ["--validate", W / "adir"]),
        ("identify-static-rotary-units", static + ["--rotary", "--force-unit", "N"]),
        ("identify-presl-static-json-bad", presl[:-2] + ["--elements", "2", "--static-json", W / "lugre.json"]),
        ("identify-presl-static-and-Fc", presl + ["--elements", "2", "--static-json", W / "static.json"]),
        ("identify-presl-branch-bogus", presl + ["--elements", "2", "--branch", "up"]),
        ("identify-presl-mask-missing", presl + ["--elements", "2", "--mask", "nocol"]),
        ("identify-presl-rests-bogus", presl + ["--elements", "2", "--rests", "x"]),
        ("identify-oe-free-bogus", ["identify", "output-error", G, "--time", "t_s", "--position", "x_m", "--force",
                                    "F_N", "--drive", "motion", "--Fc", "1", "--free", "bogus"]),
        ("identify-oe-free-empty", ["identify", "output-error", G, "--time", "t_s", "--position", "x_m", "--force",
                                    "F_N", "--drive", "motion", "--Fc", "1", "--free", ","]),
        ("identify-oe-k-xi-mismatch", ["identify", "output-error", G, "--time", "t_s", "--position", "x_m", "--force",
                                       "F_N", "--drive", "motion", "--Fc", "1", "--model", "gms", "--k", "1e4,1e5",
                                       "--xi", "1"]),
        ("identify-oe-k-text", ["identify", "output-error", G, "--time", "t_s", "--position", "x_m", "--force",
                                "F_N", "--drive", "motion", "--Fc", "1", "--model", "gms", "--k", "a,b", "--xi", "0.5,0.5"]),
        ("identify-oe-model-bogus", ["identify", "output-error", G, "--time", "t_s", "--position", "x_m", "--force",
                                     "F_N", "--model", "stribeck", "--Fc", "1"]),
        ("identify-oe-starts-0", ["identify", "output-error", G, "--time", "t_s", "--position", "x_m", "--force",
                                  "F_N", "--drive", "motion", "--Fc", "1", "--starts", "0"]),
        ("identify-oe-jacobian-bogus", ["identify", "output-error", G, "--time", "t_s", "--position", "x_m", "--force",
                                        "F_N", "--drive", "motion", "--Fc", "1", "--jacobian", "x"]),
        ("identify-oe-compare-bogus", ["identify", "output-error", G, "--time", "t_s", "--position", "x_m", "--force",
                                       "F_N", "--Fc", "1", "--compare", "q"]),
        ("identify-rb-law-bogus", ["identify", "rigid-body", G, "--time", "t_s", "--position", "x_m", "--force", "F_N",
                                   "--law", "x"]),
        ("identify-rb-delta-without-stribeck", ["identify", "rigid-body", G, "--time", "t_s", "--position", "x_m",
                                                "--force", "F_N", "--delta", "2"]),
        ("identify-unknown-verb", ["identify", "bogus"]),
        ("top-unknown-option", ["--bogus"]),
        ("debug-after-verb", ["models", "--json", W / "adir", "--debug"]),  # its traceback is asked for
    ]:
        add(f"G:{name}", argv, expect="either", cause=None, timeout=150)
    # ---- J: result files into report / export / simulate (identification-result mutations) ---------
    res = json.loads((W / "static.json").read_text())
    jm = []
    for key in list(res):
        for val in (None, "x", 1e308, [], {"a": {"b": [1, None]}}, float("nan")):
            d = json.loads(json.dumps(res))
            d[key] = val
            jm.append((f"{key}={str(val)[:15]!r}", json.dumps(d)))
    for key in list(res.get("parameters", {}))[:3]:
        d = json.loads(json.dumps(res))
        d["parameters"][key] = "1.0"
        jm.append((f"parameters.{key}=str", json.dumps(d)))
    rawr = (W / "static.json").read_text()
    jm += [("truncated", rawr[: len(rawr) * 2 // 3]), ("utf16", None), ("deep", "[" * 100000 + "]" * 100000)]
    rnd2 = random.Random(11)
    for i, (name, text) in enumerate(jm):
        p = W / f"r_{i}.json"
        if text is None:
            p.write_bytes(rawr.encode("utf-16"))
        else:
            p.write_text(text)
        verb = rnd2.choice(["report", "export", "simulate", "presl-static"])
        if verb == "report":
            argv = ["report", p, "-o", W / f"o_rep{i}"]
        elif verb == "export":
            argv = ["export", p, "--format", "st", "--out", W / f"o_x{i}.st"]
        elif verb == "simulate":
            argv = ["simulate", p, "--position", W / "motion.csv"]
        else:
            argv = ["identify", "presliding", G, "--time", "t_s", "--position", "x_m", "--force", "F_N",
                    "--elements", "2", "--static-json", p]
        add(f"J-{verb}:{name}", argv, expect="either", cause=[str(p)], inputs=[p])

    # ---- H: library calls with bad arguments ------------------------------------------------
    L = []

    def lib(id_, call, expect="error", check=None):
        L.append({"id": f"H:{id_}", "kind": "lib", "call": call, "expect": expect, "check": check, "cause": None})

    x = 20e-6 * np.sin(np.linspace(0, 6, 500))
    lg = fk.LuGre(LAW, sigma0=1e5, sigma1=30.0)
    lib("simulate-dt-str", lambda: fk.simulate(lg, position=x, dt="1e-3"))
    lib("simulate-dt-neg", lambda: fk.simulate(lg, position=x, dt=-1e-3))
    lib("simulate-dt-array", lambda: fk.simulate(lg, position=x, dt=np.array([1e-3])))
    lib("simulate-dt-1e308", lambda: fk.simulate(lg, position=x, dt=1e308))
    lib("simulate-pos-2d", lambda: fk.simulate(lg, position=np.ones((3, 3)), dt=1e-3))
    lib("simulate-pos-str", lambda: fk.simulate(lg, position="abc", dt=1e-3))
    lib("simulate-pos-obj", lambda: fk.simulate(lg, position=[1, "a", None], dt=1e-3))
    lib("simulate-pos-complex", lambda: fk.simulate(lg, position=x + 1j, dt=1e-3))
    lib("simulate-pos-empty", lambda: fk.simulate(lg, position=[], dt=1e-3))
    lib("simulate-pos-1", lambda: fk.simulate(lg, position=[0.0], dt=1e-3))
    lib("simulate-model-none", lambda: fk.simulate(None, position=x, dt=1e-3))
    lib("simulate-model-str", lambda: fk.simulate("lugre", position=x, dt=1e-3))
    lib("simulate-model-static", lambda: fk.simulate(LAW, position=x, dt=1e-3), expect="either")
    lib("simulate-both-drives", lambda: fk.simulate(lg, position=x, velocity=x, dt=1e-3))
    lib("simulate-force-no-plant", lambda: fk.simulate(lg, force=x, dt=1e-3))
    lib("simulate-force-mass-neg", lambda: fk.simulate(lg, force=x, dt=1e-3, plant=fk.Mass(-1)))
    lib("simulate-options-bogus", lambda: fk.simulate(lg, position=x, dt=1e-3, options="fast"))
    lib("simopt-rtol-neg", lambda: fk.SimOptions(rtol=-1))
    lib("simopt-bogus-kw", lambda: fk.SimOptions(bogus=1))
    lib("stribeck-Fc-str", lambda: fk.Stribeck(Fc="1", Fs=1.5, vs=1e-3))
    lib("stribeck-Fs<Fc", lambda: fk.Stribeck(Fc=1.0, Fs=0.5, vs=1e-3), expect="either")
    lib("stribeck-vs-0", lambda: fk.Stribeck(Fc=1.0, Fs=1.5, vs=0.0))
    lib("stribeck-np-array", lambda: fk.Stribeck(Fc=np.array([1.0, 2.0]), Fs=1.5, vs=1e-3))
    lib("stribeck-np-scalar", lambda: fk.Stribeck(Fc=np.float32(1.0), Fs=1.5, vs=1e-3), expect="ok")
    lib("stribeck-shape-bogus", lambda: fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, shape="x"))
    lib("gms-k-empty", lambda: fk.GMS(LAW, k=[], xi=[], C=1.0))
    lib("gms-k-xi-len", lambda: fk.GMS(LAW, k=[1.0, 2.0], xi=[1.0], C=1.0))
    lib("gms-k-2d", lambda: fk.GMS(LAW, k=[[1.0]], xi=[[1.0]], C=1.0))
    lib("gms-static-none", lambda: fk.GMS(None, k=[1.0], xi=[1.0], C=1.0))
    lib("gms-C-nan", lambda: fk.GMS(LAW, k=[1.0], xi=[1.0], C=float("nan")))
    lib("lugre-static-lugre", lambda: fk.LuGre(lg, sigma0=1.0, sigma1=1.0))
    lib("dahl-Fc-0", lambda: fk.Dahl(Fc=0.0, sigma0=1.0))
    lib("tdmssc-bogus", lambda: fk.TDMSSC(Fc0=1.0, Fs0=-1.0, vs=1e-3))
    lib("directional-mixed", lambda: fk.Directional(positive=LAW, negative=lg))
    lib("directional-none", lambda: fk.Directional(positive=None, negative=LAW))
    lib("mass-str", lambda: fk.Mass("1"))
    lib("mass-nan", lambda: fk.Mass(float("nan")))
    lib("rigidbody-bogus", lambda: fk.RigidBody(-1))
    lib("ballscrew-bogus", lambda: fk.RigidBallScrew())
    lib("steady-state-str", lambda: LAW.steady_state("abc"))
    lib("steady-state-2d", lambda: LAW.steady_state(np.ones((2, 2))), expect="either")
    lib("load-model-dir", lambda: fk.load_model(W / "adir"))
    lib("load-model-csv", lambda: fk.load_model(W / "stairs.csv"))
    lib("load-model-int", lambda: fk.load_model(5))
    lib("load-model-missing", lambda: fk.load_model(W / "nope.json"))
    lib("save-model-dir", lambda: fk.save_model(lg, W / "adir"))
    lib("save-model-none", lambda: fk.save_model(None, W / "o_none.json"))
    lib("save-model-str", lambda: fk.save_model("lugre", W / "o_none.json"))
    lib("save-model-over-input-ro", lambda: fk.save_model(lg, W / "ro" / "m.json"))
    lib("save-model-method-obj", lambda: fk.save_model(lg, W / "o_m.json", method=object()))
    lib("load-csv-dir", lambda: fk.load_csv(W / "adir", time="t"))
    lib("load-csv-none", lambda: fk.load_csv(None, time="t"))
    lib("load-recording-bad-col", lambda: fk.load_recording(W / "stairs.csv", time="t_s", velocity="nope", force="F_N"))
    lib("load-recording-col-int", lambda: fk.load_recording(W / "stairs.csv", time=0, velocity=1, force=2))
    lib("load-groups-bad", lambda: fk.load_groups(W / "stairs.csv", group="nope", time="t_s"))
    rec = fk.load_recording(W / "stairs.csv", time="t_s", velocity="v_ms", force="F_N")
    lib("decimate-0", lambda: fk.decimate(rec, 0))
    lib("decimate-float", lambda: fk.decimate(rec, 2.5))
    lib("decimate-huge", lambda: fk.decimate(rec, 10**9))
    lib("derivative-str", lambda: fk.derivative("abc", 1e-3))
    lib("derivative-dt-0", lambda: fk.derivative(np.arange(10.0), 0.0))
    lib("lowpass-cutoff-neg", lambda: fk.lowpass(np.arange(100.0), 1e-3, -5))
    lib("lowpass-cutoff-nyq", lambda: fk.lowpass(np.arange(100.0), 1e-3, 1e4))
    lib("find-plateaus-str", lambda: fk.find_plateaus("abc", 1e-3))
    lib("find-reversals-nan", lambda: fk.find_reversals(np.array([0.0, np.nan, 1.0])))
    lib("find-cycles-empty", lambda: fk.find_cycles(np.array([]), 1e-3))
    lib("fit-static-map-str", lambda: fk.fit_static_map(["a"], ["b"]))
    lib("fit-static-map-len", lambda: fk.fit_static_map(np.ones(5), np.ones(4)))
    lib("fit-static-map-zero-v", lambda: fk.fit_static_map(np.zeros(20), np.ones(20)))
    lib("fit-static-map-model-bogus", lambda: fk.fit_static_map(np.r_[np.geomspace(1e-3, 1, 10)],
                                                                 np.ones(10), model="x"))
    lib("fit-static-records-none", lambda: fk.fit_static_records(None))
    lib("fit-presliding-elements-0", lambda: fk.fit_presliding({"t": np.arange(10.0), "x": np.arange(10.0),
                                                                "F": np.arange(10.0)}, elements=0))
    lib("fit-presliding-elements-str", lambda: fk.fit_presliding({"t": np.arange(10.0), "x": np.arange(10.0),
                                                                  "F": np.arange(10.0)}, elements="3"))
    lib("fit-presliding-elements-bool", lambda: fk.fit_presliding({"t": np.arange(10.0), "x": np.arange(10.0),
                                                                   "F": np.arange(10.0)}, elements=True))
    from frictionkit.identify import piecewise_linear_fit
    lib("plfit-grid-1", lambda: piecewise_linear_fit(np.linspace(0, 1, 50), np.linspace(0, 1, 50), 2, grid=1))
    lib("plfit-nan", lambda: piecewise_linear_fit(np.r_[np.linspace(0, 1, 50), np.nan], np.linspace(0, 1, 51), 2))
    lib("plfit-len", lambda: piecewise_linear_fit(np.linspace(0, 1, 50), np.linspace(0, 1, 40), 2))
    lib("plfit-neg-u", lambda: piecewise_linear_fit(-np.linspace(0, 1, 50), np.linspace(0, 1, 50), 2))
    lib("plfit-breaks-float", lambda: piecewise_linear_fit(np.linspace(0, 1, 50), np.linspace(0, 1, 50), 2.7))
    lib("fit-rigid-body-empty", lambda: fk.fit_rigid_body({}))
    lib("fit-output-error-none", lambda: fk.fit_output_error(None, lg, inertia=1.0))
    lib("simulate-batch-models-dict", lambda: fk.simulate_batch({"a": lg}, masses=[1.0], force=x, dt=1e-3))
    lib("simulate-batch-empty", lambda: fk.simulate_batch([], masses=[], force=x, dt=1e-3))
    lib("simulate-machine-none", lambda: fk.simulate_machine(None, dt=1e-3, inputs={}, n_samples=10))
    m = fk.load_model(W / "emps.json")
    lib("simulate-machine-input-huge", lambda: fk.simulate_machine(m, dt=1e-3, inputs={"qg": np.full(50, 1e200)},
                                                                   n_samples=50))
    lib("simulate-machine-input-nan", lambda: fk.simulate_machine(m, dt=1e-3, inputs={"qg": np.full(50, np.nan)},
                                                                  n_samples=50))
    lib("simulate-machine-input-short", lambda: fk.simulate_machine(m, dt=1e-3, inputs={"qg": np.zeros(5)},
                                                                    n_samples=50))
    lib("simulate-machine-input-extra", lambda: fk.simulate_machine(m, dt=1e-3, inputs={"qg": np.zeros(50),
                                                                                       "zz": np.zeros(50)}, n_samples=50))
    lib("simulate-machine-substeps-0", lambda: fk.simulate_machine(m, dt=1e-3, inputs={"qg": np.zeros(50)},
                                                                   n_samples=50, substeps=0))
    lib("simulate-machine-seed-neg", lambda: fk.simulate_machine(m, dt=1e-3, inputs={"qg": np.zeros(50)},
                                                                 n_samples=50, seed=-1))
    lib("machine-dof-inertia-str", lambda: fk.Machine("m").dof("x", inertia="1"))
    lib("machine-dof-dup", lambda: (lambda mm: (mm.dof("x", inertia=1.0), mm.dof("x", inertia=1.0)))(fk.Machine("m")))
    lib("modelfile-from-dict-list", lambda: fk.ModelFile.from_dict([1, 2]))
    lib("modelfile-from-dict-none", lambda: fk.ModelFile.from_dict(None))
    lib("recording-bad", lambda: fk.Recording(t=[0, 1], v=[0], F=[0, 1]))
    lib("coulomb-comp-bad", lambda: fk.coulomb_compensation(np.ones(3), F0=-1))
    lib("sinc-comp-bad", lambda: fk.sinc_compensation(np.ones(3), F0=1.0, xs=0.0))
    lib("sigmoid-comp-bad", lambda: fk.sigmoid_compensation(np.ones(3), F0=1.0, sigma=float("nan")))
    for c in L:
        C.append(c)
    # ---- I: interrupts (subprocess) ---------------------------------------------------------
    for after in (0.3, 1.5, 4.0):
        C.append({"id": f"I:sigint-static-{after}", "kind": "sig", "after": after,
                  "argv": static + ["--model", "auto", "--json", W / f"o_i{after}.json"],
                  "outputs_absent": [W / f"o_i{after}.json"]})
    for after in (2.0, 6.0):
        C.append({"id": f"I:sigint-presl32-{after}", "kind": "sig", "after": after,
                  "argv": presl + ["--elements", "8", "--json", W / f"o_ip{after}.json"],
                  "outputs_absent": [W / f"o_ip{after}.json"]})
        C.append({"id": f"I:sigint-models-{after/10}", "kind": "sig", "after": after / 10,
                  "argv": ["models", "--json", W / f"o_im{after}.json"]})
    return C


# ------------------------------------------------------------------ round 11 (helper r11)
#: Address-space limit of a subprocess case [bytes]: numba and the libraries map ~1.5 GB at start.
SUB_MEMORY = 4 * 2**30


def run_sub(case):
    """A subprocess of the console script with its own environment (locales, encodings) — or several at once
    (``concurrent``: the same command N times, then ``after`` checks the shared output)."""
    t0 = time.perf_counter()
    env = {**os.environ, **case.get("env", {})}
    n = case.get("concurrent", 1)
    def limits():  # a runaway read (/dev/zero as a model file ate 15 GB in-process) ends in MemoryError
        import resource

        resource.setrlimit(resource.RLIMIT_AS, (SUB_MEMORY, SUB_MEMORY))

    procs = [subprocess.Popen([FK] + [str(a) for a in case["argv"]], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              cwd=W, env=env, stdin=subprocess.DEVNULL, preexec_fn=limits) for _ in range(n)]
    outs = []
    for p in procs:
        try:
            outs.append(p.communicate(timeout=case.get("timeout", TIMEOUT)))
        except subprocess.TimeoutExpired:
            for q in procs:
                q.kill()
            return "hang", f"no exit within {case.get('timeout', TIMEOUT)} s", None, time.perf_counter() - t0
    errs = [e.decode("utf-8", "replace") for _, e in outs]
    codes = [p.returncode for p in procs]
    worst = max(range(n), key=lambda i: codes[i] != 0)
    cls, msg = classify(case, codes[worst], errs[worst])
    if case.get("after") is not None and cls in ("ok", "own-error"):
        bad = case["after"]()
        if bad:
            cls, msg = "file-fault", f"{msg} | {bad}"
    if n > 1:
        msg = f"exits {codes}: {msg}"
    return cls, msg, codes[worst], time.perf_counter() - t0


def _numeric_leaves(node, path=()):
    """Every number in a parsed JSON document, as (path, value)."""
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _numeric_leaves(v, path + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _numeric_leaves(v, path + (i,))
    elif isinstance(node, (int, float)) and not isinstance(node, bool):
        yield path, node


def _set_path(doc, path, value):
    node = doc
    for k in path[:-1]:
        node = node[k]
    node[path[-1]] = value


def cases11():
    """Round 11: families K (unicode / long / odd paths), L (symlink loops, FIFOs, devices, files changing
    while read), N (NaN/inf/huge in every number of every model kind and of a machine file), O (huge but legal
    arrays), P (empty and half-finished folders for the fleet verbs), Q (odd locales and encodings, decimal
    comma), R (concurrent fleet writers), S (--help of every verb), T (every public Python entry point with a
    wrong type in each argument)."""
    C = []
    S = str(W / "stairs.csv")
    static = ["identify", "static", S, "--time", "t_s", "--velocity", "v_ms", "--force", "F_N", "--model",
              "coulomb_viscous"]
    lug = W / "lugre.json"

    def add(id_, argv, expect="either", cause=None, **kw):
        C.append({"id": id_, "kind": "cli", "argv": argv, "expect": expect, "cause": cause, **kw})

    (W / "fl_empty").mkdir(exist_ok=True)
    # ---- K: unicode, very long and odd paths (input and output) -------------------------------
    raw = (W / "stairs.csv").read_bytes()
    names = {"umlaut": "mëßdaten.csv", "cjk": "摩擦データ.csv", "emoji": "🙂axis.csv", "rtl": "\u202eabc.csv",
             "dash": "-x.csv", "space-end": "a .csv", "long-255": "a" * 251 + ".csv", "newline": "a\nb.csv",
             "backslash": "a\\b.csv", "colon": "a:b.csv", "star": "a*b.csv"}
    for key, name in names.items():
        p = W / name
        p.write_bytes(raw)
        argv = list(static)
        argv[2] = str(p)
        add(f"K-in:{key}", argv, expect="ok")
        add(f"K-json:{key}", static + ["--json", str(W / ("o_" + name[:-4] + ".json"))], expect="either",
            cause=["--json"])
    deep = W / "/".join(["d" * 200] * 25)  # > PATH_MAX (4096)
    add("K-in:path-too-long", static[:2] + [str(deep / "x.csv")] + static[3:], expect="error", cause=["x.csv", "long"])
    add("K-json:path-too-long", static + ["--json", str(deep / "x.json")], expect="error", cause=["--json", "long"])
    add("K-json:name-too-long", static + ["--json", str(W / ("b" * 300 + ".json"))], expect="error",
        cause=["--json", "long"])
    add("K-export:name-too-long", ["export", lug, "--format", "c", "--out", str(W / ("c" * 300 + ".h"))],
        expect="error", cause=["--out", "long"])
    add("K-model:name-too-long", ["export", str(W / ("m" * 300 + ".json")), "--format", "c", "--out", W / "o_k.h"],
        expect="error", cause=["long", "json"])
    add("K-fleet-out:too-long", ["fleet", "simulate", "--axes", "1", "--days", "1", "--out", str(deep)],
        expect="error", cause=["--out", "long"])
    add("K-json-dash", static + ["--json", "-"], expect="either", cause=["--json"])
    # ---- L: symlink loops, FIFOs, devices, files changing while read -----------------------------
    (W / "loop_a.csv").symlink_to(W / "loop_b.csv")
    (W / "loop_b.csv").symlink_to(W / "loop_a.csv")
    (W / "loopdir").mkdir()
    (W / "loopdir" / "self").symlink_to(W / "loopdir")
    os.mkfifo(W / "fifo.csv")
    os.mkfifo(W / "fifo.json")
    for key, p in (("symlink-loop", W / "loop_a.csv"), ("fifo", W / "fifo.csv"), ("dev-zero", "/dev/zero"),
                   ("dev-null", "/dev/null"), ("proc-file", "/proc/self/stat"), ("dir-loop", W / "loopdir" / "self")):
        argv = list(static)
        argv[2] = str(p)
        add(f"L-in:{key}", argv, expect="error", cause=[str(p), "file", "fifo", "loop", "symbolic", "empty"],
            timeout=90, kind="sub")
        add(f"L-sim-pos:{key}", ["simulate", lug, "--position", str(p)], expect="error",
            cause=[str(p), "file", "fifo", "loop", "symbolic", "empty"], timeout=90, kind="sub")
    # a model, result or configuration file that is a FIFO, a device or a link loop (run as subprocesses with a
    # memory limit: /dev/zero read whole grows without end)
    for key, p in (("symlink-loop", W / "loop_a.csv"), ("fifo", W / "fifo.json"), ("dev-zero", "/dev/zero"),
                   ("dev-urandom", "/dev/urandom")):
        add(f"L-model:{key}", ["export", str(p), "--format", "c", "--out", W / "o_l.h"], expect="error",
            cause=[str(p), "file", "fifo", "loop", "symbolic"], timeout=90, kind="sub")
        add(f"L-sim-model:{key}", ["simulate", str(p), "--position", W / "motion.csv"], expect="error",
            cause=[str(p), "file", "fifo", "loop", "symbolic"], timeout=90, kind="sub")
        add(f"L-report-in:{key}", ["report", str(p), "-o", W / "o_lrep"], expect="error",
            cause=[str(p), "file", "fifo", "loop", "symbolic"], timeout=90, kind="sub")
        add(f"L-study-toml:{key}", ["study", str(p), "--out", W / "o_lst.parquet", "--workers", "0"],
            expect="error", cause=[str(p), "file", "fifo", "loop", "symbolic"], timeout=90, kind="sub")
        add(f"L-fleet-config:{key}", ["fleet", "identify", W / "fl_empty", "--config", str(p), "--out",
                                      W / "o_lfc.parquet", "--workers", "0"], expect="error",
            cause=[str(p), "file", "fifo", "loop", "symbolic"], timeout=90, kind="sub")
        add(f"L-compensate-test:{key}", ["compensate", W / "emps.json", "--test", str(p)], expect="error",
            cause=[str(p), "file", "fifo", "loop", "symbolic"], timeout=90, kind="sub")
        add(f"L-static-json:{key}", ["identify", "presliding", str(W / "gms.csv"), "--time", "t_s", "--position",
                                     "x_m", "--force", "F_N", "--elements", "2", "--static-json", str(p)],
            expect="error", cause=[str(p), "file", "fifo", "loop", "symbolic"], timeout=90, kind="sub")
        add(f"L-json-out:{key}", static + ["--json", str(p)], expect="error", cause=["--json"], timeout=90, kind="sub")
    add("L-fleet-identify:dir-loop", ["fleet", "identify", W / "loopdir", "--out", W / "o_fl.parquet", "--workers",
                                      "0", "--no-progress"], expect="error", cause=["loopdir", "log", "file"],
        timeout=60)

    def changing(mode):
        def call():
            import threading

            p = W / f"chg_{mode}.csv"
            p.write_bytes(raw)
            stop = threading.Event()

            def writer():
                i = 0
                while not stop.is_set():
                    if mode == "truncate":
                        p.write_bytes(raw[: (i * 7919) % len(raw)])
                    elif mode == "append":
                        with p.open("ab") as f:
                            f.write(b"9.9,1,1\n")
                    else:  # replace atomically by another complete file
                        q = W / f"chg_{mode}.tmpw"
                        q.write_bytes(raw if i % 2 else raw.replace(b"v_ms", b"v_xx", 1))
                        os.replace(q, p)
                    i += 1
                    time.sleep(0.001)

            th = threading.Thread(target=writer, daemon=True)
            th.start()
            try:
                return fk.load_recording(p, time="t_s", velocity="v_ms", force="F_N")
            finally:
                stop.set()
                th.join()
        return call

    L = []
    for mode in ("truncate", "append", "replace"):
        for rep in range(3):
            L.append({"id": f"L-changing:{mode}-{rep}", "kind": "lib", "call": changing(mode), "expect": "either",
                      "check": None, "cause": None})
    # ---- N: NaN / inf / huge in every number of every model kind and a machine file ---------------
    laws = {"stribeck": LAW, "coulomb": fk.CoulombViscous(Fc=1.0, sigma2=0.4),
            "tdmssc": fk.TDMSSC(Fc0=1.0, Fs0=1.5, vs=1e-3, Fc1=0.1),
            "directional": fk.Directional(positive=LAW, negative=fk.Stribeck(Fc=1.1, Fs=1.4, vs=2e-3)),
            "dahl": fk.Dahl(Fc=1.0, sigma0=1e5), "lugre": fk.LuGre(LAW, sigma0=1e5, sigma1=30.0),
            "gms": fk.GMS(LAW, k=[1e4, 1e5], xi=[0.5, 0.5], C=20.0)}
    NUMBERS = (("NaN", float("nan")), ("Infinity", float("inf")), ("-Infinity", float("-inf")), ("1e200", 1e200))
    count = iter(range(10**6))

    def mutants_of(doc, values):
        """Each number of the document's "model" replaced by each value in turn, written to a file."""
        for path, _ in _numeric_leaves(doc["model"], ("model",)):
            for val_name, val in values:
                d = json.loads(json.dumps(doc))
                _set_path(d, path, val)
                p = W / f"n_{next(count)}.json"
                p.write_text(json.dumps(d, allow_nan=True))
                yield ".".join(map(str, path[1:])), val_name, path, p

    for kind, law in laws.items():
        src = W / f"n_{kind}.json"
        fk.save_model(law, src)
        for field, val_name, path, p in mutants_of(json.loads(src.read_text()), NUMBERS):
            add(f"N-{kind}:{field}={val_name}", ["export", p, "--format", "csv", "--out", W / "o_n.csv"],
                expect="error", cause=[path[-1] if isinstance(path[-1], str) else str(path[-2]), "finite", "1e+150"])
    for field, val_name, path, p in mutants_of(json.loads((W / "emps.json").read_text()), NUMBERS[:2] + NUMBERS[3:]):
        exp = "either" if path[-1] in ("limit", "lo", "hi") else "error"
        add(f"N-machine:{field}={val_name}", ["simulate", p, "--input", "qg=0", "--dt", "1e-3", "--duration", "0.02"],
            expect=exp, cause=[str(k) for k in path[-2:]] + ["finite", "1e+150"])
    # ---- O: huge but legal arrays ----------------------------------------------------------------
    lg = fk.LuGre(LAW, sigma0=1e5, sigma1=30.0)

    def lib(id_, call, expect="error", check=None, timeout=TIMEOUT):
        L.append({"id": id_, "kind": "lib", "call": call, "expect": expect, "check": check, "cause": None,
                  "timeout": timeout})

    big = 2_000_000
    lib("O:steady-state-1e7", lambda: lg.steady_state(np.linspace(-1, 1, 10_000_000)), expect="ok")
    lib("O:simulate-position-2e6", lambda: fk.simulate(lg, position=1e-5 * np.sin(np.linspace(0, 200, big)), dt=1e-4),
        expect="ok", timeout=150)
    lib("O:simulate-force-2e6", lambda: fk.simulate(lg, plant=fk.Mass(1.0), force=np.sin(np.linspace(0, 200, big)),
                                                    dt=1e-4), expect="ok", timeout=150)
    lib("O:gms-200-elements", lambda: fk.simulate(fk.GMS(LAW, k=np.full(200, 1e3), xi=np.full(200, 1 / 200), C=20.0),
                                                  position=1e-5 * np.sin(np.linspace(0, 20, 20001)), dt=1e-4),
        expect="ok", timeout=150)
    lib("O:batch-5000-sets", lambda: fk.simulate_batch([lg] * 5000, masses=1.0, force=np.sin(np.linspace(0, 6, 2001)),
                                                       dt=1e-3, target=np.zeros(2001), compare="v"),
        expect="ok", timeout=150)
    lib("O:fit-static-1e6", lambda: fk.fit_static_map(np.r_[np.geomspace(1e-4, 0.2, 500_000),
                                                            -np.geomspace(1e-4, 0.2, 500_000)],
                                                      LAW.steady_state(np.r_[np.geomspace(1e-4, 0.2, 500_000),
                                                                             -np.geomspace(1e-4, 0.2, 500_000)]),
                                                      model="coulomb_viscous"), expect="ok", timeout=150)
    lib("O:derivative-1e7", lambda: fk.derivative(np.zeros(10_000_000), 1e-3), expect="ok")
    lib("O:find-plateaus-5e6", lambda: fk.find_plateaus(np.repeat([0.01, 0.02, -0.01], 1_666_667), 1e-3),
        expect="ok", timeout=150)
    tb = np.arange(big) * 1e-4
    write_csv(W / "big.csv", t=tb, x=1e-5 * np.sin(tb), u=np.sin(tb))
    add("O:cli-simulate-big-csv", ["simulate", lug, "--position", W / "big.csv", "--column", "x", "--json",
                                   W / "o_big.json"], expect="ok", timeout=200)
    add("O:cli-export-points-1e7", ["export", lug, "--format", "csv", "--out", W / "o_big.csv", "--points",
                                    "10000001"], expect="either", cause=["--points"], timeout=200)
    # ---- P: empty and half-finished folders for the fleet verbs ------------------------------------
    for sub in ("empty", "only_toml", "only_dirs", "zero_files", "unfinished"):
        (W / f"fl_{sub}").mkdir(exist_ok=True)
    (W / "fl_only_toml" / "fleet.toml").write_text(
        __import__("frictionkit.fleet.simulate", fromlist=["x"]).fleet_config_toml())
    (W / "fl_only_dirs" / "axis-0001").mkdir()
    (W / "fl_zero_files" / "axis-0001").mkdir()
    (W / "fl_zero_files" / "axis-0001" / "2026-01-05.csv").write_bytes(b"")
    (W / "fl_unfinished" / "axis-0001").mkdir()
    (W / "fl_unfinished" / "axis-0001" / "2026-01-05.csv").write_bytes(raw)
    (W / "fl_unfinished" / "unfinished.json").write_text("{}")
    for sub in ("empty", "only_toml", "only_dirs", "zero_files", "unfinished"):
        add(f"P-identify:{sub}", ["fleet", "identify", W / f"fl_{sub}", "--out", W / f"o_p_{sub}.parquet", "--workers",
                                  "0", "--no-progress"], expect="error",
            cause=[f"fl_{sub}", "log", "file", "fleet.toml", "config"], timeout=120)
    import pandas as pd
    pd.DataFrame({"axis": pd.Series([], dtype=str)}).to_parquet(W / "p_empty.parquet")
    (W / "p_zero.parquet").write_bytes(b"")
    for name in ("p_empty.parquet", "p_zero.parquet"):
        add(f"P-monitor:{name}", ["fleet", "monitor", W / name], expect="error", cause=[name, "row", "column", "empty"])
        add(f"P-report:{name}", ["fleet", "report", W / name, "--out", W / "o_p.html"], expect="error",
            cause=[name, "row", "column", "empty"])
    add("P-identify:glob-empty-dir", ["fleet", "identify", str(W / "fl_empty" / "*" / "*.csv"), "--out",
                                      W / "o_p_glob.parquet", "--workers", "0"], expect="error",
        cause=["match", "file", "glob"])
    add("P-simulate:into-unfinished", ["fleet", "simulate", "--axes", "1", "--days", "1", "--out",
                                       W / "fl_unfinished"], expect="ok", timeout=120)
    # ---- Q: locales and encodings ------------------------------------------------------------------
    dec = "t_s;v_ms;F_N\n" + "\n".join(l.replace(",", ";").replace(".", ",") for l in raw.decode().splitlines()[1:])
    (W / "decimal_comma.csv").write_text(dec)
    for env_name, env in (("LC_ALL=C", {"LC_ALL": "C", "LANG": "C"}), ("LC_ALL=POSIX", {"LC_ALL": "POSIX"}),
                          ("PYTHONIOENCODING=ascii", {"PYTHONIOENCODING": "ascii"}),
                          ("LANG=de_DE", {"LC_ALL": "de_DE.UTF-8", "LANG": "de_DE.UTF-8"}),
                          ("PYTHONUTF8=0+C", {"PYTHONUTF8": "0", "LC_ALL": "C", "PYTHONCOERCECLOCALE": "0"}),
                          ("COLUMNS=20", {"COLUMNS": "20"}), ("TERM=dumb", {"TERM": "dumb", "NO_COLOR": "1"})):
        umlaut = W / names["umlaut"]
        C.append({"id": f"Q:{env_name}:static-ok", "kind": "sub", "env": env, "expect": "ok",
                  "argv": static + ["--json", W / "o_q.json"]})
        C.append({"id": f"Q:{env_name}:unicode-path-error", "kind": "sub", "env": env, "expect": "error",
                  "cause": ["nope", "column"], "argv": ["identify", "static", umlaut, "--time", "t_s", "--velocity",
                                                        "nope", "--force", "F_N"]})
        C.append({"id": f"Q:{env_name}:decimal-comma", "kind": "sub", "env": env, "expect": "either",
                  "cause": ["decimal_comma", "column", "comma", "number"],
                  "argv": ["identify", "static", W / "decimal_comma.csv", "--time", "t_s", "--velocity", "v_ms",
                           "--force", "F_N", "--model", "coulomb_viscous"]})
        C.append({"id": f"Q:{env_name}:export-unicode-name", "kind": "sub", "env": env, "expect": "either",
                  "cause": ["--name", "name ="], "argv": ["export", lug, "--format", "c", "--out", W / "o_q.h", "--name",
                                                "reibung_ä"]})
        C.append({"id": f"Q:{env_name}:help", "kind": "sub", "env": env, "expect": "ok", "argv": ["identify", "static",
                                                                                                   "--help"]})
    # ---- R: concurrent fleet writers -----------------------------------------------------------------
    def fleet_ok(folder, n):
        def check():
            got = sorted(p.name for p in (W / folder).rglob("*.*") if p.suffix in (".csv", ".parquet")
                         and p.parent.name.startswith("axis-"))
            bad = [] if len(got) == n and (W / folder / "fleet.toml").exists() else [f"{len(got)} logs of {n}"]
            left = [str(p) for p in (W / folder).rglob("*") if p.name.endswith(".tmp") or p.name.startswith(".fk-")]
            broken = set((W / folder / "broken.txt").read_text().split()) if (W / folder / "broken.txt").exists() else set()
            try:  # every log but the deliberately broken ones (broken.txt) reads
                import pandas as pd

                for p in sorted((W / folder).glob("axis-*/*.*")):
                    if p.relative_to(W / folder).as_posix() not in broken:
                        pd.read_parquet(p) if p.suffix == ".parquet" else pd.read_csv(p)
            except Exception as e:  # noqa: BLE001
                bad.append(f"unreadable: {e}")
            return "; ".join(bad + left)
        return check

    C.append({"id": "R:fleet-simulate-x2-same-out", "kind": "sub", "concurrent": 2, "expect": "ok", "timeout": 200,
              "argv": ["fleet", "simulate", "--axes", "2", "--days", "2", "--out", W / "fl_conc", "--seed", "1"],
              "after": fleet_ok("fl_conc", 4)})
    C.append({"id": "R:fleet-simulate-x3-same-out", "kind": "sub", "concurrent": 3, "expect": "ok", "timeout": 300,
              "argv": ["fleet", "simulate", "--axes", "2", "--days", "1", "--out", W / "fl_conc3", "--seed", "2",
                       "--json", W / "o_conc3.json"], "after": fleet_ok("fl_conc3", 2)})

    def parquet_ok(path):
        def check():
            try:
                import pandas as pd

                pd.read_parquet(path)
                return ""
            except Exception as e:  # noqa: BLE001
                return f"{path}: {e}"
        return check

    C.append({"id": "R:fleet-identify-x2-same-out", "kind": "sub", "concurrent": 2, "expect": "ok", "timeout": 300,
              "argv": ["fleet", "identify", W / "fl_conc", "--out", W / "o_conc.parquet", "--workers", "0",
                       "--no-progress"], "after": parquet_ok(W / "o_conc.parquet")})
    # ---- I (round 11): Ctrl-C in fleet simulate, then the same command (resumes) ------------------------
    C.append({"id": "I11:sigint-fleet-simulate-4s", "kind": "sig", "after": 4.0,
              "argv": ["fleet", "simulate", "--axes", "20", "--days", "20", "--out", W / "fl_int", "--json",
                       W / "o_fl_int.json"], "outputs_absent": [W / "o_fl_int.json", W / "fl_int" / "fleet.toml"]})
    C.append({"id": "I11:fleet-simulate-again-resumes", "kind": "sub", "expect": "ok", "timeout": 600,
              "argv": ["fleet", "simulate", "--axes", "20", "--days", "20", "--out", W / "fl_int"],
              "after": fleet_ok("fl_int", 400)})
    # ---- S: --help of every verb ---------------------------------------------------------------------
    import typer

    def walk(c, path):
        yield path
        for name, sub in sorted(getattr(c, "commands", {}).items()):
            yield from walk(sub, path + [name])

    for path in walk(typer.main.get_command(app), []):
        add(f"S-help:{' '.join(path) or 'top'}", path + ["--help"], expect="ok")
        add(f"S-help-h:{' '.join(path) or 'top'}", path + ["-h"], expect="either", cause=["-h", "no such option"])
        if path:
            add(f"S-bare:{' '.join(path)}", path, expect="either", cause=None)
    # ---- T: every public entry point with a wrong type in each argument -------------------------------
    import inspect

    x = 20e-6 * np.sin(np.linspace(0, 6, 500))
    rec = fk.load_recording(W / "stairs.csv", time="t_s", velocity="v_ms", force="F_N")
    gm = fk.load_recording(W / "gms.csv", time="t_s", position="x_m", force="F_N")
    m = fk.load_model(W / "emps.json")
    valid = {
        "GMS": dict(static=LAW, k=[1e4], xi=[1.0], C=20.0), "CoulombViscous": dict(Fc=1.0, sigma2=0.4),
        "Dahl": dict(Fc=1.0, sigma0=1e5, sigma2=0.0), "Directional": dict(positive=LAW, negative=LAW),
        "LuGre": dict(static=LAW, sigma0=1e5, sigma1=30.0), "Mass": dict(m=1.0), "Machine": dict(name="m"),
        "simulate_machine": dict(machine=m, dt=1e-3, inputs={"qg": np.zeros(50)}, n_samples=50),
        "RigidBallScrew": dict(), "RigidBody": dict(M=1.0, friction=LAW, offset=0.0),
        "Recording": dict(t=np.arange(5.0), x=np.zeros(5), v=np.zeros(5), F=np.zeros(5), name="r"),
        "decimate": dict(y=np.arange(100.0), q=2), "derivative": dict(y=np.arange(100.0), dt=1e-3),
        "find_cycles": dict(x=x, dt=1e-3), "find_plateaus": dict(v=rec.v, dt=1e-3),
        "find_reversals": dict(v=np.sin(np.linspace(0, 9, 100))),
        "fit_presliding": dict(data=gm, elements=2, static=LAW, polish=False),
        "fit_static_map": dict(v=np.r_[np.geomspace(1e-3, 0.1, 12), -np.geomspace(1e-3, 0.1, 12)],
                               F=LAW.steady_state(np.r_[np.geomspace(1e-3, 0.1, 12), -np.geomspace(1e-3, 0.1, 12)]),
                               model="coulomb_viscous"),
        "fit_static_records": dict(records=[rec], model="coulomb_viscous"),
        "load_csv": dict(path=W / "stairs.csv", time="t_s", velocity="v_ms", force="F_N"),
        "load_recording": dict(path=W / "stairs.csv", time="t_s", velocity="v_ms", force="F_N"),
        "load_groups": dict(path=W / "stairs.csv", group="t_s", time="t_s"),
        "lowpass": dict(y=np.arange(100.0), fs=1000.0, cutoff=50.0),
        "SimOptions": dict(rtol=1e-5), "simulate": dict(model=lg, dt=1e-3, position=x),
        "simulate_batch": dict(models=[lg, lg], masses=1.0, force=np.sin(np.linspace(0, 6, 200)), dt=1e-3,
                               target=np.zeros(200), compare="v"),
        "ModelFile": dict(model=lg), "load_model": dict(path=W / "lugre.json"),
        "save_model": dict(model=lg, path=W / "o_t.json"),
        "Stribeck": dict(Fc=1.0, Fs=1.5, vs=1e-3), "TDMSSC": dict(Fc0=1.0, Fs0=1.5, vs=1e-3),
        "coulomb_compensation": dict(v=np.ones(3), F0=1.0), "sigmoid_compensation": dict(x=np.ones(3), F0=1.0, sigma=2e-6),
        "sinc_compensation": dict(x=np.ones(3), F0=1.0, xs=2e-6),
    }
    wrong = (("str", "abc"), ("object", object()), ("None", None), ("nan-list", [float("nan")]))
    for name, kw in valid.items():
        f = getattr(fk, name)
        sig = inspect.signature(f)
        for pname, prm in sig.parameters.items():
            if prm.kind in (prm.VAR_KEYWORD, prm.VAR_POSITIONAL):
                continue
            ann = str(prm.annotation)
            for wname, wval in wrong:
                if wval is None and prm.default is None:
                    continue  # None is this argument's documented "not given"
                legal = ((wname == "str" and any(w in ann for w in ("str", "Path", "Any", "object")))
                         or (wname == "None" and "None" in ann) or (wname == "object" and ann in ("Any", "object")))
                args = {**kw, pname: wval}
                if "path" in args and pname != "path" and name == "save_model":
                    args["path"] = W / f"o_t_{pname}_{wname}.json"

                def call(f=f, args=args):
                    pos = [args.pop(k) for k, p in list(inspect.signature(f).parameters.items())
                           if p.kind == p.POSITIONAL_ONLY and k in args]
                    return f(*pos, **args)

                lib(f"T:{name}({pname}={wname})", call, expect="either" if legal else "error", timeout=60)
    for c in L:
        C.append(c)
    return C


def main():
    out = Path(sys.argv[1]) if len(sys.argv) > 1 and not sys.argv[1].startswith("--") else Path("robustness_campaign.json")
    only = sys.argv[sys.argv.index("--only") + 1] if "--only" in sys.argv else None
    rounds = sys.argv[sys.argv.index("--rounds") + 1].split(",") if "--rounds" in sys.argv else ["10", "11"]
    setup()
    os.chdir(W)
    allc = (cases() if "10" in rounds else []) + (cases11() if "11" in rounds else [])
    rows = []
    t_all = time.perf_counter()
    for c in allc:
        if only and not c["id"].startswith(tuple(only.split(","))):  # --only K-,T: (comma-separated prefixes)
            continue
        try:
            fn = {"cli": run_cli, "lib": run_lib, "sig": run_sig, "sub": run_sub}[c["kind"]]
            cls, msg, code, el = fn(c)
        except Exception as e:  # noqa: BLE001  (the campaign's own fault)
            cls, msg, code, el = "campaign-fault", f"{type(e).__name__}: {e} {traceback.format_exc()[-300:]}", None, 0
        rows.append({"id": c["id"], "class": cls, "code": code, "msg": msg[:400], "s": round(el, 2)})
        print(f"{cls:18s} {el:6.1f}s {c['id'][:70]:70s} {msg[:160]!r}", flush=True)
    counts = {}
    for r in rows:
        counts[r["class"]] = counts.get(r["class"], 0) + 1
    print(json.dumps(counts, indent=1), f"{len(rows)} cases in {time.perf_counter() - t_all:.0f} s")
    out.write_text(json.dumps({"counts": counts, "rows": rows}, indent=1))
    os.system(f"chmod -R u+w {W}")


if __name__ == "__main__":
    main()
