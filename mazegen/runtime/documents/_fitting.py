"""A bundled controller's parameters fitted to measured runs (``mazegen fit``).

The measured runs are a CSV of ``scenario, outcome, time`` rows: a scenario file (relative to the
CSV), how a real stack's run on it ended (``arrived``, ``collision``, ``timeout`` or ``failed``) and
its time in seconds; a scenario may have many rows (repeated runs). An optional ``length`` column
gives the path length in metres the scenario's times are divided by (BARN's own paths, say), the same
on each of its rows. Each scenario is measured as BARN measures its worlds: the mean over its runs of
the time (a failure counting as ``failure_time``) over that length, or over MazeGen's shortest path
without one, in seconds per metre. The simulator gives the same measure of one episode per scenario.

The fit searches the named parameters, each in a box around its default (a quarter to four times it,
within the parameter's bounds; counts half to twice), for the least ``(1 - ρ) + (1 - agreement)``:
ρ the Spearman rank correlation of the simulated and measured measures, agreement the share of
scenarios where the simulated robot arrives exactly when most measured runs did. The search is the
cross-entropy method (Rubinstein 1999): a Gaussian over the box, log-scaled where the box is, sampled
``POPULATION`` at a time from the run's seeded generator, refitted to the best ``ELITES``; the same
measurements, controller and seed give the same parameters. How well a fit carries to floors it did
not see is measured by k-fold cross-validation over scenarios.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mazegen.controllers import ANGLE, BUNDLED, TURN
from mazegen.errors import MazeError
from mazegen.fileio import read_text
from mazegen.runtime.documents._driving import Floors, driving_robot
from mazegen.runtime.documents._floor import load_floor
from mazegen.runtime.navigation import spearman
from mazegen.spec import ControllerSpec, Spec, metres_per_unit
from mazegen.text import number, printable

COLUMNS = ("scenario", "outcome", "time")
"""The columns of a measured-runs CSV, in any order."""
OPTIONAL_COLUMNS = ("length",)
"""Columns it may have besides."""
MEASURED_OUTCOMES = ("arrived", "collision", "timeout", "failed")
POPULATION = 16
"""Parameter sets the cross-entropy method draws at a time."""
ELITES = 4
"""The best of them it refits its Gaussian to."""


@dataclass(frozen=True)
class Measured:
    """The measured runs of one scenario: whether each arrived, and its time (seconds); the path
    length its times are divided by (metres), when the measurements give one."""

    scenario: Path
    arrived: tuple[bool, ...]
    time: tuple[float, ...]
    length_m: float | None = None

    def measure(self, failure_time: float, length_m: float) -> float:
        """BARN's measure of the runs: mean time (a failure counting ``failure_time``) per metre of path."""
        times = [t if ok else failure_time for ok, t in zip(self.arrived, self.time)]
        return sum(times) / len(times) / length_m

    @property
    def mostly_arrived(self) -> bool:
        return 2 * sum(self.arrived) > len(self.arrived)


