"""Arena, scenario, fitness and evolution blocks of a ``.maze`` model → Spec parts."""

from __future__ import annotations

import re
from collections.abc import Collection
from typing import Any

from mazegen.dsl.bounds import MAX_LENGTH, MAX_SLOTS, MAX_TARGET, MAX_TERMINALS, MAX_WEIGHT, at_most
from mazegen.dsl.located import check_range, fail, single_properties, suggestion, where
from mazegen.dsl.plugin_terms import plugin_term
from mazegen.dsl.required import REQUIRED_PROPERTY, required_counts
from mazegen.dsl.robot import drive_controllers
from mazegen.fitness_terms import TERMS
from mazegen.spec import (
    CROSSOVER_OPERATORS,
    DIFFICULTY_LEVELS,
    MAX_CLASSES,
    MAX_CODONS,
    Arena,
    Evolution,
    FitnessTerm,
    GrammarPlacement,
    Scenario,
    out_of_bounds,
    row_count_rule,
)
from mazegen.text import decode_escapes, quoted

_WORD = re.compile(r"\w")


def _int_values(obj: Any, what: str, *, minimum: int) -> tuple[int, ...]:
    step = obj.step if obj.step is not None else 1
    if step <= 0:
        fail(obj, f"{what} step must be positive, got {step}")
    check_range(obj, obj.low, obj.high, what, positive=False)
    if obj.low < minimum:
        fail(obj, f"{what} must be at least {minimum}, got {obj.low}")
    count = (obj.high - obj.low) // step + 1
    if count > MAX_TERMINALS:
        fail(obj, f"{what} {obj.low}..{obj.high} give {count} values; at most {MAX_TERMINALS}")
    return tuple(range(obj.low, obj.high + 1, step))


def _bnf_text(symbol: Any, rows: Collection[str]) -> str:
    if type(symbol).__name__ != "TextSymbol":  # a rule or an element, written as is; a row with its count
        return f"{symbol.name}({row_count_rule(symbol.name)})" if symbol.name in rows else symbol.name
    text = symbol.text
    if text == "":
        fail(symbol, "empty text in a grammar rule")
    if '"' in text and "'" in text:
        fail(symbol, "grammar text cannot hold both kinds of quote")
    if not text.isprintable():
        fail(symbol, f"grammar text {quoted(text)} holds a control character (write \\n for a line break)")
    try:
        decode_escapes(text)  # as the run will, so a bad escape is found at the spec's line
    except ValueError as error:
        fail(symbol, f"bad escape in grammar text {quoted(text)}: {error}")
    return f"'{text}'" if '"' in text else f'"{text}"'


def _edge_is_word(symbol: Any, rows: Collection[str], *, end: bool) -> bool:
    """Whether a symbol may end (or start) with a word character once derived."""
    if type(symbol).__name__ != "TextSymbol":
        return not (end and symbol.name in rows)  # names are words; a rule may derive one; a row ends in ')'
    return bool(symbol.text) and bool(_WORD.match(symbol.text[-1] if end else symbol.text[0]))


def _bnf_alternative(alternative: Any, rows: Collection[str]) -> str:
    pieces: list[str] = []
    previous = None
    for symbol in alternative.symbols:
        # Two words side by side would fuse (`cobotrouter`) and no longer name elements.
        if (
            previous is not None
            and _edge_is_word(previous, rows, end=True)
            and _edge_is_word(symbol, rows, end=False)
        ):
            pieces.append(" ")
        pieces.append(_bnf_text(symbol, rows))
        previous = symbol
    return "".join(pieces)


def _custom_rules(
    grammar: Any, known_elements: dict[str, Any], rows: dict[str, Any]
) -> tuple[tuple, list[str]]:
    rules: dict[str, Any] = {}
    for rule in grammar.rules:
        if rule.lhs in rules:
            fail(rule, f"rule {rule.lhs} is defined twice (first at {where(rules[rule.lhs])})")
        rules[rule.lhs] = rule
    known = {**known_elements, **rows}
    used: list[str] = []
    for rule in grammar.rules:
        for alternative in rule.alternatives:
            for symbol in alternative.symbols:
                kind = type(symbol).__name__
                if kind == "RuleUse" and symbol.name not in rules:
                    fail(
                        symbol,
                        f"rule {symbol.name} is used but never defined{suggestion(symbol.name, rules)}",
                    )
                if kind == "ElementUse":
                    if symbol.name not in known:
                        fail(symbol, f"unknown element '{symbol.name}'{suggestion(symbol.name, known)}")
                    if symbol.name not in used:
                        used.append(symbol.name)
    for name in used:
        if name in rows and row_count_rule(name) in rules:
            fail(
                rules[row_count_rule(name)],
                f"rule {row_count_rule(name)} chooses the count of row '{name}', which MazeGen writes: "
                "give your rule another name",
            )
    converted = tuple(
        (r.lhs, tuple(_bnf_alternative(a, rows) for a in r.alternatives)) for r in grammar.rules
    )
    return converted, used


