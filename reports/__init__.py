"""Reports: report.json, mesh export and (loaded only when asked) pyvista images and report.html."""
from .report import build_report

__all__ = ["build_report"]
