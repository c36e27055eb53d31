"""The one place frictionkit writes result files: atomically, never over an input.

Every result file (JSON, plots, summaries, reports) goes through :func:`atomic_open`
(or its shorthands :func:`atomic_write_text` / :func:`atomic_write_bytes`): the data
go to a temporary file in the target's folder, are flushed and ``fsync``-ed, and the
temporary file is renamed over the target with :func:`os.replace`. A reader therefore
sees either the previous file or the complete new one — never a truncated file — and
when writing fails (full disk, interrupt, an exception in the writer) the temporary
file is removed and the previous file is left as it was.

:func:`check_output_file` / :func:`check_output_dir` validate output paths up front
(before any work is done) and :func:`check_not_input` refuses to write over one of a
command's input files.
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import stat
import tempfile
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import IO, Any

from .errors import DataError

__all__ = [
    "atomic_open",
    "atomic_write_bytes",
    "atomic_write_text",
    "check_not_input",
    "check_output_dir",
    "check_output_file",
    "plot_formats",
]


def _file_mode(target: Path) -> int:
    """Permission bits for the new file: those of the file it replaces, else 0o666 minus the umask."""
    try:
        return target.stat().st_mode & 0o7777
    except OSError:
        umask = os.umask(0)
        os.umask(umask)
        return 0o666 & ~umask


def _fsync_dir(folder: Path) -> None:
    """Make the rename durable (POSIX); best effort, silently skipped where unsupported."""
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def _named(exc: OSError, target: Path) -> OSError:
    """The same kind of OSError, naming the target instead of the temporary file."""
    if exc.errno is None:
        return OSError(f"cannot write '{target}': {exc}")
    return OSError(exc.errno, f"cannot write '{target}': {exc.strerror or exc}")


def missing_reason(p: str | os.PathLike) -> str:
    """Why an input path that does not exist is missing, in words: ``"not found"``, or for a symbolic
    link ``"a loop of symbolic links"`` / ``"a symbolic link to 'X', which does not exist"`` (both said
    "not found", pointing at the link's own name; issue 13 round 9)."""
    if os.path.islink(p):
        try:
            os.stat(p)
        except OSError as exc:
            if exc.errno == errno.ELOOP:
                return "a loop of symbolic links"
        return f"a symbolic link to '{os.readlink(p)}', which does not exist"
    return "not found"


#: Largest text input file (model, result, configuration JSON/TOML) read whole [bytes]: assumption — the largest
#: the package writes is an identification result with its fitted samples (EMPS rigid-body JSON 172 kB; a
#: 100,000-sample output-error fit ~10 MB); 256 MB is far beyond that and still fits in memory. ``/dev/zero``
#: as a model file read until memory ran out (issue 13 round 11).
MAX_TEXT_INPUT = 256 * 2**20


def check_regular_input(path: str | os.PathLike, where: str) -> None:
    """Refuse an input file that is no regular file or is too large to read whole, with a :class:`DataError`
    prefixed by ``where``: a FIFO (reading one blocked for ever: a model file named ``fifo.json`` hung the
    command, issue 13 round 11), a device (``/dev/zero`` read until memory ran out), a file beyond
    :data:`MAX_TEXT_INPUT`. A path that does not exist, a folder or a link loop is left to the caller's read
    (its own message)."""
    try:
        st = os.stat(path)
    except OSError:
        return
    if not stat.S_ISREG(st.st_mode) and not stat.S_ISDIR(st.st_mode):
        raise DataError(f"{where}: is not a regular file (a device, pipe or socket)")
    if st.st_size > MAX_TEXT_INPUT:
        raise DataError(f"{where}: {st.st_size / 2**20:.0f} MB, beyond the {MAX_TEXT_INPUT // 2**20} MB a "
                        "text input file may have; is it the right file?")


def read_input_bytes(path: str | os.PathLike, where: str, *, missing: str = "no such file",
                     expected: str = "a file") -> bytes:
    """The bytes of an input file read whole (a model file, a result, a TOML configuration); what is no
    regular file raises a :class:`DataError` prefixed by ``where`` (``"model file 'm.json'"``): missing, a
    symbolic link loop or to nothing, a folder, and what :func:`check_regular_input` refuses. ``missing``: the
    words for a path that does not exist (the callers' wording before this helper); ``expected``: what a folder
    given instead should have been (``"a JSON file"``)."""
    p = Path(path)
    if not os.path.lexists(p) or (os.path.islink(p) and not os.path.exists(p)):
        raise DataError(f"{where}: {missing if not os.path.islink(p) else missing_reason(p)}")
    if p.is_dir():
        raise DataError(f"{where}: is a folder, expected {expected}")
    check_regular_input(p, where)
    with open(p, "rb") as fh:  # a file growing while read: at most the limit (and one byte to notice)
        raw = fh.read(MAX_TEXT_INPUT + 1)
    if len(raw) > MAX_TEXT_INPUT:
        raise DataError(f"{where}: grew beyond {MAX_TEXT_INPUT // 2**20} MB while read")
    return raw


def _through_link(path: Path) -> Path:
    """The file a write to ``path`` means: ``path`` itself, or for a symbolic link the file it points to.

    Named decision (issue 13 round 8 leftover): renaming over a link replaced the link by a regular file and
    left its target stale (a dangling link ``--out`` became a plain file beside nothing). A write now goes
    through the link, as the shell's ``>`` and editors do: the target is replaced atomically and the link
    stays; a dangling link creates its target when the target's folder exists. A link loop is refused.
    """
    if not os.path.islink(path):
        return path
    try:
        os.stat(path)
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise OSError(errno.ELOOP, f"cannot write '{path}': a loop of symbolic links") from None
    return Path(os.path.realpath(path))


@contextlib.contextmanager
def atomic_open(path: str | os.PathLike, mode: str = "wb", *, encoding: str | None = None) -> Iterator[IO[Any]]:
    """Open a temporary file beside ``path``; on a clean exit it replaces ``path`` atomically.

    Parameters
    ----------
    path : path-like
        The file to (re)write. Its folder must exist.
    mode : {"wb", "w"}
        Binary or text.
    encoding : str, optional
        Text encoding (default UTF-8 for ``mode="w"``).

    Yields
    ------
    file object
        Write to it (``fig.savefig(f, format="png")``, ``df.to_parquet(f)``, ``f.write(...)``).

    Raises
    ------
    OSError
        Creating, writing, syncing or renaming failed; it names ``path``. The previous
        file at ``path`` is unchanged and no temporary file is left behind. Any other
        exception (or ``KeyboardInterrupt``) raised inside the block propagates with the
        same guarantee.

    Examples
    --------
    >>> from frictionkit._io import atomic_open
    >>> with atomic_open("fit.png") as f:  # doctest: +SKIP
    ...     fig.savefig(f, format="png")
    """
    if mode not in ("wb", "w"):
        raise ValueError(f"atomic_open: mode = {mode!r}: must be 'wb' or 'w'")
    target = _through_link(Path(path))
    folder = target.parent
    try:  # renaming over a device or pipe would replace it (as root: --json /dev/null deleted the device)
        st = os.stat(target)
    except OSError:
        st = None
    if st is not None and stat.S_ISDIR(st.st_mode):  # was reported as "a device, pipe or socket" (round 10)
        raise IsADirectoryError(errno.EISDIR, f"cannot write '{target}': it is a folder; give a file name")
    if st is not None and not stat.S_ISREG(st.st_mode):
        raise OSError(errno.EINVAL, f"cannot write '{target}': not a regular file (a device, pipe or socket); "
                                    "refusing to replace it")
    if st is not None and not os.access(target, os.W_OK):
        # the rename needs only the folder's permission: a file its owner made read-only was replaced (issue 13)
        raise PermissionError(errno.EACCES, f"cannot write '{target}': the file is read-only; refusing to replace "
                                            "it (make it writable or choose another path)")
    try:
        # the name's first 40 characters: the whole name + 14 exceeded NAME_MAX for names of 242-255 bytes
        fd, tmp = tempfile.mkstemp(dir=folder, prefix=f".{target.name[:40]}.", suffix=".tmp")
    except OSError as exc:
        raise _named(exc, target) from exc
    ok = False
    try:
        try:
            f = os.fdopen(fd, mode, encoding=(encoding or "utf-8") if mode == "w" else None)
        except BaseException:
            os.close(fd)
            raise
        with f:
            yield f
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, _file_mode(target))
        os.replace(tmp, target)
        ok = True
    except OSError as exc:
        raise _named(exc, target) from exc
    finally:
        if not ok:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
    _fsync_dir(folder)