def convert_scenario(
    decl: Any, arenas: dict[str, Arena], elements: dict[str, Any], rows: dict[str, Any], genome: int
) -> Scenario:
    """Check the ``scenario`` block against the declared arenas, elements and rows (``rows`` its
    declarations, each of a declared element: see :func:`~mazegen.dsl.structure.check_row_members`);
    the scenario's rows are left to the caller, which converts them into the arena's units."""
    what = f"scenario '{decl.name}'"
    if decl.arena not in arenas:
        fail(decl, f"unknown arena '{decl.arena}'{suggestion(decl.arena, arenas)}")
    arena = arenas[decl.arena]
    needed = [p for p in decl.properties if type(p).__name__ == REQUIRED_PROPERTY]
    props = single_properties([p for p in decl.properties if p not in needed], what)
    names: list[str] = []
    if "ElementsProperty" in props:
        for use in props["ElementsProperty"].elements:
            if use.name not in elements and use.name not in rows:
                fail(use, f"unknown element '{use.name}'{suggestion(use.name, {**elements, **rows})}")
            if use.name in names:
                fail(use, f"{'row' if use.name in rows else 'element'} '{use.name}' is listed twice")
            names.append(use.name)
    grammar = props.get("GrammarProperty")
    style = grammar.style if grammar is not None else "nested"
    custom: tuple = ()
    if style == "custom":
        custom, used = _custom_rules(grammar, elements, rows)
        for name in used:
            if names and name not in names:
                fail(props["ElementsProperty"], f"the grammar uses '{name}', which 'elements' does not list")
        names = names or used
    if not names:
        fail(decl, f"{what} names no elements (add e.g. 'elements cobot, router')")
    slots = props.get("MaxElementsProperty")
    max_elements = slots.value if slots is not None else min(genome, MAX_SLOTS)
    if not 1 <= max_elements <= MAX_SLOTS:
        fail(slots, f"max elements must be within 1..{MAX_SLOTS}, got {max_elements}")
    placement = None
    prop = props.get("PlacementProperty")
    if prop is not None and not prop.genes:
        sizes = _int_values(prop.sizes, "sizes", minimum=1)
        positions = _int_values(prop.positions, "positions", minimum=0)
        if positions[-1] > min(arena.width, arena.height):
            fail(
                prop.positions,
                f"positions up to {positions[-1]} go beyond the arena {arena.width:g} x {arena.height:g}",
            )
        scale = prop.scale if prop.scale is not None else 1.0
        if scale <= 0:
            fail(prop, f"scale must be positive, got {scale:g}")
        at_most(prop, scale, MAX_LENGTH, "scale")
        at_most(prop, sizes[-1] * scale, MAX_LENGTH, f"sizes up to {sizes[-1]} x scale {scale:g}")
        placement = GrammarPlacement(sizes, scale, positions)
    required = required_counts(needed, names, style, max_elements, rows)
    # A row's members are of its element type: a type of the scenario (an id) whether listed or not.
    types = tuple(dict.fromkeys(rows[name].member if name in rows else name for name in names))
    listed = tuple(names) if any(name in rows for name in names) else ()
    return Scenario(
        decl.name, decl.arena, types, style, custom, max_elements, placement, required, listed=listed
    )


def convert_fitness(decl: Any | None, elements: tuple[str, ...]) -> tuple[FitnessTerm, ...]:
    """Check the ``fitness`` block (``elements``: the scenario's element types, which a metric
    plug-in's floors name); without one the fitness is the element count."""
    if decl is None or not decl.terms:
        return (FitnessTerm("count"),)
    seen: dict[str, Any] = {}
    terms = []
    for term in decl.terms:
        converted = _fitness_term(term, elements)
        key = converted.key
        if key in seen:
            fail(term, f"duplicate fitness term '{key}' (first given at {where(seen[key])})")
        seen[key] = term
        terms.append(converted)
    return tuple(terms)


_KIND_OF_RULE = {row.rule: kind for kind, row in TERMS.items()}


def _fitness_term(term: Any, elements: tuple[str, ...]) -> FitnessTerm:
    kind = _KIND_OF_RULE[type(term).__name__]
    if kind == "plugin":
        return plugin_term(term, _target(term), elements)
    metric = getattr(term, "metric", None) or getattr(term, "measure", None) or None
    controllers = drive_controllers(term) if kind == "drive" else ()
    weight = term.weight if term.weight is not None else 1.0
    if weight < 0:
        fail(term, f"weight must not be negative, got {weight:g}")
    at_most(term, weight, MAX_WEIGHT, "weight")
    limit = getattr(term, "limit", None)
    if limit is not None and limit <= 0:
        fail(term, f"size limit must be positive, got {limit:g}")
    if limit is not None:
        at_most(term, limit, MAX_LENGTH, "size limit")
    reject = bool(getattr(term, "reject", False))
    if kind == "size_limit" and getattr(term, "allow", False):
        fail(term, "a size limit needs 'reject' or 'penalty W'")
    if kind == "outside" and getattr(term, "allow", False):
        weight = 0.0
    bound = getattr(term, "bound", None)
    if bound is not None:
        if bound <= 0:
            fail(term, f"travel below a length: it must be positive, got {bound:g}")
        at_most(term, bound, MAX_LENGTH, "travel bound")
        limit = bound
    tasks = getattr(term, "tasks", None) or "mean"
    target = _target(term)
    exactly = getattr(term, "exactly", None)
    if exactly is not None:
        if not 1 <= exactly <= MAX_CLASSES:
            fail(
                term, f"classes N counts 1 to {MAX_CLASSES} classes (the most a floor is told), got {exactly}"
            )
        target = (float(exactly), float(exactly))
    return FitnessTerm(kind, weight, limit, reject, target, metric, controllers, tasks=tasks)


