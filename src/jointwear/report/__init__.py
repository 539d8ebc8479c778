"""jointwear.report: one figure style for the whole project, figure functions over plain data, and the
self-contained HTML report of a study (``build_report(out_dir)``)."""

from .html import build_report

__all__ = ["build_report"]
