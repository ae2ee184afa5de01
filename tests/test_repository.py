"""House-keeping of the checkout: what git ignores, and what the tests hand pytest."""

from __future__ import annotations

import ast
import re

import click

from mazegen.cli.main import COMMANDS, main
from tests.conftest import ROOT

DEFAULT_FOLDER = re.compile(r"\(default (\w+)/<")
"""An ``-o`` help naming a folder of the working directory that a command writes by default."""


def test_git_ignores_every_folder_a_command_writes_by_default():
    context = click.Context(main)
    folders = set()
    for name in COMMANDS:
        command = main.get_command(context, name)
        assert command is not None
        for parameter in command.params:
            found = DEFAULT_FOLDER.search(getattr(parameter, "help", None) or "")
            if parameter.name == "out" and found:
                folders.add(found[1])
    assert folders >= {"build", "runs", "suites", "sweeps"}
    ignored = set((ROOT / ".gitignore").read_text(encoding="utf-8").splitlines())
    assert {f"/{folder}/" for folder in folders} <= ignored


ITERATORS = {"product", "permutations", "combinations", "chain", "map", "filter", "zip", "iter", "reversed"}
"""Calls that give a one-shot iterator: pytest 9.1 warns when ``parametrize`` gets one, pytest 10
refuses it (it wants a collection, which it may read more than once)."""


def _iterator_call(node: ast.expr) -> bool:
    if isinstance(node, ast.GeneratorExp):
        return True
    if not isinstance(node, ast.Call):
        return False
    function = node.func
    name = function.attr if isinstance(function, ast.Attribute) else getattr(function, "id", "")
    return name in ITERATORS


def test_parametrize_is_given_collections_not_iterators():
    found = []
    for path in sorted((ROOT / "tests").rglob("test_*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            is_parametrize = (
                isinstance(node, ast.Call)
                and isinstance(node.func, ast.Attribute)
                and node.func.attr == "parametrize"
            )
            if is_parametrize and len(node.args) > 1 and _iterator_call(node.args[1]):
                found.append(f"{path.relative_to(ROOT)}:{node.lineno}")
    assert found == []
