"""The kinds of fitness term, one row each: the language, the build, the reports and the docs read them.

A row says which grammar rule of ``mazegen/dsl/maze.tx`` writes the kind, what it reads of a floor,
whether it is added (a reward) or subtracted (a penalty), the call a generated ``fitness.py`` makes
(a function of :mod:`mazegen.runtime.metrics`), how the ``fitness`` block writes it, and why a
``reject`` term of the kind rejects. ``tests/generator/test_term_kinds.py`` keeps the rows and the
grammar in step; docs/architecture.md's recipe "A new fitness term" names every file a new kind
touches.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from mazegen.errors import MazeError
from mazegen.spec import DIFFICULTY_LEVELS, FitnessTerm, Spec
from mazegen.text import number

READS = ("elements", "occupancy", "path", "survey", "drive", "plug-in")
"""What a term may read of a floor, cheapest first: its elements alone, the occupied grid and
whether a path exists, the path itself, the difficulty survey (paths and their metrics), robots
driven through it, or whatever a user's metric reads."""


@dataclass(frozen=True)
class TermKind:
    """One kind of fitness term.

    Attributes:
        kind: Its name in a spec (``FitnessTerm.kind``, ``spec.json``).
        rule: The rule of ``maze.tx`` that writes it.
        syntax: How docs/language.md's synopsis of the ``fitness`` block writes it.
        reads: What it reads of a floor (one of :data:`READS`).
        reward: Added to the fitness (True) or subtracted (a penalty).
        function: The function of :mod:`mazegen.runtime.metrics` it calls (a drive term's
            ``{measure}`` filled in).
        call: The term's call in ``fitness.py`` and a comment on what it is.
        words: The term as the ``fitness`` block writes it.
        rejects: Why a ``reject`` term of this kind rejects, for a run with no valid scenario
            ("" when the kind cannot reject).
    """

    kind: str
    rule: str
    syntax: str
    reads: str
    reward: bool
    function: str
    call: Callable[[FitnessTerm], tuple[str, str]]
    words: Callable[[FitnessTerm], str]
    rejects: str = ""


def _target(term: FitnessTerm) -> str:
    return "" if term.target is None else ", {!r}, {!r}".format(*term.target)


def _span(term: FitnessTerm) -> str:
    low, high = term.target or (0.0, 0.0)
    return f"{number(low)}..{number(high)}"


def _weighted(words: str, term: FitnessTerm) -> str:
    return words if term.weight == 1.0 else f"{words} weight {number(term.weight)}"


def _penalised(words: str, term: FitnessTerm, *, allow: bool = False) -> str:
    """``words reject``, ``words penalty W``, or with ``allow`` a zero weight as ``words allow``."""
    if term.reject:
        return f"{words} {'required' if words == 'solvable' else 'reject'}"
    return f"{words} allow" if allow and term.weight == 0 else f"{words} penalty {number(term.weight)}"


def _closeness(function: str, note: str) -> Callable[[FitnessTerm], tuple[str, str]]:
    return lambda term: (f"metrics.closeness(metrics.{function}(pop){_target(term)})", note)


_DRIVE_NOTES = {
    "fails": "1 where {0} collides or times out",
    "time": "{0}'s time over the optimal time (failures: the timeout factor)",
    "clearance": "{0}'s closest approach to an obstacle (arena units)",
    "disagree": "1 where one of {0} and {1} arrives and the other fails",
}


def _drive_call(term: FitnessTerm) -> tuple[str, str]:
    """A drive term's call, over lines of their own (controller names may be long), and its note;
    an individual not driven gets no credit: 0, or 0 closeness to a target."""
    names = ", ".join(repr(name) for name in term.controllers)
    call = f"metrics.drive_{term.metric}(pop, {names}, driven)"
    note = _DRIVE_NOTES[term.metric or ""].format(*term.controllers)
    if term.target is None:
        return f"np.nan_to_num(\n            {call}\n        )", note
    low, high = term.target
    return f"metrics.closeness(\n            {call}, {low!r}, {high!r}\n        )", f"{note}, near a target"


def _drive_words(term: FitnessTerm) -> str:
    names = ", ".join(term.controllers)
    head = f"controllers {names}" if len(term.controllers) > 1 else f"controller {names}"
    span = "" if term.target is None else f" {_span(term)}"
    return _weighted(f"{head} {term.metric}{span}", term)


def _over_tasks(words: str, term: FitnessTerm) -> str:
    """``words`` with how the term scores several tasks, unless it is the mean (the default)."""
    return _weighted(words if term.tasks == "mean" else f"{words} tasks {term.tasks}", term)


def _difficulty_words(term: FitnessTerm) -> str:
    level = {span: name for name, span in DIFFICULTY_LEVELS.items()}.get(term.target or (0.0, 0.0))
    return _over_tasks(f"difficulty target {level}" if level else f"difficulty {_span(term)}", term)


