"""Reports: report.json, mesh export, the output transaction, and (loaded only when asked) pyvista images."""
from .output import write_outputs
from .report import build_report

__all__ = ["build_report", "write_outputs"]
