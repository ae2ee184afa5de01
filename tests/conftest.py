"""Shared fixtures: paths to the examples and a helper to write specs."""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"


@pytest.fixture
def write_spec(tmp_path: Path):
    """Write ``text`` as a .maze file in a temporary directory and return its path."""

    def write(text: str, name: str = "spec.maze") -> Path:
        path = tmp_path / name
        path.write_text(text, encoding="utf-8")
        return path

    return write