def read_measured(path: Path) -> list[Measured]:
    """The measured runs of ``path``, grouped by scenario in the order each first appears.

    Raises:
        MazeError: at the line of an unknown or missing column, an unknown outcome, or a time that is
            not a finite number of seconds.
    """
    text = read_text(path, "measured runs")  # a FIFO or a directory is one line, never a wait
    rows = list(csv.reader(text.splitlines()))
    if not rows:
        raise MazeError(
            f"no measured runs: the first line names the columns {', '.join(COLUMNS)}", filename=str(path)
        )
    header = [name.strip() for name in rows[0]]
    for k, name in enumerate(header):
        if name not in COLUMNS + OPTIONAL_COLUMNS or name in header[:k]:
            what = "repeated" if name in header[:k] else "unknown"
            raise MazeError(
                f"{what} column {printable(name)!r}: a measured run is {', '.join(COLUMNS)}",
                filename=str(path), line=1,
            )  # fmt: skip
    missing = [name for name in COLUMNS if name not in header]
    if missing:
        raise MazeError(
            f"missing column {missing[0]!r}: a measured run is {', '.join(COLUMNS)}",
            filename=str(path),
            line=1,
        )
    runs: dict[Path, tuple[list[bool], list[float]]] = {}
    lengths: dict[Path, float] = {}
    for line, row in enumerate(rows[1:], start=2):
        if not any(cell.strip() for cell in row):
            continue
        if len(row) != len(header):
            raise MazeError(f"{len(row)} values, expected {len(header)}", filename=str(path), line=line)
        values = {name: cell.strip() for name, cell in zip(header, row)}
        if values["outcome"] not in MEASURED_OUTCOMES:
            raise MazeError(
                f"outcome {printable(values['outcome'])!r} is not one of {', '.join(MEASURED_OUTCOMES)}",
                filename=str(path), line=line,
            )  # fmt: skip
        seconds = _number(values["time"])
        if not seconds >= 0:
            raise MazeError(
                f"time {printable(values['time'])!r} is not a number of seconds",
                filename=str(path),
                line=line,
            )
        scenario = path.parent / values["scenario"]
        if "length" in values:
            _note_length(lengths, scenario, values["length"], path, line)
        arrived, times = runs.setdefault(scenario, ([], []))
        arrived.append(values["outcome"] == "arrived")
        times.append(seconds)
    if not runs:
        raise MazeError("no measured runs below the header", filename=str(path))
    return [
        Measured(scenario, tuple(ok), tuple(t), lengths.get(scenario)) for scenario, (ok, t) in runs.items()
    ]


def _number(text: str) -> float:
    """``text`` as a finite number, NaN when it is none."""
    try:
        value = float(text)
    except ValueError:
        return math.nan
    return value if math.isfinite(value) else math.nan


def _note_length(lengths: dict[Path, float], scenario: Path, text: str, path: Path, line: int) -> None:
    """Keep the path length of a row's scenario, which its earlier rows must have given alike."""
    metres = _number(text)
    if not metres > 0:
        raise MazeError(
            f"length {printable(text)!r} is not a number of metres", filename=str(path), line=line
        )
    earlier = lengths.setdefault(scenario, metres)
    if earlier != metres:
        raise MazeError(
            f"length {number(metres)} differs from the {number(earlier)} of this scenario's earlier runs",
            filename=str(path),
            line=line,
        )


@dataclass(frozen=True)
class SearchSpace:
    """The parameters searched: each one's name, box (SI) and default, and whether it is a count."""

    names: tuple[str, ...]
    low: np.ndarray
    high: np.ndarray
    default: np.ndarray
    count: np.ndarray

    @classmethod
    def of(cls, controller: str, names: Sequence[str] | None) -> SearchSpace:
        """The box of ``names`` (default: every parameter of ``controller`` that is not a count).

        Raises:
            MazeError: for a controller that is not bundled, or a parameter it does not have.
        """
        row = BUNDLED.get(controller)
        if row is None:
            raise MazeError(
                f"controller {controller!r} is not bundled: only a bundled controller's parameters are fitted"
            )
        chosen = list(names) if names else [p.name for p in row.parameters if not isinstance(p.default, int)]
        params = []
        for name in chosen:
            parameter = row.parameter(name)
            if parameter is None:
                known = ", ".join(p.name for p in row.parameters)
                raise MazeError(f"controller {controller} has no parameter {name!r} (it has {known})")
            params.append(parameter)
        count = np.array([isinstance(p.default, int) for p in params])
        default = np.array([float(p.default) for p in params])
        shrink, grow = np.where(count, 2.0, 4.0), np.where(count, 2.0, 4.0)
        low = np.maximum([p.low for p in params], np.where(default > 0, default / shrink, 0.0))
        high = np.minimum([p.high for p in params], np.where(default > 0, default * grow, 1.0))
        return cls(tuple(chosen), low, np.maximum(high, low), default, count)

    def values(self, unit: np.ndarray) -> np.ndarray:
        """SI values of points of the unit box (log-scaled where the box is positive)."""
        logged = self.low > 0
        safe_low = np.where(logged, self.low, 1.0)
        ratio = np.where(logged, self.high / safe_low, 1.0)
        values = np.where(logged, safe_low * ratio**unit, self.low + (self.high - self.low) * unit)
        return np.where(self.count, np.round(values), values)

    def unit(self, values: np.ndarray) -> np.ndarray:
        """The unit-box point of SI ``values`` (the inverse of :meth:`values`, counts aside)."""
        logged = (self.low > 0) & (self.high > self.low)
        with np.errstate(divide="ignore", invalid="ignore"):
            logs = np.log(values / self.low) / np.log(self.high / self.low)
            lines = (values - self.low) / (self.high - self.low)
        return np.clip(np.nan_to_num(np.where(logged, logs, lines)), 0.0, 1.0)