def atomic_write_bytes(path: str | os.PathLike, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (see :func:`atomic_open`); returns the path."""
    with atomic_open(path, "wb") as f:
        f.write(data)
    return Path(path)


def atomic_write_text(path: str | os.PathLike, text: str, *, encoding: str = "utf-8") -> Path:
    """Write ``text`` to ``path`` atomically (see :func:`atomic_open`); returns the path."""
    with atomic_open(path, "w", encoding=encoding) as f:
        f.write(text)
    return Path(path)


# --------------------------------------------------------------------------- up-front checks
def _same_file(a: Path, b: Path) -> bool:
    try:
        if a.exists() and b.exists():
            return os.path.samefile(a, b)
    except OSError:
        pass
    return os.path.realpath(a) == os.path.realpath(b)


def check_not_input(out: str | os.PathLike, inputs: Iterable[str | os.PathLike | None], *,
                    option: str = "output") -> None:
    """Raise :class:`~frictionkit.DataError` if ``out`` is (a link to) one of ``inputs``.

    Examples
    --------
    >>> check_not_input("fit.json", ["run.csv"])  # fine
    >>> check_not_input("run.csv", ["run.csv"], option="--json")
    Traceback (most recent call last):
    ...
    frictionkit.errors.DataError: --json 'run.csv' is the input file 'run.csv': refusing to overwrite an input; choose another path
    """
    o = Path(out)
    for inp in inputs:
        if inp is None:
            continue
        if _same_file(o, Path(inp)):
            raise DataError(f"{option} '{out}' is the input file '{inp}': refusing to overwrite an input; "
                            "choose another path")


class DuplicateKeyError(ValueError):
    """A JSON object names the same key twice (see :func:`json_loads`)."""


def _unique_pairs(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            shown = json.dumps(value)[:40] if not isinstance(value, (dict, list)) else type(value).__name__
            raise DuplicateKeyError(f"key {key!r} appears twice in one object (values {json.dumps(out[key])[:40]} "
                                    f"and {shown}); a hand edit? keep one")
        out[key] = value
    return out


def json_loads(text: str | bytes) -> Any:
    """``json.loads`` for the package's input files (model files, results, tests): a key named twice in
    one object raises :class:`DuplicateKeyError` — plain ``json`` keeps the last silently, so an edited
    first copy was ignored without a word (issue 13 round 8: ``{"Fc": 1.0, "Fc": 5.0}`` ran with 5)."""
    return json.loads(text, object_pairs_hook=_unique_pairs)


def plot_formats() -> dict[str, str]:
    """File extensions matplotlib can write, mapped to their description."""
    from matplotlib.backend_bases import FigureCanvasBase

    return dict(FigureCanvasBase.get_supported_filetypes())


#: Why creating a file in an existing folder failed, in words (the system's own text for ENOENT,
#: "No such file or directory", read as if the folder were missing: /proc, issue 13).
_PROBE_REASONS = {
    errno.ENOENT: "it does not accept new files: a virtual file system such as /proc or /sys",
    errno.EROFS: "read-only file system",
    errno.EACCES: "permission denied",
    errno.EPERM: "operation not permitted (an immutable folder?)",
    errno.ENOSPC: "the disk is full",
    errno.EDQUOT: "disk quota exceeded",
}


def _probe_folder(folder: Path) -> str | None:
    """Create and remove a temporary file in ``folder`` (the way :func:`atomic_open` will write
    there); ``None`` when that works, else the reason.

    ``os.access`` alone answers for the permission bits, and for root it says yes to almost
    everything: an immutable folder, ``/sys``, a read-only bind mount then failed only when the
    result was written, after all the work (issue 13).
    """
    try:
        fd, name = tempfile.mkstemp(prefix=".fk-probe-", dir=folder)
    except OSError as exc:
        return _PROBE_REASONS.get(exc.errno, exc.strerror or type(exc).__name__)
    os.close(fd)
    with contextlib.suppress(OSError):
        os.unlink(name)
    return None


def _writable_folder(folder: Path, option: str, q: str) -> None:
    """``q``: the output as shown in messages, quoted (``'out.json'``, or with its link target)."""
    if not folder.exists():
        raise DataError(f"{option} {q}: folder '{folder}' does not exist")
    if not folder.is_dir():
        raise DataError(f"{option} {q}: '{folder}' is not a folder")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise DataError(f"{option} {q}: folder '{folder}' is not writable")
    why = _probe_folder(folder)
    if why is not None:
        raise DataError(f"{option} {q}: folder '{folder}' is not writable ({why})")


def _nearest_existing(folder: Path) -> Path:
    p = folder
    while not p.exists() and p != p.parent:
        p = p.parent
    return p


def check_output_file(path: str | os.PathLike, *, option: str, inputs: Iterable[str | os.PathLike | None] = (),
                      plot: bool = False, make_parents: bool = False) -> Path:
    """Validate a result-file path before any work is done; returns it as a :class:`~pathlib.Path`.

    Checks that the path is not a folder, that its folder exists (or, with
    ``make_parents``, can be created) and is writable, that it is none of ``inputs``,
    and with ``plot`` that its extension is one matplotlib can write.

    Raises
    ------
    DataError
        Naming ``option``, the path and what is wrong.
    """
    out = Path(path)
    if str(path) == "" or out.name in ("", ".", ".."):
        raise DataError(f"{option} '{path}': not a file name")
    if isinstance(path, str) and path.endswith(("/", os.sep)):  # Path('DIR/sub/') is 'DIR/sub': a file named 'sub'
        raise DataError(f"{option} '{path}' ends in '{path[-1]}', the name of a folder; give a file name")
    real, q = out, f"'{out}'"
    if os.path.islink(out):  # the write goes to the link's target (see _through_link): check that one
        try:
            real = _through_link(out)
        except OSError:
            raise DataError(f"{option} '{out}' is a loop of symbolic links; give a file name") from None
        q = f"'{out}' (a link to '{real}')"
    _check_name_length(real, option, q)  # before any stat: Path.is_dir raises on a name too long
    if real.is_dir():
        raise DataError(f"{option} {q} is a folder; give a file name")
    if real.exists() and not real.is_file():
        raise DataError(f"{option} {q} is not a regular file (a device, pipe or socket); give a file name")
    if real.is_file() and not os.access(real, os.W_OK):
        raise DataError(f"{option} {q}: the file is read-only; refusing to replace it (make it writable or "
                        "choose another path)")
    folder = real.parent
    if make_parents and not folder.exists() and real == out:
        base = _nearest_existing(folder)
        if not base.is_dir():
            raise DataError(f"{option} {q}: '{base}' is a file, not a folder")
        _writable_folder(base, option, q)
    else:
        _writable_folder(folder, option, q)
    check_not_input(out, inputs, option=option)
    if plot:
        _check_plot_extension(out, option)
    return out


def _check_name_length(path: Path, option: str, q: str) -> None:
    """A name longer than the file system takes failed only when the result was written, after the work
    (issue 13 round 9: a 304-byte --json name, "File name too long", exit 1)."""
    try:
        most = os.pathconf(path.parent, "PC_NAME_MAX")
    except (OSError, ValueError):
        return
    size = len(os.fsencode(path.name))
    if most > 0 and size > most:
        raise DataError(f"{option} {q}: the file name is {size} bytes; the file system takes at most {most}")


def _check_plot_extension(out: Path, option: str) -> None:
    ext = out.suffix.lower().lstrip(".")
    formats = plot_formats()
    if ext not in formats:
        known = ", ".join(f".{e}" for e in sorted(formats))
        what = f"extension '.{ext}' is not a plot format" if ext else "no file extension"
        raise DataError(f"{option} '{out}': {what}; use one of {known}")


def check_output_dir(path: str | os.PathLike, *, option: str, inputs: Iterable[str | os.PathLike | None] = ()) -> Path:
    """Validate an output folder (existing or to be created) before any work is done.

    Raises
    ------
    DataError
        The path is an existing file, lies under a file, is not writable, or is an input.
    """
    out = Path(path)
    if out.exists() and not out.is_dir():
        raise DataError(f"{option} '{out}' is an existing file, not a folder")
    if os.path.islink(out) and not out.exists():  # mkdir failed with "File exists" (round 10)
        raise DataError(f"{option} '{out}' is a link to '{os.readlink(out)}', which does not exist; create that "
                        "folder or give another")
    base = _nearest_existing(out)
    if not base.is_dir():
        raise DataError(f"{option} '{out}': '{base}' is a file, not a folder")
    if not os.access(base, os.W_OK | os.X_OK):
        raise DataError(f"{option} '{out}': folder '{base}' is not writable")
    why = _probe_folder(base)
    if why is not None:
        raise DataError(f"{option} '{out}': folder '{base}' is not writable ({why})")
    for inp in inputs:
        if inp is not None and _same_file(out, Path(inp)):
            raise DataError(f"{option} '{out}' is the input '{inp}'")
    return out
