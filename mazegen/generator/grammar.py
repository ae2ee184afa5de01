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
    names = scenario.entries
    if scenario.grammar == "custom":  # a row's name in a rule is already written with its count
        return [(lhs, list(alternatives)) for lhs, alternatives in scenario.custom_rules] + _count_rules(
            scenario
        )
    if scenario.grammar == "nested":
        rules = [
            (START, [_call(n, scenario, None, empty_parens=False) for n in names] + [COMPOSED]),
            (COMPOSED, [_call(n, scenario, START, empty_parens=False) for n in names]),
        ]
    elif scenario.grammar == "flat":
        rules = [
            (
                START,
                [_call(n, scenario, None, empty_parens=True) for n in names]
                + [_call(n, scenario, START, empty_parens=True) for n in names],
            )
        ]
    else:  # list
        rules = [
            (START, [ELEMENT, f"{ELEMENT} {START}"]),
            (ELEMENT, [_call(n, scenario, None, empty_parens=False) for n in names]),
        ]
    return rules + _count_rules(scenario) + _placement_rules(scenario.placement)
