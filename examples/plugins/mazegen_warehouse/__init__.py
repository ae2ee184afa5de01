"""Warehouse plug-ins for MazeGen: what ``pyproject.toml`` registers under MazeGen's entry points.

- ``import warehouse`` in a spec: the element library :data:`LIBRARY`;
- ``metric dock_clearance(x=..., y=...)``: :func:`mazegen_warehouse.metrics.dock_clearance`;
- ``--controller cautious``: :func:`mazegen_warehouse.policies.cautious`;
- ``mazegen export --format layout-csv``: :func:`mazegen_warehouse.exporters.layout_csv`.
"""

from pathlib import Path

LIBRARY = Path(__file__).with_name("warehouse.maze")
"""The element library ``import warehouse`` reads."""
