"""The bundled controllers' rows (mazegen/controllers.py) against the kernels: each kernel reads its
parameters and the robot's limits at the positions the row and LIMITS give, reads what the row says,
and the episode loop gives each controller the slot of its code; the limits arrays follow LIMITS."""

from __future__ import annotations

import ast
import importlib
import inspect
import re
import textwrap
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

from mazegen.controllers import BUNDLED, BY_CODE, COSTMAP, FIELDS, LIDAR, LIMITS, PATH, BundledController
from mazegen.runtime.simulation import _controllers, _loop, drive
from mazegen.runtime.simulation._state import robot_limits
from mazegen.spec import Arena, robot_for
from tests.runtime.floors import population

ROWS = BY_CODE
READS = {
    LIDAR: {"scan", "angles"},
    PATH: {"path"},
    FIELDS: {"nav", "clear", "grid"},
    COSTMAP: {"nav", "clear", "grid"},
}
"""What each kind of input is called among a controller kernel's arguments (the two kinds of map,
MazeGen's fields and move_base's costmap, in the same three)."""


def _kernel(row: BundledController) -> tuple[ModuleType, dict[str, ast.FunctionDef], str]:
    """The module of ``row``'s kernel, its functions' definitions, and the kernel's name."""
    module_name, function = row.kernel.split(".")
    module = importlib.import_module(f"mazegen.runtime.simulation.{module_name}")
    return module, _functions(module), function


def _functions(module: ModuleType) -> dict[str, ast.FunctionDef]:
    tree = ast.parse(inspect.getsource(module))
    return {node.name: node for node in tree.body if isinstance(node, ast.FunctionDef)}


def _subscripts(row: BundledController, array: str) -> set[tuple[ModuleType, str]]:
    """Every index ``row``'s kernel reads ``array`` at, with the module it is read in: in its body and
    in the functions it hands ``array`` to, of its module or of the simulation modules it imports
    them from."""
    module, _, kernel = _kernel(row)
    found: set[tuple[ModuleType, str]] = set()
    todo, seen = [(module, kernel)], {(module.__name__, kernel)}
    while todo:
        where, name = todo.pop()
        functions = _functions(where)
        for node in ast.walk(functions[name]):
            if isinstance(node, ast.Subscript) and _is_name(node.value, array):
                found.add((where, ast.unparse(node.slice)))
            elif isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
                callee, home = node.func.id, where
                if callee not in functions:  # imported from another simulation module?
                    home = inspect.getmodule(getattr(where, callee, None)) or where
                    if not home.__name__.startswith("mazegen.runtime.simulation."):
                        continue
                handed = any(_is_name(a, array) for a in node.args)
                if handed and (home.__name__, callee) not in seen and callee in _functions(home):
                    todo.append((home, callee))
                    seen.add((home.__name__, callee))
    return found


def _is_name(node: ast.expr, name: str) -> bool:
    return isinstance(node, ast.Name) and node.id == name


def test_the_rows_codes_number_the_controllers_from_zero():
    assert [row.code for row in ROWS] == list(range(len(BUNDLED)))
    assert all(name == row.name for name, row in BUNDLED.items())


@pytest.mark.parametrize("row", ROWS, ids=lambda row: row.name)
def test_each_kernel_reads_its_parameters_where_its_row_puts_them(row):
    read = _subscripts(row, "params")
    names = [p.name for p in row.parameters]
    assert {index.lower() for _, index in read} <= set(names)  # by named constants, never a bare number
    for module, index in read:
        assert getattr(module, index) == row.index(index.lower()), (module.__name__, index)
    # every parameter is read: by the kernel, or by the drive (the path's margin)
    assert {index.lower() for _, index in read} | {row.margin} - {None} == set(names)