@dataclass(frozen=True)
class Agreement:
    """How a simulated controller agrees with the measured runs on some scenarios."""

    rho: float
    agreement: float
    simulated_success: float
    measured_success: float
    error: float

    @property
    def loss(self) -> float:
        rho = self.rho if math.isfinite(self.rho) else 0.0
        return (1.0 - rho) + (1.0 - self.agreement)


class FitProblem:
    """Measured scenarios made ready to drive, with their measures."""

    def __init__(self, measured: list[Measured], controller: str, failure_time: float) -> None:
        self.controller, self.failure_time = controller, failure_time
        self.floors: list[Floors] = []
        for runs in measured:
            floor = load_floor(runs.scenario)
            spec = floor.needs_spec("fitting")
            driving_robot(spec, str(runs.scenario))
            floors = Floors.of(spec, [(str(runs.scenario), floor.document)])
            if floors.without_path:
                raise MazeError(
                    "MazeGen finds no path on this floor: it cannot be driven", filename=str(runs.scenario)
                )
            self.floors.append(floors)
        self.units = [metres_per_unit(floors.spec.arena) for floors in self.floors]
        self.length_m = np.array(
            [
                float(f.population.measured["navigation"].path_length[0]) * u
                if m.length_m is None
                else m.length_m
                for f, u, m in zip(self.floors, self.units, measured)
            ]
        )
        self.measured = measured
        self.target = np.array(
            [m.measure(failure_time, length) for m, length in zip(measured, self.length_m)]
        )
        self.mostly_arrived = np.array([m.mostly_arrived for m in measured])

    @property
    def spec(self) -> Spec:
        return self.floors[0].spec

    def simulate(
        self, space: SearchSpace, values: np.ndarray, rows: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """The simulated measure and arrival of scenarios ``rows`` with the parameters ``values`` (SI)."""
        from mazegen.runtime.simulation import ARRIVED, DriveRequest, drive_many

        requests = []
        for k in rows.tolist():
            floors, unit = self.floors[k], self.units[k]
            robot = floors.robot
            own = dict(robot.controller(self.controller).params)
            row = BUNDLED[self.controller]
            for name, value in zip(space.names, values.tolist()):
                own[name] = value / unit if row.parameter(name).scaled else value  # type: ignore[union-attr]
            controller = ControllerSpec(self.controller, tuple(own.items()))
            requests.append(DriveRequest(floors.population, robot, controller, np.zeros(1, np.int64)))
        episodes = drive_many(requests)
        arrived = np.array([e.outcome[0] == ARRIVED for e in episodes])
        seconds = np.array([float(e.time[0]) for e in episodes])
        return np.where(arrived, seconds, self.failure_time) / self.length_m[rows], arrived

    def agreement(self, space: SearchSpace, values: np.ndarray, rows: np.ndarray) -> Agreement:
        simulated, arrived = self.simulate(space, values, rows)
        target = self.target[rows]
        return Agreement(
            rho=spearman(simulated, target) if len(rows) > 1 else math.nan,
            agreement=float((arrived == self.mostly_arrived[rows]).mean()),
            simulated_success=float(arrived.mean()),
            measured_success=float(np.mean([np.mean(self.measured[k].arrived) for k in rows.tolist()])),
            error=float(np.abs(simulated - target).mean()),
        )


def cross_entropy(
    loss: Callable[[np.ndarray], float], space: SearchSpace, rng: np.random.Generator, budget: int
) -> tuple[np.ndarray, float]:
    """The parameters (SI) of least ``loss`` the cross-entropy method finds in ``budget`` evaluations,
    starting from the defaults, and their loss."""
    start = space.unit(space.default)
    best_values, best_loss = space.values(start), loss(space.values(start))
    mean, spread = start, np.full(len(start), 0.3)
    for _ in range(max(0, budget - 1) // POPULATION):
        points = np.clip(mean + spread * rng.standard_normal((POPULATION, len(start))), 0.0, 1.0)
        losses = np.array([loss(space.values(point)) for point in points])
        order = np.argsort(losses, kind="stable")
        if losses[order[0]] < best_loss:
            best_values, best_loss = space.values(points[order[0]]), float(losses[order[0]])
        elite = points[order[:ELITES]]
        mean, spread = elite.mean(axis=0), np.maximum(elite.std(axis=0), 0.02)
    return best_values, best_loss


def folds_of(count: int, folds: int, rng: np.random.Generator) -> list[np.ndarray]:
    """``folds`` disjoint sets of scenario rows covering all ``count``, drawn at random."""
    order = rng.permutation(count)
    return [np.sort(order[k::folds]) for k in range(folds)]


def robot_block(controller: str, space: SearchSpace, values: np.ndarray, spec: Spec, source: str) -> str:
    """A robot block setting the fitted parameters, in the arena's unit, for a spec to import."""
    unit = metres_per_unit(spec.arena)
    row = BUNDLED[controller]
    settings = []
    for name, value in zip(space.names, values.tolist()):
        parameter = row.parameter(name)
        assert parameter is not None  # SearchSpace.of checked it
        if parameter.unit in (ANGLE, TURN):  # a spec writes angles in degrees
            written = math.degrees(value)
        else:
            written = value / unit if parameter.scaled else value
        shown = str(round(written)) if isinstance(parameter.default, int) else number(round(written, 6))
        settings.append(f"{name} {shown}")
    return (
        f"// Fitted by mazegen fit to the measured runs of {source}: {controller}'s "
        f"{', '.join(space.names)} (lengths in {spec.arena.unit}, times in seconds, angles in degrees).\n"
        f"robot {{\n    controller {controller} {{ {'  '.join(settings)} }}\n}}\n"
    )


@dataclass(frozen=True)
class Fit:
    """What a fit found: the fitted parameters (SI), and how the defaults, the fit and each held-out
    fold agree with the measured runs; each fold's scenario rows and the parameters fitted on the
    others, to check a fold under another protocol."""

    space: SearchSpace
    fitted: np.ndarray
    default: Agreement
    result: Agreement
    held_out: tuple[Agreement, ...]
    folds: tuple[np.ndarray, ...] = ()
    fold_fits: tuple[np.ndarray, ...] = ()


def fit_controller(problem: FitProblem, space: SearchSpace, *, folds: int, budget: int, seed: int) -> Fit:
    """Fit ``space`` to all of ``problem``'s scenarios, after ``folds``-fold cross-validation (each
    fold's held-out agreement, fitted on the others; none for 1 fold), ``budget`` evaluations a fit,
    every draw from ``numpy.random.default_rng(seed)``."""
    rng = np.random.default_rng(seed)
    rows = np.arange(len(problem.measured))
    tests = folds_of(len(rows), folds, rng) if folds > 1 else []

    def loss_on(scenarios: np.ndarray) -> Callable[[np.ndarray], float]:
        return lambda values: problem.agreement(space, values, scenarios).loss

    fold_fits = [cross_entropy(loss_on(np.setdiff1d(rows, test)), space, rng, budget)[0] for test in tests]
    values, _ = cross_entropy(loss_on(rows), space, rng, budget)
    return Fit(
        space,
        values,
        problem.agreement(space, space.default, rows),
        problem.agreement(space, values, rows),
        tuple(problem.agreement(space, fitted, test) for fitted, test in zip(fold_fits, tests)),
        tuple(tests),
        tuple(fold_fits),
    )
