"""The rules that keep a first run's compiling short and the kernels fast (docs/architecture.md,
Compiling), checked on the sources: no parallel kernels, no literal constants given to kernels that are
not inlined, a Python wrapper for exactly the kernels Python calls, and kernels compiled without
reference counting calling only their like."""

from __future__ import annotations

import ast
import tokenize
from pathlib import Path

from tests.conftest import ROOT

RUNTIME = ROOT / "mazegen" / "runtime"
UNWRAPPED = ("inner_kernel", "leaf_kernel")
"""The decorators of kernels without a Python wrapper (mazegen/runtime/compiling.py)."""
DECORATORS = (*UNWRAPPED, "wrapped_leaf_kernel", "counted_kernel")
"""compiling.py's decorators."""


def _kernels() -> list[tuple[Path, ast.FunctionDef, str]]:
    """Every compiled function of the runtime: its file, its definition and its decorator's text."""
    found = []
    for path in sorted(RUNTIME.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.FunctionDef):
                decorators = [
                    ast.unparse(d)
                    for d in node.decorator_list
                    if "njit" in ast.unparse(d)
                    or ast.unparse(d) in (*UNWRAPPED, "wrapped_leaf_kernel", "counted_kernel")
                ]
                if decorators:
                    found.append((path, node, decorators[0]))
    return found


def _inlined(decorator: str) -> bool:
    return "inline" in decorator


def _uncounted(decorator: str) -> bool:
    return decorator in ("leaf_kernel", "wrapped_leaf_kernel")


def _callees(node: ast.FunctionDef) -> set[str]:
    return {
        call.func.attr if isinstance(call.func, ast.Attribute) else getattr(call.func, "id", "")
        for call in ast.walk(node)
        if isinstance(call, ast.Call)
    }


def test_no_kernel_is_parallel():
    offending = [
        f"{path.name}:{node.lineno} {node.name}"
        for path, node, decorator in _kernels()
        if "parallel" in decorator
    ]
    assert offending == []


def test_no_kernel_gives_another_a_literal_constant():
    names = {node.name for _, node, decorator in _kernels() if not _inlined(decorator)}
    offending = []
    for path, node, _ in _kernels():
        for call in ast.walk(node):
            if not isinstance(call, ast.Call):
                continue
            callee = call.func.attr if isinstance(call.func, ast.Attribute) else getattr(call.func, "id", "")
            constants = [a for a in call.args if isinstance(a, ast.Constant) and type(a.value) in (int, bool)]
            if callee in names and constants:
                offending.append(f"{path.name}:{call.lineno} {ast.unparse(call)}")
    assert offending == []


def test_kernels_have_a_python_wrapper_exactly_when_python_calls_them():
    kernels = _kernels()
    bodies = {(path, line) for path, node, _ in kernels for line in range(node.lineno, node.end_lineno + 1)}
    sources = [
        *(ROOT / "mazegen").rglob("*.py"),
        *(ROOT / "tests").rglob("*.py"),
        *(ROOT / "benchmarks").glob("*.py"),
    ]
    outside: dict[str, int] = {}
    for path in sources:
        if path == Path(__file__):
            continue
        with path.open("rb") as code:  # names in code, not words of docstrings or comments
            for token in tokenize.tokenize(code.readline):
                if token.type == tokenize.NAME and (path, token.start[0]) not in bodies:
                    outside[token.string] = outside.get(token.string, 0) + 1
    wrong = [
        f"{path.name}:{node.lineno} {node.name}"
        for path, node, decorator in kernels
        if not _inlined(decorator) and (decorator in UNWRAPPED) == (outside.get(node.name, 0) > 0)
    ]
    assert wrong == []


def test_kernels_without_reference_counting_call_only_their_like():
    """numba compiles a kernel a kernel without reference counting calls without it too, unless the
    callee says otherwise: a kernel that allocates would then fail to compile, and one that both kinds
    call would compile as whichever called it first. So they call only kernels that say which they
    are (leaf or counted), directly or through inlined ones."""
    kernels = {node.name: (path, node, decorator) for path, node, decorator in _kernels()}
    offending = []
    for path, node, decorator in kernels.values():
        if not _uncounted(decorator):
            continue
        seen, todo = set(), list(_callees(node))
        while todo:
            name = todo.pop()
            if name in seen or name not in kernels or name == node.name:
                continue
            seen.add(name)
            callee = kernels[name][2]
            if _inlined(callee):
                todo.extend(_callees(kernels[name][1]))
            elif not _uncounted(callee) and callee != "counted_kernel":
                offending.append(f"{path.name}:{node.lineno} {node.name} calls {name}")
    assert offending == []
    assert sum(_uncounted(decorator) for _, _, decorator in kernels.values()) > 20  # (the rule applies)
