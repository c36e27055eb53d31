"""A reusable report: sections collected from results, rendered as ONE self-contained HTML page.

A :class:`Report` holds :class:`Section` s (a title, paragraphs, tables, figures as PNG
bytes, links to files beside the page). Sections come from code (the demo builds its own),
from result objects (:meth:`Report.add_result`) or from result files
(:meth:`Report.add_file`) through the adapters of :mod:`frictionkit.report.adapters`
(identification results, model files and laws, reproductions, compensation, fleet and
study tables, simulated traces).

The page embeds every figure as a base64 PNG and carries its style inline: no external
asset, no script, nothing fetched. Every title, paragraph, table cell and link label is
HTML-escaped. The page (and the text digest) are written with the package's atomic writer
(:mod:`frictionkit._io`), never over an input.

Examples
--------
>>> from frictionkit.report import Report, Section
>>> rep = Report("my axis")
>>> _ = rep.add(Section("Notes", text=["Friction measured on 2026-11-23."], table=[["a", "b"], ["1", "<2>"]]))
>>> "&lt;2&gt;" in rep.html()
True
>>> rep.add_file("fit.json")  # doctest: +SKIP
>>> rep.add_result(fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3), sigma0=1e5, sigma1=63.2))  # doctest: +SKIP
>>> rep.write("out/")  # doctest: +SKIP
PosixPath('out/report.html')
"""

from __future__ import annotations

import base64
import html
import io
import os
from collections.abc import Iterable
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

from ..errors import ParameterError

__all__ = ["Report", "Section", "figure_png"]

#: Cell texts drawn in colour (exact match) in the verdict columns (by header) of a table.
_MARKS = {"holds": "ok", "does not hold": "bad", "flagged": "bad", "failed": "bad"}
_MARK_COLUMNS = {"verdict", "identifiable", "interval holds truth", "status"}

_CSS = (
    "body{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222;line-height:1.4}"
    "h1{margin-bottom:.2em}h2{border-bottom:1px solid #ddd;margin-top:2em}h3{margin-bottom:.3em}"
    ".src{color:#666;font-size:13px;margin-top:-.6em}"
    ".tw{overflow-x:auto}table{border-collapse:collapse;margin:.6em 0 1em}"
    "td,th{border:1px solid #ccc;padding:4px 8px;font-size:14px;vertical-align:top;text-align:left}"
    "th{background:#f3f3f3}td.ok{background:#e6f4e6}td.bad{background:#fbe3e3}"
    "caption{text-align:left;font-weight:600;padding:.2em 0}"
    "img{max-width:100%;border:1px solid #eee;margin:.5em 0;display:block}"
    "nav ol{columns:2;font-size:14px}code{background:#f5f5f5;padding:0 .2em}"
)


def figure_png(fig: Any, *, dpi: int = 110, close: bool = True) -> bytes:
    """A matplotlib figure as PNG bytes (closed afterwards unless ``close=False``)."""
    buf = io.BytesIO()
    try:
        fig.savefig(buf, format="png", dpi=dpi)
    finally:
        if close:
            import matplotlib.pyplot as plt

            plt.close(fig)
    return buf.getvalue()


@dataclass
class Section:
    """One part of a report.

    Parameters
    ----------
    title : str
        Heading.
    text : list of str
        Paragraphs (plain text; escaped when rendered).
    figures : list of (str, bytes)
        ``(file name, PNG bytes)``; embedded in the page (the name is the image's alt text
        and, for the demo, the file written beside the page).
    table : list of list of str, optional
        The main table; its first row is the header.
    tables : list of (str, list of list of str)
        Further tables with a caption each (first row the header).
    links : list of (str, str)
        ``(file beside the page, label)``.
    kind, source : str
        What produced the section (``"static_map"``, ``"study"`` ...) and the file it was read from.
    """

    title: str
    text: list[str] = field(default_factory=list)
    figures: list[tuple[str, bytes]] = field(default_factory=list)
    table: list[list[str]] | None = None
    tables: list[tuple[str, list[list[str]]]] = field(default_factory=list)
    links: list[tuple[str, str]] = field(default_factory=list)
    kind: str = ""
    source: str = ""

    def all_tables(self) -> list[tuple[str, list[list[str]]]]:
        """The main table (caption ``""``) then the captioned ones; empty tables left out."""
        out = [("", self.table)] if self.table else []
        return out + [(c, t) for c, t in self.tables if t]

    def add_figure(self, name: str, fig: Any, *, dpi: int = 110) -> None:
        """Append a matplotlib figure (as PNG; the figure is closed)."""
        self.figures.append((name, figure_png(fig, dpi=dpi)))


def _esc(x: Any) -> str:
    return html.escape("" if x is None else str(x), quote=True)


def _table_html(caption: str, rows: list[list[str]]) -> str:
    head, body = rows[0], rows[1:]
    out = ["<div class='tw'><table>"]
    if caption:
        out.append(f"<caption>{_esc(caption)}</caption>")
    out.append("<tr>" + "".join(f"<th>{_esc(h)}</th>" for h in head) + "</tr>")
    marked = [str(h) in _MARK_COLUMNS for h in head]
    for row in body:
        cells = []
        for j, c in enumerate(row):
            cls = _MARKS.get(str(c)) if j < len(marked) and marked[j] else None
            cells.append(f"<td class='{cls}'>{_esc(c)}</td>" if cls else f"<td>{_esc(c)}</td>")
        out.append("<tr>" + "".join(cells) + "</tr>")
    out.append("</table></div>")
    return "\n".join(out)


