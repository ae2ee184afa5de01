"""The scenario's BNF grammar (PonyGE2 dialect) as rules, one function per style.

Styles follow the MazeGen paper: ``nested`` is its Figure 1, ``flat`` its
Figure 4; ``list`` is a plain sequence; ``custom`` takes the spec's rules. A row is
an alternative like an element, its member count chosen by a rule of its own:
``rackRow(<rackRow-count>)``, ``<rackRow-count> ::= 2 | 3 | 4``.
"""

from __future__ import annotations

from mazegen.spec import GrammarPlacement, Scenario, Spec, row_count_rule

Rules = list[tuple[str, list[str]]]

START = "<scenario>"
COMPOSED = "<composed>"
ELEMENT = "<element>"
SIZE = "<size>"
NUMBER = "<number>"
MORE = "<more>"


def _call(name: str, scenario: Scenario, inner: str | None, *, empty_parens: bool) -> str:
    """``name``, ``name()``, ``name(<scenario>)``, their placement-carrying forms, or a row's with its
    count first: ``rackRow(<rackRow-count>,<scenario>)``."""
    args = [SIZE, NUMBER, NUMBER] if scenario.placement is not None else []
    if any(row.name == name for row in scenario.rows):
        args = [row_count_rule(name)]
    if inner is not None:
        args.append(inner)
    if not args:
        return f"{name}()" if empty_parens else name
    return f"{name}({','.join(args)})"


def _placement_rules(placement: GrammarPlacement | None) -> Rules:
    if placement is None:
        return []
    return [(SIZE, [str(v) for v in placement.sizes]), (NUMBER, [str(v) for v in placement.positions])]


def _count_rules(scenario: Scenario) -> Rules:
    return [
        (row_count_rule(row.name), [str(n) for n in range(row.count[0], row.count[1] + 1)])
        for row in scenario.rows
    ]


def scenario_rules(spec: Spec) -> Rules:
    """Return the grammar's rules; the first rule is the start rule."""
    scenario = spec.scenario
    if scenario.grammar == "custom":  # a row's name in a rule is already written with its count
        return [(lhs, list(alternatives)) for lhs, alternatives in scenario.custom_rules] + _count_rules(
            scenario
        )
    exact = {name for name, _, exactly in scenario.required if exactly}
    names = [name for name in scenario.entries if name not in exact]
    start = MORE if scenario.required else START
    rules = _style_rules(scenario, names, start) if names else []
    if scenario.required:
        rules = [(START, _required_alternatives(scenario, names)), *rules]
    return rules + _count_rules(scenario) + _placement_rules(scenario.placement)


def _style_rules(scenario: Scenario, names: list[str], start: str) -> Rules:
    """The rules of the scenario's grammar style deriving any number of ``names``, from ``start``."""
    if scenario.grammar == "nested":
        return [
            (start, [_call(n, scenario, None, empty_parens=False) for n in names] + [COMPOSED]),
            (COMPOSED, [_call(n, scenario, start, empty_parens=False) for n in names]),
        ]
    if scenario.grammar == "flat":
        return [
            (
                start,
                [_call(n, scenario, None, empty_parens=True) for n in names]
                + [_call(n, scenario, start, empty_parens=True) for n in names],
            )
        ]
    return [  # list
        (start, [ELEMENT, f"{ELEMENT} {start}"]),
        (ELEMENT, [_call(n, scenario, None, empty_parens=False) for n in names]),
    ]


def _required_alternatives(scenario: Scenario, names: list[str]) -> list[str]:
    """The start rule of a scenario with required elements: those elements first, in the order the
    spec requires them, then any number of the others (``<more>``, whose rules are the style's) or,
    as a second alternative, none."""
    flat = scenario.grammar == "flat"
    needed = [name for name, count, _ in scenario.required for _ in range(count)]
    if scenario.grammar == "list":
        calls = [_call(n, scenario, None, empty_parens=False) for n in needed]
        return [" ".join([*calls, MORE]), " ".join(calls)] if names else [" ".join(calls)]
    alternatives = []
    for inner in ([MORE] if names else []) + [None]:
        derived = inner
        for k, name in enumerate(reversed(needed)):
            derived = _call(name, scenario, derived, empty_parens=flat or k > 0)
        alternatives.append(str(derived))
    return alternatives
