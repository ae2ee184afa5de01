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
    names = scenario.elements
    placement = scenario.placement
    if scenario.grammar == "custom":
        return [(lhs, list(alternatives)) for lhs, alternatives in scenario.custom_rules]
    if scenario.grammar == "nested":
        rules = [
            (START, [_call(n, placement, None, empty_parens=False) for n in names] + [COMPOSED]),
            (COMPOSED, [_call(n, placement, START, empty_parens=False) for n in names]),
        ]
    elif scenario.grammar == "flat":
        rules = [
            (
                START,
                [_call(n, placement, None, empty_parens=True) for n in names]
                + [_call(n, placement, START, empty_parens=True) for n in names],
            )
        ]
    else:  # list
        rules = [
            (START, [ELEMENT, f"{ELEMENT} {START}"]),
            (ELEMENT, [_call(n, placement, None, empty_parens=False) for n in names]),
        ]
    return rules + _placement_rules(placement)