class Report:
    """Sections rendered as one self-contained HTML page.

    Parameters
    ----------
    title : str
        The page's title and top heading.
    intro : iterable of str
        Paragraphs under the heading.
    """

    def __init__(self, title: str = "frictionkit report", intro: Iterable[str] = ()) -> None:
        if not isinstance(title, str) or not title.strip() or "\n" in title:
            raise ParameterError(f"Report.title = {title!r}: must be a non-empty one-line text")
        self.title = title
        self.intro = list(intro)
        self.sections: list[Section] = []
        self.inputs: list[dict[str, Any]] = []

    def add(self, *sections: Section | None) -> Report:
        """Append sections (None is skipped); returns the report."""
        for s in sections:
            if s is None:
                continue
            if not isinstance(s, Section):
                raise ParameterError(f"Report.add: {type(s).__name__} is not a Section")
            self.sections.append(s)
        return self

    def add_file(self, path: str | os.PathLike) -> list[Section]:
        """Read a result file through its adapter and append its sections.

        Raises
        ------
        DataError
            One line naming the file and why it cannot be read.
        """
        from .adapters import sections_from_file

        kind, secs = sections_from_file(path)
        self.add(*secs)
        self.inputs.append({"file": str(path), "kind": kind, "sections": [s.title for s in secs]})
        return secs

    def add_result(self, result: Any, *, name: str | None = None) -> list[Section]:
        """Append the sections of a result object in memory (see
        :func:`frictionkit.report.adapters.sections_from_result` for what it takes); ``name``
        labels the sections' source (default: the object's type)."""
        from .adapters import sections_from_result

        kind, secs = sections_from_result(result, name=name)
        self.add(*secs)
        self.inputs.append({"object": name or type(result).__name__, "kind": kind, "sections": [s.title for s in secs]})
        return secs

    # ------------------------------------------------------------------ rendering
    def html(self, *, footer: str | None = None) -> str:
        """The page as text (UTF-8, no external assets)."""
        when = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
        parts = ["<!doctype html><html lang='en'><head><meta charset='utf-8'>",
                 "<meta name='viewport' content='width=device-width, initial-scale=1'>",
                 f"<title>{_esc(self.title)}</title><style>{_CSS}</style></head><body>",
                 f"<h1>{_esc(self.title)}</h1>"]
        parts.extend(f"<p>{_esc(t)}</p>" for t in self.intro)
        if len(self.sections) > 2:
            parts.append("<nav><ol>" + "".join(f"<li><a href='#s{i}'>{_esc(s.title)}</a></li>"
                                               for i, s in enumerate(self.sections, 1)) + "</ol></nav>")
        for i, s in enumerate(self.sections, 1):
            parts.append(f"<section id='s{i}'><h2>{_esc(s.title)}</h2>")
            if s.source:
                parts.append(f"<p class='src'>from <code>{_esc(s.source)}</code></p>")
            parts.extend(f"<p>{_esc(t)}</p>" for t in s.text)
            for caption, rows in s.all_tables():
                parts.append(_table_html(caption, rows))
            for name, png in s.figures:
                parts.append(f"<img alt='{_esc(name)}' src='data:image/png;base64,{base64.b64encode(png).decode()}'>")
            for href, label in s.links:
                parts.append(f"<p><a href='{_esc(href)}'>{_esc(label)}</a></p>")
            parts.append("</section>")
        from .. import __version__

        parts.append(f"<hr><p class='src'>{_esc(footer or '')} Written by frictionkit {_esc(__version__)}, {when}.</p>")
        parts.append("</body></html>")
        return "\n".join(parts)

    def text(self, *, heading: str | None = None) -> str:
        """A plain-text digest: each section's title, paragraphs, links and tables."""
        lines = [heading or self.title, ""]
        for s in self.sections:
            lines.append(f"== {s.title}")
            lines.extend(s.text)
            lines.extend(f"{label}: {href}" for href, label in s.links)
            for caption, rows in s.all_tables():
                if caption:
                    lines.append(f"  [{caption}]")
                lines.extend("  " + " | ".join(str(c) for c in row) for row in rows)
            lines.append("")
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: title, inputs (file, kind, section titles), sections (title, kind, source, counts)."""
        return {"title": self.title, "inputs": list(self.inputs),
                "sections": [{"title": s.title, "kind": s.kind, "source": s.source, "figures": len(s.figures),
                              "tables": len(s.all_tables())} for s in self.sections]}

    def summary(self) -> str:
        """One line per section."""
        return "\n".join([f"{self.title}: {len(self.sections)} section(s)"]
                         + [f"  {s.title}" + (f" ({s.source})" if s.source else "") for s in self.sections])

    def write(self, out: str | os.PathLike, *, name: str = "report.html", footer: str | None = None,
              inputs: Iterable[str | os.PathLike] = ()) -> Path:
        """Write the page to ``out/name`` atomically (the folder is created); returns its path.

        Raises
        ------
        DataError
            The page would replace one of ``inputs`` (or of the files added by :meth:`add_file`).
        """
        from .._io import atomic_write_text, check_not_input

        folder = Path(out)
        target = folder / name
        check_not_input(target, [*inputs, *(i["file"] for i in self.inputs if "file" in i)], option="report")
        folder.mkdir(parents=True, exist_ok=True)
        return atomic_write_text(target, self.html(footer=footer))
