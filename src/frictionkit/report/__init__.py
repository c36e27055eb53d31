"""Reports: one self-contained HTML page from results (:class:`Report`, :class:`Section`), and the demo."""

from .builder import Report, Section, figure_png

__all__ = ["Report", "Section", "figure_png"]
