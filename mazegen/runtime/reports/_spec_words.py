"""A resolved spec's settings in the words of the .maze language.

Reports show settings as a spec writes them (``codons 0..255``, ``selection
truncation 0.1``, ``solvable required``), not by their field names in
``spec.json`` (``codon_max``, ``truncation``, ``reject``), and only those that
apply: a truncation spec has no tournament size.
"""

from __future__ import annotations

from mazegen.fitness_terms import term_kind
from mazegen.spec import Arena, Evolution, FitnessTerm, Scenario, Spec, Station, Zone
from mazegen.text import number, quoted

_INDENT = "    "
SUITE_EVOLUTION = ("genome", "crossover", "mutation", "codons", "wraps", "consume")
"""The evolution settings a suite uses (:func:`mazegen.runtime.campaigns._suite.fill_archive` breeds
and maps genomes by them); its seed, batches and their size are its own, and it neither selects,
keeps elites, counts runs nor keeps a best."""


def term_words(term: FitnessTerm) -> str:
    """One fitness term as the ``fitness`` block writes it: ``overlap penalty 0.5``."""
    return term_kind(term).words(term)


def evolution_words(evolution: Evolution, *, only: tuple[str, ...] | None = None) -> list[str]:
    """The ``evolution`` block's settings, one per item: ``population 1000``, ``codons 0..255``; with
    ``only``, those it names by their first word (:data:`SUITE_EVOLUTION`)."""
    selection = (
        f"selection tournament {evolution.tournament}"
        if evolution.selection == "tournament"
        else f"selection truncation {number(evolution.truncation)}"
    )
    words = [
        f"population {evolution.population}",
        f"generations {evolution.generations}",
        f"genome {evolution.genome}",
        selection,
        f"crossover {evolution.crossover_operator} {number(evolution.crossover)}",
        f"mutation {evolution.mutation_operator} {number(evolution.mutation)}",
        f"elitism {evolution.elitism}",
        f"runs {evolution.runs}",
        f"seed {evolution.seed}",
        f"codons 0..{evolution.codon_max}",
        f"wraps {evolution.wraps}",
        f"consume {evolution.consume}",
        f"best {evolution.best}",
    ]
    return words if only is None else [setting for setting in words if setting.split()[0] in only]


def arena_words(arena: Arena) -> list[str]:
    """The ``arena`` block's settings: its size or map, task, robot, grid and zones."""
    if arena.base is not None:
        unknown = [] if arena.base.unknown == "blocked" else ["unknown free"]
        words = [f"map {quoted(arena.base.source)} {arena.unit}", *unknown]
    else:
        words = [f"size {number(arena.width)} x {number(arena.height)} {arena.unit}"]
    if not arena.tasks:
        words += [
            f"start ({number(arena.start[0])}, {number(arena.start[1])})",
            f"goal ({number(arena.goal[0])}, {number(arena.goal[1])})",
        ]
    words += [_station_words(station) for station in arena.stations]
    listed = [task for task in arena.tasks if " -> " in task.name]
    words += [f"task {task.name}" for task in listed]
    drawn = len(arena.tasks) - len(listed)
    words += [f"// {drawn} tasks drawn at random (tasks N seed S)"] if drawn else []
    words += [f"robot radius {number(arena.robot_radius)}"]
    words += [f"grid {number(arena.grid)}"] if arena.grid is not None else []
    return words + [_zone_words(zone) for zone in arena.zones]


def _station_words(station: Station) -> str:
    heading = "" if station.heading is None else f" heading {number(station.heading)}"
    return f"station {station.name} ({number(station.point[0])}, {number(station.point[1])}){heading}"


def _zone_words(zone: Zone) -> str:
    corners = " ".join(f"({number(x)}, {number(y)})" for x, y in zone.outline)
    rule = "keep clear" if zone.rule == "clear" else f"{zone.rule} {', '.join(zone.types)}"
    return f"zone {zone.name} polygon {corners} {rule}"


def _steps(values: tuple[int, ...]) -> str:
    """``LOW..HIGH [step S]`` of an evenly spaced run of whole numbers."""
    step = values[1] - values[0] if len(values) > 1 else 1
    return f"{values[0]}..{values[-1]}" + (f" step {step}" if step != 1 else "")


def scenario_words(scenario: Scenario) -> list[str]:
    """The ``scenario`` block's settings; a custom grammar by its rule count (rules: grammar.bnf)."""
    grammar = scenario.grammar
    if grammar == "custom":
        grammar = f"custom {{ ... }}  // {len(scenario.custom_rules)} rules, see experiment/grammar.bnf"
    words = [
        f"elements {', '.join(scenario.entries)}",
        f"grammar {grammar}",
        f"max elements {scenario.max_elements}",
    ]
    placement = scenario.placement
    if placement is not None:
        scale = f" scale {number(placement.scale)}" if placement.scale != 1 else ""
        sizes, positions = _steps(placement.sizes), _steps(placement.positions)
        words.append(f"placement grammar sizes {sizes}{scale} positions {positions}")
    return words


def spec_blocks(spec: Spec, *, evolution: tuple[str, ...] | None = None) -> list[tuple[str, list[str]]]:
    """The spec's blocks as ``(header, settings)``: arena, scenario, fitness and evolution (only the
    settings ``evolution`` names, when given: see :func:`evolution_words`)."""
    return [
        (f"arena {spec.arena.name}", arena_words(spec.arena)),
        (f"scenario {spec.scenario.name} on {spec.scenario.arena}", scenario_words(spec.scenario)),
        ("fitness", [term_words(term) for term in spec.fitness]),
        ("evolution", evolution_words(spec.evolution, only=evolution)),
    ]


def block_text(header: str, settings: list[str]) -> str:
    """One block as .maze text: ``header {``, a setting per line, ``}``."""
    return "\n".join([f"{header} {{", *(_INDENT + words for words in settings), "}"])
