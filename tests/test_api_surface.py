"""The Python API the README advertises is reachable from the package itself."""

from __future__ import annotations

import mazegen
from mazegen import api


def test_the_readme_api_is_on_the_package():
    for name in ("load", "build", "run", "resume", "sweep"):
        assert getattr(mazegen, name) is getattr(api, name), name
        assert name in mazegen.__all__