@pytest.mark.parametrize("row", ROWS, ids=lambda row: row.name)
def test_each_kernel_reads_the_limits_and_inputs_its_row_names(row):
    _, functions, kernel = _kernel(row)
    read = _subscripts(row, "limits")
    assert {index.lower() for _, index in read} == set(row.limits)
    for module, index in read:
        assert getattr(module, index) == LIMITS.index(index.lower()), index
    used = {node.id for node in ast.walk(functions[kernel]) if isinstance(node, ast.Name)}
    inputs = set().union(*READS.values())
    assert used & inputs == set().union(*(READS[kind] for kind in row.reads))
    assert not {FIELDS, COSTMAP} <= row.reads  # one kind of map: they share the arguments


def test_the_limits_constants_follow_limits():
    for index, name in enumerate(LIMITS):
        assert getattr(_controllers, name.upper()) == index


def test_the_episode_loop_gives_each_controller_the_slot_of_its_code():
    command, run_all = (_definition(kernel.py_func) for kernel in (_loop.command, _loop.run_all))
    names = [row.name for row in ROWS]
    assert [a.arg for a in command.args.args[: len(ROWS)]] == names
    assert [a.arg for a in run_all.args.args[2 : 2 + len(ROWS)]] == names  # after (first, last)
    branch: ast.stmt = command.body[1]  # after the docstring: if slot 0 … elif slot 1 …
    for row in ROWS:
        assert isinstance(branch, ast.If) and ast.unparse(branch.test) == f"{row.name} is not None"
        call = branch.body[0]
        assert isinstance(call, ast.Expr) and isinstance(call.value, ast.Call)
        module, _, kernel = _kernel(row)
        assert ast.unparse(call.value.func) == kernel and getattr(_loop, kernel) is getattr(module, kernel)
        branch = branch.orelse[0]
    params = np.zeros(3)
    for row in ROWS:
        slots = _loop.controller_slots(row.code, params)
        assert [slot is params for slot in slots] == [other is row for other in ROWS]


def _definition(function) -> ast.FunctionDef:
    definition = ast.parse(textwrap.dedent(inspect.getsource(function))).body[0]
    assert isinstance(definition, ast.FunctionDef)
    return definition


def test_limits_arrays_are_built_in_limits_order():
    arena = Arena("limits", 1000, 600, "cm", (100, 100), (900, 500), 17, 10)
    changes = {"max_speed": 11, "min_speed": 2, "max_turn": 3, "accel": 40, "turn_accel": 50, "step": 0.25}
    robot = robot_for(arena, goal_tolerance=30, footprint=(51, 43), **changes)
    expected = changes | {"radius": 17, "goal_tolerance": 30, "length": 51, "width": 43}
    assert dict(zip(LIMITS, robot_limits(robot, arena), strict=True)) == expected
    seen = []

    def stand_still(observations):
        seen.append(observations.limits)
        return np.zeros((observations.floor.size, 2))

    drive(population(arena, [[]]), robot=robot, controller=stand_still)
    assert dict(zip(LIMITS, seen[0], strict=True)) == expected  # what a policy is shown


@pytest.mark.parametrize("name", list(BUNDLED))
def test_the_docs_table_of_a_controller_is_its_row(name):
    """docs/simulation.md lists each parameter as the row has it: in order, default, unit, source."""
    page = (Path(__file__).resolve().parents[3] / "docs" / "simulation.md").read_text(encoding="utf-8")
    section = re.search(rf"^###[^\n]*`{name}`[^\n]*\n(.*?)(?=^### |^## )", page, re.S | re.M)
    assert section is not None, f"docs/simulation.md has no section on {name}"
    rows = [
        [cell.strip() for cell in line.split("|")[1:-1]]
        for line in section.group(1).splitlines()
        if re.match(r"^\| `\w+` \|", line)
    ]
    written = [(cells[0].strip("`"), float(cells[1]), cells[2], cells[4].replace("`", "")) for cells in rows]
    assert written == [(p.name, p.default, p.unit, p.source) for p in BUNDLED[name].parameters]
