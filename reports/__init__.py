"""Reports: report.json, mesh export, and (loaded only when asked) pyvista images."""
from .report import build_report, write_outputs

__all__ = ["build_report", "write_outputs"]
