"""Plug-ins registered by installed packages, as ``mazegen.plugins`` finds and loads them."""

from importlib.metadata import EntryPoint

import pytest

from mazegen import plugins
from mazegen.errors import MazeError


def test_a_registered_plugin_is_found_with_its_package(register_plugins):
    register_plugins("metrics", {"dock_clearance": len})
    (found,) = [p for p in plugins.installed("metrics") if p.name == "dock_clearance"]
    assert found.origin == "fake-plugins 1.0"
    assert plugins.find("metrics", "dock_clearance").load() is len
    assert plugins.find("metrics", "no_such_metric") is None
    assert "dock_clearance" in plugins.names("metrics")


def test_a_name_two_packages_register_is_refused(register_plugins):
    register_plugins("exporters", {"webots": len})
    register_plugins("exporters", {"webots": abs})
    with pytest.raises(MazeError, match=r"'webots' is registered by more than one package"):
        plugins.find("exporters", "webots")


def test_a_plugin_that_fails_to_import_is_one_line(monkeypatch):
    broken = EntryPoint("broken", "no_such_module_anywhere:thing", plugins.GROUPS["metrics"])
    monkeypatch.setattr(plugins, "_entry_points", lambda kind: [broken] if kind == "metrics" else [])
    with pytest.raises(MazeError, match=r"metric plug-in 'broken' of .* fails to load .*ModuleNotFoundError"):
        plugins.find("metrics", "broken").load()