def _target(term: Any) -> tuple[float, float] | None:
    """The range a term rewards closeness to: a difficulty level's or the one written."""
    level = getattr(term, "level", None)
    if level:
        return DIFFICULTY_LEVELS[level]
    span = getattr(term, "range", None)
    if span is None:
        return None
    if span.low >= span.high:
        fail(span, f"a target range needs low < high, got {span.low:g}..{span.high:g}")
    if span.low < 0:
        fail(span, f"a target range cannot go below 0, got {span.low:g}..{span.high:g}")
    if span.high > MAX_TARGET:
        fail(span, f"a target range cannot go above {MAX_TARGET}, got {span.low:.15g}..{span.high:.15g}")
    if getattr(term, "kind", None) in ("coverage", "reachable") and span.high > 1:
        fail(span, f"{term.kind} is a fraction of the floor (0..1), got {span.low:g}..{span.high:g}")
    return (float(span.low), float(span.high))


def _bounded(node: Any, key: str, value: Any, label: str) -> Any:
    """``value`` of evolution setting ``key``, failing at ``node`` when it is out of its bounds."""
    problem = out_of_bounds(key, value)
    if problem is not None:
        shown = f"{value:g}" if isinstance(value, float) else str(value)
        fail(node, f"{label} {problem}, got {shown}")
    return value


def _operator(key: str, operator: Any) -> str:
    """The crossover or mutation operator as ``spec.json`` names it: ``onepoint within used``."""
    scope = f"within {operator.scope or 'used'}"
    if key == "mutation":
        if operator.kind:
            fail(operator, f"mutation is int-flip, not {operator.kind}: write mutation {scope} RATE")
        return scope
    if not operator.kind:
        fail(operator, f"say which crossover: crossover onepoint {scope} RATE or crossover variable RATE")
    if f"{operator.kind} {scope}" not in CROSSOVER_OPERATORS:
        fail(operator, f"{operator.kind} crossover cuts within the used codons only, not {scope}")
    return f"{operator.kind} {scope}"


def convert_evolution(decl: Any | None) -> Evolution:
    """Check the ``evolution`` block against the bounds each setting must respect."""
    if decl is None:
        return Evolution()
    props = single_properties(decl.settings, "evolution")
    values: dict[str, Any] = {}
    for key in ("population", "generations", "genome", "elitism", "runs", "seed", "wraps", "best"):
        if key in props:
            values[key] = _bounded(props[key], key, props[key].value, key)
    for key in ("crossover", "mutation"):
        if key in props:
            values[key] = _bounded(props[key], key, props[key].value, f"{key} rate")
            if props[key].operator is not None:
                values[f"{key}_operator"] = _operator(key, props[key].operator)
    selection = props.get("SelectionSetting")
    if selection is not None:
        if selection.tournament is not None:
            size = _bounded(selection, "tournament", selection.tournament, "tournament size")
            values.update(selection="tournament", tournament=size)
        else:
            fraction = _bounded(selection, "truncation", selection.fraction, "selection")
            values.update(selection="truncation", truncation=fraction)
    if "CodonSetting" in props:
        codons = props["CodonSetting"].range
        if codons.low != 0 or codons.high < 1 or codons.step is not None:
            fail(
                codons, f"codons must be written 0..MAX with MAX at least 1, got {codons.low}..{codons.high}"
            )
        values["codon_max"] = _bounded(codons, "codon_max", codons.high, "codons 0..MAX: MAX")
    if "ConsumeSetting" in props:
        values["consume"] = props["ConsumeSetting"].mode
    population = values.get("population", Evolution.population)
    genome = values.get("genome", Evolution.genome)
    if population * genome > MAX_CODONS:
        fail(
            props.get("genome", props.get("population")),
            f"population x genome must be at most {MAX_CODONS} codons, got {population} x {genome}",
        )
    evolution = Evolution(**values)
    if evolution.elitism >= evolution.population:
        if "elitism" in props:
            fail(
                props["elitism"],
                f"elitism {evolution.elitism} must be below the population {evolution.population}",
            )
        fail(
            props.get("population", decl),
            f"population {evolution.population} must be above the elitism {evolution.elitism} (the default; "
            "set elitism 0 to keep no elites)",
        )
    if evolution.selection == "tournament" and evolution.tournament > evolution.population:
        fail(
            selection,
            f"tournament {evolution.tournament} is larger than the population {evolution.population}",
        )
    return evolution
