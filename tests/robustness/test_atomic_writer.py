"""Fault injection for the one atomic writer (:mod:`frictionkit._io`).

Full disk (ENOSPC on write and on fsync), an exception or Ctrl-C in the middle of a
write, a real SIGINT to a writing process, and two processes writing the same path:
the file is always the old version or one complete new version, and no temporary
file is left behind.
"""

from __future__ import annotations

import errno
import hashlib
import json
import multiprocessing
import os
import signal
import subprocess
import sys
import time

import pytest

from frictionkit._io import atomic_open, atomic_write_bytes, atomic_write_text, check_not_input
from frictionkit.errors import DataError

OLD = '{"version": "old"}\n'


@pytest.fixture
def target(tmp_path):
    p = tmp_path / "result.json"
    p.write_text(OLD)
    return p


def _only(target):
    """The folder holds the target and nothing else (no temporary file)."""
    assert sorted(p.name for p in target.parent.iterdir()) == [target.name]


def test_writes_and_replaces(target):
    atomic_write_text(target, "new ✓")
    assert target.read_text(encoding="utf-8") == "new ✓"
    atomic_write_bytes(target, b"\x00\x01")
    assert target.read_bytes() == b"\x00\x01"
    _only(target)


def test_keeps_permissions_of_the_file_it_replaces(target):
    target.chmod(0o640)
    atomic_write_text(target, "new")
    assert target.stat().st_mode & 0o777 == 0o640


def test_new_file_gets_normal_permissions(tmp_path):
    umask = os.umask(0o022)
    try:
        atomic_write_text(tmp_path / "new.json", "{}")
    finally:
        os.umask(umask)
    assert (tmp_path / "new.json").stat().st_mode & 0o777 == 0o644


def _enospc(*a, **k):
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


def test_disk_full_on_fsync_keeps_the_old_file(target, monkeypatch):
    monkeypatch.setattr(os, "fsync", _enospc)
    with pytest.raises(OSError) as info:
        atomic_write_text(target, json.dumps({"version": "new", "pad": "x" * 100_000}))
    assert info.value.errno == errno.ENOSPC
    assert str(info.value) == f"[Errno 28] cannot write '{target}': No space left on device"
    monkeypatch.undo()
    assert target.read_text() == OLD
    _only(target)


def test_disk_full_half_way_through_the_write_keeps_the_old_file(target, monkeypatch):
    """The file object accepts part of the data, then the disk is full."""
    real_fdopen = os.fdopen

    class FillsUp:
        def __init__(self, f):
            self._f = f

        def write(self, data):
            self._f.write(data[: len(data) // 2])
            self._f.flush()
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

        def __getattr__(self, name):
            return getattr(self._f, name)

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            self._f.close()

    monkeypatch.setattr(os, "fdopen", lambda fd, *a, **k: FillsUp(real_fdopen(fd, *a, **k)))
    with pytest.raises(OSError) as info:
        atomic_write_bytes(target, b"n" * 1_000_000)
    monkeypatch.undo()
    assert info.value.errno == errno.ENOSPC and str(target) in str(info.value)
    assert target.read_text() == OLD
    _only(target)


def test_disk_full_when_the_temporary_file_is_created(target, monkeypatch):
    import tempfile

    monkeypatch.setattr(tempfile, "mkstemp", _enospc)
    with pytest.raises(OSError, match="cannot write .*No space left on device"):
        atomic_write_text(target, "new")
    monkeypatch.undo()
    assert target.read_text() == OLD
    _only(target)


@pytest.mark.parametrize("exc", [KeyboardInterrupt, RuntimeError, OSError])
def test_exception_in_the_middle_of_a_write_keeps_the_old_file(target, exc):
    with pytest.raises(exc):
        with atomic_open(target, "w") as f:
            f.write('{"version": "new", ')
            f.flush()
            raise exc()
    assert target.read_text() == OLD
    _only(target)


def test_failing_plot_keeps_the_old_plot(tmp_path):
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    png = tmp_path / "fit.png"
    png.write_bytes(b"old plot")
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    with pytest.raises(ValueError):
        with atomic_open(png) as f:
            fig.savefig(f, format="png")
            raise ValueError("the figure was fine, the caller failed afterwards")
    assert png.read_bytes() == b"old plot"
    with atomic_open(png) as f:
        fig.savefig(f, format="png")
    plt.close(fig)
    assert png.read_bytes()[:4] == b"\x89PNG"
    _only(png)


_SLOW_WRITER = """
import sys, time
from frictionkit._io import atomic_open
with atomic_open(sys.argv[1], "wb") as f:
    for i in range(2000):
        f.write(b"new " * 256)
        f.flush()
        if i == 10:
            print("writing", flush=True)
        time.sleep(0.01)
"""


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT to a child process")
def test_real_sigint_while_writing_keeps_the_old_file(target):
    # SIG_DFL in the child: a SIGINT ignored by the xdist worker (inherited) would let it finish
    # (seen once in a full -n 2 run: returncode 0); the same guard as test_cli_error_path's
    proc = subprocess.Popen([sys.executable, "-c", _SLOW_WRITER, str(target)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        assert proc.stdout.readline().strip() == "writing"
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode != 0 and "KeyboardInterrupt" in err
    assert target.read_text() == OLD
    _only(target)


# --------------------------------------------------------------------------- concurrent writers
def _payload(writer: int, i: int) -> bytes:
    body = (f"{writer}:{i}:" * 20_000).encode()  # ~160 kB, several write() calls
    return json.dumps({"writer": writer, "i": i, "sha": hashlib.sha256(body).hexdigest(),
                       "body": body.decode()}).encode()


def _write_many(path: str, writer: int, n: int, start) -> None:
    start.wait()
    for i in range(n):
        atomic_write_bytes(path, _payload(writer, i))


def _complete(raw: bytes) -> tuple[int, int]:
    d = json.loads(raw)
    assert hashlib.sha256(d["body"].encode()).hexdigest() == d["sha"]
    assert d["body"] == f"{d['writer']}:{d['i']}:" * 20_000
    return d["writer"], d["i"]


def test_two_processes_writing_the_same_path(tmp_path):
    target = tmp_path / "shared.json"
    target.write_bytes(_payload(0, -1))
    # fork starts the writers at once (spawn would spend seconds importing); both wait on one event
    ctx = multiprocessing.get_context("fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn")
    start = ctx.Event()
    procs = [ctx.Process(target=_write_many, args=(str(target), w, 10, start)) for w in (1, 2)]
    for p in procs:
        p.start()
    start.set()
    seen, reads = set(), 0
    deadline = time.monotonic() + 120
    while any(p.is_alive() for p in procs) and time.monotonic() < deadline:
        seen.add(_complete(target.read_bytes()))  # never a torn or mixed file
        reads += 1
    for p in procs:
        p.join(timeout=60)
        assert p.exitcode == 0
    last = _complete(target.read_bytes())
    assert last in {(1, 9), (2, 9)}
    assert reads > 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["shared.json"]


# --------------------------------------------------------------------------- inputs
def test_check_not_input_names_both(tmp_path):
    data = tmp_path / "run.csv"
    data.write_text("t,x\n")
    link = tmp_path / "link.csv"
    link.symlink_to(data)
    for out in (data, tmp_path / "." / "run.csv", link):
        with pytest.raises(DataError, match=f"--json '{out}' is the input file '{data}'"):
            check_not_input(out, [None, data], option="--json")
    check_not_input(tmp_path / "fit.json", [data])
