"""The base layer (rank 0): plain data every stage may import and that imports no stage.

``specs``: what the setup says about the machine, the stock and the tools (``MachineSpec``,
``StockSpec``, ``ToolSpec``). Imports flow one way, base -> interp -> kinematics -> stock -> reports
-> the API (docs/architecture.md, "Layers and imports"; tests/test_imports.py checks it).
"""