def _task_closeness(measure: str, note: str) -> Callable[[FitnessTerm], tuple[str, str]]:
    """The call of a term scoring the closeness of ``measure`` (``difficulty``, a path metric's name)
    to its target: of the tasks' mean, or over the tasks as ``tasks worst`` or ``tasks all`` say."""

    def call(term: FitnessTerm) -> tuple[str, str]:
        if term.tasks == "mean":
            of = "difficulty(pop)" if measure == "difficulty" else f"path_metric(pop, {measure!r})"
            return f"metrics.closeness(metrics.{of}{_target(term)})", note
        values = f"metrics.task_values(pop, {measure!r}){_target(term)}, {term.tasks!r}"
        call = f"metrics.task_closeness(\n            {values}\n        )"
        return call, f"{note}, over the tasks: {term.tasks}"

    return call


def _travel_call(term: FitnessTerm) -> tuple[str, str]:
    """``travel total|worst``: how straight the tasks' paths are, or with ``below L`` how near their
    total (or longest) length is to at most L."""
    measure = term.metric or "total"
    if term.limit is None:
        note = "straight distance over path length, " + ("all tasks" if measure == "total" else "worst task")
        return f"metrics.travel(pop, {measure!r})", note
    call = f"metrics.closeness(metrics.travel_length(pop, {measure!r}), 0.0, {float(term.limit)!r})"
    return (
        call,
        f"{'total' if measure == 'total' else 'longest'} path of the tasks, at most {number(term.limit)}",
    )


def _plugin_call(term: FitnessTerm) -> tuple[str, str]:
    """A metric plug-in's call: its value, its closeness to a target, or its excess over a reject
    threshold (``> 0`` where it rejects)."""
    plugin = term.plugin
    if plugin is None:
        raise MazeError(f"fitness term {term.key!r} is a metric plug-in with no plug-in recorded")
    lines = [
        "pop",
        repr(term.metric),
        repr(dict(plugin.arguments)),
        f"source={plugin.source!r}",
        f"package={plugin.package!r}",
        f"types={plugin.types!r}",
        f"where={plugin.where!r}",
    ]
    call = "metrics.plugin_metric(\n" + "".join(f"            {line},\n" for line in lines) + "        )"
    origin = f"from {plugin.source}" if plugin.source else f"of {plugin.package}"
    note = f"metric plug-in {term.metric} {origin}"
    if term.reject:
        return f"{call} - {float(term.limit or 0.0)!r}", note
    if term.target is not None:
        return f"metrics.closeness({call}{_target(term)})", f"{note}, near a target"
    return call, note


def _plugin_words(term: FitnessTerm) -> str:
    plugin = term.plugin
    arguments = (
        ""
        if plugin is None or not plugin.arguments
        else "(" + ", ".join(f"{name}={number(value)}" for name, value in plugin.arguments) + ")"
    )
    source = "" if plugin is None or plugin.source is None else f' from "{plugin.source}"'
    head = f"metric {term.metric}{arguments}{source}"
    if term.reject:
        return f"{head} reject above {number(term.limit or 0.0)}"
    if term.target is not None:
        return _weighted(f"{head} range {_span(term)}", term)
    return f"{head} penalty {number(-term.weight)}" if term.weight < 0 else _weighted(head, term)


def _classes_call(term: FitnessTerm) -> tuple[str, str]:
    if term.target is None:
        return "metrics.classes(pop)", "homotopy classes of the way from start to goal (docs/classes.md)"
    exactly = int(term.target[0])
    return f"metrics.classes(pop, {exactly})", f"closeness to exactly {exactly} homotopy classes"


def _classes_words(term: FitnessTerm) -> str:
    return _weighted("classes" if term.target is None else f"classes {int(term.target[0])}", term)


