"""The scenario's BNF grammar (PonyGE2 dialect) as rules, one function per style.

Styles follow the MazeGen paper: ``nested`` is its Figure 1, ``flat`` its
Figure 4; ``list`` is a plain sequence; ``custom`` takes the spec's rules.
"""

from __future__ import annotations

from mazegen.spec import GrammarPlacement, Spec

Rules = list[tuple[str, list[str]]]

START = "<scenario>"
COMPOSED = "<composed>"
ELEMENT = "<element>"
SIZE = "<size>"
NUMBER = "<number>"
MORE = "<more>"


def _call(name: str, placement: GrammarPlacement | None, inner: str | None, *, empty_parens: bool) -> str:
    """``name``, ``name()``, ``name(<scenario>)`` or their placement-carrying forms."""
    args = [SIZE, NUMBER, NUMBER] if placement is not None else []
    if inner is not None:
        args.append(inner)
    if not args:
        return f"{name}()" if empty_parens else name
    return f"{name}({','.join(args)})"


def _placement_rules(placement: GrammarPlacement | None) -> Rules:
    if placement is None:
        return []
    return [(SIZE, [str(v) for v in placement.sizes]), (NUMBER, [str(v) for v in placement.positions])]


def scenario_rules(spec: Spec) -> Rules:
    """Return the grammar's rules; the first rule is the start rule."""
    scenario = spec.scenario
    placement = scenario.placement
    if scenario.grammar == "custom":
        return [(lhs, list(alternatives)) for lhs, alternatives in scenario.custom_rules]
    exact = {name for name, _, exactly in scenario.required if exactly}
    names = [name for name in scenario.elements if name not in exact]
    start = MORE if scenario.required else START
    rules = _style_rules(scenario.grammar, names, placement, start) if names else []
    if scenario.required:
        rules = [(START, _required_alternatives(spec, names)), *rules]
    return rules + _placement_rules(placement)


def _style_rules(style: str, names: list[str], placement: GrammarPlacement | None, start: str) -> Rules:
    """The rules of a grammar ``style`` deriving any number of ``names``, from ``start``."""
    if style == "nested":
        return [
            (start, [_call(n, placement, None, empty_parens=False) for n in names] + [COMPOSED]),
            (COMPOSED, [_call(n, placement, start, empty_parens=False) for n in names]),
        ]
    if style == "flat":
        return [
            (
                start,
                [_call(n, placement, None, empty_parens=True) for n in names]
                + [_call(n, placement, start, empty_parens=True) for n in names],
            )
        ]
    return [  # list
        (start, [ELEMENT, f"{ELEMENT} {start}"]),
        (ELEMENT, [_call(n, placement, None, empty_parens=False) for n in names]),
    ]


def _required_alternatives(spec: Spec, names: list[str]) -> list[str]:
    """The start rule of a scenario with required elements: those elements first, in the order the
    spec requires them, then any number of the others (``<more>``, whose rules are the style's) or,
    as a second alternative, none."""
    scenario = spec.scenario
    placement, flat = scenario.placement, scenario.grammar == "flat"
    needed = [name for name, count, _ in scenario.required for _ in range(count)]
    if scenario.grammar == "list":
        calls = [_call(n, placement, None, empty_parens=False) for n in needed]
        return [" ".join([*calls, MORE]), " ".join(calls)] if names else [" ".join(calls)]
    alternatives = []
    for inner in ([MORE] if names else []) + [None]:
        derived = inner
        for k, name in enumerate(reversed(needed)):
            derived = _call(name, placement, derived, empty_parens=flat or k > 0)
        alternatives.append(str(derived))
    return alternatives
