"""Stock: tool shapes, exact sweeps, batched manifold3d booleans; the part is measured in reports (reports/measure.py)."""
from .build import build_stock, stock_outline
from .removal import Removal, remove
from cutsim.base.specs import StockSpec, ToolSpec

__all__ = ["build_stock", "stock_outline", "remove", "Removal", "StockSpec", "ToolSpec"]