_ROWS = (
    TermKind(
        kind="count",
        rule="CountTerm",
        syntax="count [weight W]",
        reads="elements",
        reward=True,
        function="element_count",
        call=lambda term: ("metrics.element_count(pop)", "paper eq. 1: number of elements"),
        words=lambda term: _weighted("count", term),
    ),
    TermKind(
        kind="overlap",
        rule="OverlapTerm",
        syntax="overlap penalty K | reject",
        reads="elements",
        reward=False,
        function="overlapping_pairs",
        call=lambda term: ("metrics.overlapping_pairs(pop)", "paper eq. 2: pairs of overlapping elements"),
        words=lambda term: _penalised("overlap", term),
        rejects="elements overlap one another (too many or too large for the arena?)",
    ),
    TermKind(
        kind="size_limit",
        rule="SizeLimitTerm",
        syntax="size limit L reject | penalty W",
        reads="elements",
        reward=False,
        function="elements_over_size",
        call=lambda term: (
            f"metrics.elements_over_size(pop, {float(term.limit or 0.0)!r})",
            "paper v1.5: elements over the size limit",
        ),
        words=lambda term: _penalised(f"size limit {number(term.limit or 0.0)}", term),
        rejects="elements larger than the limit",
    ),
    TermKind(
        kind="outside",
        rule="OutsideTerm",
        syntax="outside reject | penalty W | allow",
        reads="elements",
        reward=False,
        function="elements_outside",
        call=lambda term: ("metrics.elements_outside(pop)", "elements not wholly inside the arena"),
        words=lambda term: _penalised("outside", term, allow=True),
        rejects="elements not wholly inside the arena (larger than it, placed beyond it, "
        "or on its map's walls?)",
    ),
    TermKind(
        kind="solvable",
        rule="SolvableTerm",
        syntax="solvable required | penalty W",
        reads="occupancy",
        reward=False,
        function="unsolvable",
        call=lambda term: ("metrics.unsolvable(pop)", "no path from start to goal for the robot"),
        words=lambda term: _penalised("solvable", term),
        rejects="no path from start to goal for the robot (are the gaps narrower than the robot, or start "
        "or goal covered?)",
    ),
    TermKind(
        kind="difficulty",
        rule="DifficultyTerm",
        syntax="difficulty target easy|medium|hard [tasks mean|worst|all] [weight W]",
        reads="survey",
        reward=True,
        function="difficulty",
        call=_task_closeness("difficulty", "closeness to the difficulty target"),
        words=_difficulty_words,
    ),
    TermKind(
        kind="metric",
        rule="MetricTerm",
        syntax="METRIC LO..HI [tasks mean|worst|all] [weight W]",
        reads="survey",
        reward=True,
        function="path_metric",
        call=lambda term: _task_closeness(
            term.metric or "", f"closeness of the path's {term.metric} to its target"
        )(term),
        words=lambda term: _over_tasks(f"{term.metric} {_span(term)}", term),
    ),
    TermKind(
        kind="diversity",
        rule="DiversityTerm",
        syntax="diversity [types | entropy] [weight W]",
        reads="elements",
        reward=True,
        function="distinct_types",
        call=lambda term: (
            ("metrics.type_entropy(pop)", "entropy of the element types, bits")
            if term.metric == "entropy"
            else ("metrics.distinct_types(pop)", "number of distinct element types")
        ),
        words=lambda term: _weighted("diversity entropy" if term.metric == "entropy" else "diversity", term),
    ),
    TermKind(
        kind="coverage",
        rule="CoverageTerm",
        syntax="coverage LO..HI [weight W]",
        reads="occupancy",
        reward=True,
        function="coverage",
        call=_closeness("coverage", "occupied fraction near its target"),
        words=lambda term: _weighted(f"coverage {_span(term)}", term),
    ),
    TermKind(
        kind="travel",
        rule="TravelTerm",
        syntax="travel total|worst [below L] [weight W]",
        reads="path",
        reward=True,
        function="travel",
        call=_travel_call,
        words=lambda term: _weighted(
            f"travel {term.metric}" + ("" if term.limit is None else f" below {number(term.limit)}"), term
        ),
    ),
    TermKind(
        kind="reachable",
        rule="ReachableTerm",
        syntax="reachable LO..HI [weight W]",
        reads="occupancy",
        reward=True,
        function="reachable",
        call=_closeness("reachable", "share of the free floor reachable from the start, near its target"),
        words=lambda term: _weighted(f"reachable {_span(term)}", term),
    ),
    TermKind(
        kind="classes",
        rule="ClassesTerm",
        syntax="classes [N] [weight W]",
        reads="path",
        reward=True,
        function="classes",
        call=_classes_call,
        words=_classes_words,
    ),
    TermKind(
        kind="drive",
        rule="DriveTerm",
        syntax="controller C fails [weight W]",
        reads="drive",
        reward=True,
        function="drive_{measure}",
        call=_drive_call,
        words=_drive_words,
    ),
    TermKind(
        kind="plugin",
        rule="PluginTerm",
        syntax="metric NAME[(ARG=V, ...)] [from FILE] "
        "[weight W | penalty W | range LO..HI [weight W] | reject above X]",
        reads="plug-in",
        reward=True,
        function="plugin_metric",
        call=_plugin_call,
        words=_plugin_words,
        rejects="a metric plug-in's value above its reject threshold",
    ),
)

TERMS: dict[str, TermKind] = {row.kind: row for row in _ROWS}
"""Every kind of fitness term, by its name in a spec."""


def term_kind(term: FitnessTerm) -> TermKind:
    """The row of ``term``'s kind.

    Raises:
        MazeError: for a kind no row has (a ``spec.json`` edited by hand).
    """
    row = TERMS.get(term.kind)
    if row is None:
        raise MazeError(f"unknown fitness term kind {term.kind!r} (known: {', '.join(TERMS)})")
    return row


def reads_survey(spec: Spec) -> bool:
    """Whether a fitness term reads the difficulty survey (not just whether a path exists)."""
    return any(term_kind(term).reads == "survey" for term in spec.fitness)
