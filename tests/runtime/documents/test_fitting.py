"""mazegen fit: controller parameters fitted to measured runs, checked on runs a known controller made."""

from __future__ import annotations

import os

import numpy as np
import pytest
from click.testing import CliRunner

import mazegen
from mazegen.cli.main import main
from mazegen.errors import MazeError
from mazegen.runtime.documents import FitProblem, SearchSpace, fit_controller, read_measured
from tests.conftest import EXAMPLES
from tests.runtime.documents.test_import import imported

TRUTH = {"obstacle_weight": 0.35, "inflation": 0.55}
"""The parameters of the 'real stack' whose runs are measured: dwa, set otherwise than its defaults."""


@pytest.fixture(scope="module")
def measured(tmp_path_factory):
    """Floors of an imported map, 10 tasks, each driven by dwa with :data:`TRUTH`, as a measured CSV."""
    folder = tmp_path_factory.mktemp("fit")
    files = imported(EXAMPLES / "maps" / "warehouse.yaml", folder / "floors", "--tasks", "10", "--seed", "3")
    space = SearchSpace.of("dwa", list(TRUTH))
    fake = [mazegen.runtime.documents.Measured(path, (True,), (1.0,)) for path in files]
    problem = FitProblem(fake, "dwa", 30.0)
    seconds, arrived = problem.simulate(space, np.array(list(TRUTH.values())), np.arange(len(files)))
    lines = ["scenario,outcome,time"]
    for path, per_metre, ok, length in zip(files, seconds, arrived, problem.length_m):
        lines.append(f"{path.relative_to(folder)},{'arrived' if ok else 'timeout'},{per_metre * length:.4f}")
    (folder / "measured.csv").write_text("\n".join(lines) + "\n")
    return folder / "measured.csv"


def test_a_fit_agrees_with_the_measured_runs_at_least_as_well_as_the_defaults(measured):
    runs = read_measured(measured)
    problem = FitProblem(runs, "dwa", 30.0)
    space = SearchSpace.of("dwa", list(TRUTH))
    found = fit_controller(problem, space, folds=2, budget=33, seed=4)
    assert found.default.loss > 0.05 and found.result.loss < found.default.loss  # the search found better
    truth = problem.agreement(space, np.array(list(TRUTH.values())), np.arange(len(runs)))
    assert truth.rho == pytest.approx(1.0) and truth.agreement == 1.0  # the measure is the simulator's own
    assert len(found.held_out) == 2
    assert np.all((space.low <= found.fitted) & (found.fitted <= space.high))
    # Each fold's own fit, to check it under another protocol: the folds cover the scenarios once.
    assert np.array_equal(np.sort(np.concatenate(found.folds)), np.arange(len(runs)))
    for fitted, rows, agreement in zip(found.fold_fits, found.folds, found.held_out):
        assert problem.agreement(space, fitted, rows) == agreement


def test_the_written_robot_block_imports_into_a_spec_and_the_same_seed_writes_the_same_bytes(
    measured, tmp_path
):
    outs = []
    for name in ("a.maze", "b.maze"):
        result = CliRunner().invoke(
            main,
            ["fit", str(measured), "-c", "dwa", "--params", "obstacle_weight,inflation", "--folds", "1",
             "--budget", "17", "-o", str(tmp_path / name)],
        )  # fmt: skip
        assert result.exit_code == 0, result.output
        assert "fitted, all scenarios" in result.output and "obstacle_weight" in result.output
        outs.append((tmp_path / name).read_bytes())
    assert outs[0] == outs[1]
    floors = measured.parent / "floors"
    spec_text = next(floors.glob("*.maze")).read_text()
    (tmp_path / "fitted.maze").write_text('import "a.maze"\n' + spec_text)
    robot = mazegen.load(tmp_path / "fitted.maze").robot
    assert robot is not None and [c.name for c in robot.controllers] == ["dwa"]
    assert {name for name, _ in robot.controllers[0].params} == set(TRUTH)


@pytest.mark.parametrize(
    ("rows", "line", "message"),
    [
        ("scenario,outcome,seconds\n", 1, "unknown column 'seconds'"),
        ("scenario,outcome\n", 1, "missing column 'time'"),
        ("scenario,outcome,time\nx.json,crashed,3\n", 2, "outcome 'crashed' is not one of"),
        ("scenario,outcome,time\nx.json,arrived,3\nx.json,arrived,nan\n", 3, "time 'nan' is not a number"),
        ("scenario,outcome,time\nx.json,arrived\n", 2, "2 values, expected 3"),
        ("scenario,outcome,time,length\nx.json,arrived,3,0\n", 2, "length '0' is not a number of metres"),
        (
            "scenario,length,outcome,time\nx.json,5,arrived,3\nx.json,6,timeout,9\n",
            3,
            "length 6 differs from the 5",
        ),
    ],
)
def test_a_bad_measured_file_is_one_line_at_its_line(tmp_path, rows, line, message):
    path = tmp_path / "measured.csv"
    path.write_text(rows)
    with pytest.raises(MazeError, match=message) as caught:
        read_measured(path)
    assert caught.value.line == line
    result = CliRunner().invoke(main, ["fit", str(path), "-c", "dwa", "-o", str(tmp_path / "r.maze")])
    assert result.exit_code == 1 and len(result.stderr.splitlines()) == 1 and f":{line}:" in result.stderr


def test_a_length_column_is_what_the_times_are_divided_by(measured, tmp_path):
    """The measure of a scenario with a measured path length (BARN's, say) is its time over that
    length, the simulated as the measured; without one, over MazeGen's shortest path."""
    lines = measured.read_text().splitlines()
    given = [round(1.5 + 0.25 * k, 2) for k in range(len(lines) - 1)]
    (tmp_path / "floors").symlink_to(measured.parent / "floors")
    with_length = tmp_path / "measured.csv"
    rows = [f"{lines[0]},length"] + [f"{line},{metres}" for line, metres in zip(lines[1:], given)]
    with_length.write_text("\n".join(rows) + "\n")
    plain, runs = read_measured(measured), read_measured(with_length)
    assert [m.length_m for m in plain] == [None] * len(plain) and [m.length_m for m in runs] == given
    own, by_length = FitProblem(plain, "dwa", 30.0), FitProblem(runs, "dwa", 30.0)
    assert np.array_equal(by_length.length_m, given) and not np.allclose(own.length_m, given)
    assert np.allclose(by_length.target * by_length.length_m, own.target * own.length_m)
    space = SearchSpace.of("dwa", list(TRUTH))
    rows = np.arange(len(runs))
    simulated, arrived = by_length.simulate(space, np.array(list(TRUTH.values())), rows)
    assert np.allclose(simulated, by_length.target) and np.array_equal(arrived, by_length.mostly_arrived)


def test_only_a_bundled_controllers_own_parameters_are_fitted():
    with pytest.raises(MazeError, match="has no parameter 'speed'"):
        SearchSpace.of("dwa", ["speed"])
    with pytest.raises(MazeError, match="is not bundled"):
        SearchSpace.of("pkg.mod:policy", None)
    assert "v_samples" not in SearchSpace.of("dwa", None).names  # counts are left alone by default


def test_a_measured_file_that_is_a_fifo_is_refused_in_one_line_not_waited_on(tmp_path):
    fifo = tmp_path / "measured.csv"
    os.mkfifo(fifo)
    with pytest.raises(MazeError, match="cannot read measured runs: a FIFO, not a regular file"):
        read_measured(fifo)
