"""Drive terms at run time: who is driven, what each term scores, one drive per controller and
population, no drive of a cached genome, and no simulator loaded by a spec that drives nothing."""

from __future__ import annotations

import dataclasses
import math
import subprocess
import sys

import numpy as np
import pytest

from mazegen.runtime import metrics, simulation
from mazegen.runtime.engine import _operators as ops
from mazegen.runtime.engine._evolution import evolve
from mazegen.runtime.simulation import ARRIVED
from mazegen.spec import Evolution, FitnessTerm
from tests.conftest import EXAMPLES
from tests.drive_fakes import DRIVE_SPEC, FakeDrive, build_problem, floor_code, has_path, outcome_of

DRIVING = (
    DRIVE_SPEC
    + """
robot { drive best 0.25  timeout factor 6 }
fitness {
    count
    solvable required
    controller dwa fails weight 2
    controller dwa time 2..4
    controller dwa clearance
    controllers dwa, straight disagree
}
"""
)


@pytest.fixture
def fake_drive(monkeypatch) -> FakeDrive:
    fake = FakeDrive()
    monkeypatch.setattr(simulation, "drive", fake, raising=False)
    return fake


@pytest.fixture(scope="module")
def driving(tmp_path_factory):
    return build_problem(DRIVING, tmp_path_factory.mktemp("driving"))


def decoded(problem, size: int, seed: int = 3):
    rng = np.random.default_rng(seed)
    codons = ops.random_codons(rng, size, problem.spec.evolution.genome, problem.spec.evolution.codon_max)
    genes = ops.random_genes(rng, size, problem.slots)
    return problem.decode(codons, genes, searching=True)[1]


def test_the_best_fraction_of_those_kept_is_driven_once_per_controller(driving, fake_drive):
    pop = decoded(driving, 200)
    driving.fitness_module.terms(pop)
    kept = np.flatnonzero(pop.valid & ~driving.fitness_module.rejected(pop))
    assert kept.size > 60  # enough to choose among
    [(dwa, driven), (straight, again)] = fake_drive.calls  # three dwa terms, one drive
    assert (dwa, straight) == ("dwa", "straight") and np.array_equal(driven, again)
    assert driven.size == math.ceil(0.25 * pop.size)
    assert set(driven) <= set(kept)
    passed_over = np.setdiff1d(kept, driven)
    assert pop.n_elements[driven].min() >= pop.n_elements[passed_over].max()  # by count, the static term


def test_each_drive_term_scores_what_the_docs_say(driving, fake_drive):
    pop = decoded(driving, 200)
    scores = driving.fitness_module.terms(pop)
    driven = fake_drive.calls[0][1]
    undriven = np.setdiff1d(np.arange(pop.size), driven)
    for key in ("dwa_fails", "dwa_time", "dwa_clearance", "dwa_straight_disagree"):
        assert not scores[key][undriven].any(), key  # no credit
    for row in driven:
        if not has_path(pop, row):  # no path: nothing to judge
            assert [scores[key][row] for key in ("dwa_fails", "dwa_time", "dwa_straight_disagree")] == [
                0,
                0,
                0,
            ]
            continue
        failed = outcome_of(pop, int(row)) != ARRIVED
        assert scores["dwa_fails"][row] == (2.0 if failed else 0.0)
        ratio = 6.0 if failed else 25.0 / 10.0  # a failure counts as the timeout factor
        assert scores["dwa_time"][row] == pytest.approx(math.exp(-(ratio - 4) / 2) if ratio > 4 else 1.0)
        assert scores["dwa_clearance"][row] == floor_code(pop, row)  # the fake's closest approach
        assert scores["dwa_straight_disagree"][row] == 1.0


def test_drive_all_drives_every_valid_individual_not_rejected(tmp_path, fake_drive):
    problem = build_problem(DRIVING.replace("drive best 0.25", "drive all"), tmp_path)
    pop = decoded(problem, 100)
    problem.fitness_module.terms(pop)
    kept = np.flatnonzero(pop.valid & ~problem.fitness_module.rejected(pop))
    assert np.array_equal(fake_drive.calls[0][1], kept)


def test_a_drive_is_kept_with_its_population(driving, fake_drive):
    pop = decoded(driving, 40)
    driven = np.array([1, 2, 5])
    first = metrics.drive_fails(pop, "dwa", driven)
    assert np.array_equal(metrics.drive_fails(pop, "dwa", driven), first, equal_nan=True)
    metrics.drive_time(pop, "dwa", driven)
    assert len(fake_drive.calls) == 1
    metrics.drive_fails(pop, "dwa", np.array([3]))  # other individuals: driven anew
    assert len(fake_drive.calls) == 2


def run_counting(problem, fake: FakeDrive, settings: Evolution):
    sizes: list[int] = []
    original = problem.fitness_module.terms

    def terms(pop):
        sizes.append(pop.size)
        return original(pop)

    problem.fitness_module.terms = terms
    try:
        result = evolve(problem, settings, np.random.default_rng(5))
    finally:
        problem.fitness_module.terms = original
    return result, sizes


def test_a_cached_genome_is_never_driven_again(driving, fake_drive):
    """Children that are copies of their parents are all cached: only generation 0 is driven."""
    settings = Evolution(population=40, generations=3, crossover=0.0, mutation=0.0, elitism=1)
    result, _ = run_counting(driving, fake_drive, settings)
    assert [stats.evaluations for stats in result.stats][1:] == [0, 0, 0]
    assert [name for name, _ in fake_drive.calls] == ["dwa", "straight"]


def test_only_the_genomes_a_generation_evaluates_are_driven(driving, fake_drive):
    settings = Evolution(population=40, generations=3, mutation=0.2, elitism=2)
    result, sizes = run_counting(driving, fake_drive, settings)
    evaluated = [stats.evaluations for stats in result.stats]
    assert sizes == [n for n in evaluated if n]  # the fitness sees the uncached genomes only
    driven = [rows.size for name, rows in fake_drive.calls if name == "dwa"]
    assert len(driven) == len(sizes)  # one drive per evaluation, however many terms
    assert all(count <= math.ceil(0.25 * size) for count, size in zip(driven, sizes))
    assert fake_drive.episodes("dwa") < sum(evaluated) < 4 * settings.population


LOADED = """
import sys
import mazegen
mazegen.run(sys.argv[1], population=10, generations=1, runs=1, out_dir=sys.argv[2], executor="serial",
            catalog=False)
simulator = sorted(name for name in sys.modules if name.startswith("mazegen.runtime.simulation."))
print("loaded:" + ",".join(simulator))
"""


def test_a_spec_without_drive_terms_loads_none_of_the_simulator(tmp_path):
    done = subprocess.run(
        [sys.executable, "-c", LOADED, str(EXAMPLES / "factory.maze"), str(tmp_path / "run")],
        capture_output=True,
        text=True,
        check=True,
    )
    loaded = set(filter(None, done.stdout.splitlines()[-1].removeprefix("loaded:").split(",")))
    assert loaded <= {"mazegen.runtime.simulation._episodes"}, loaded  # what a drive returns: no kernels


def test_a_run_scores_drive_terms_with_the_simulator(tmp_path):
    """End to end with the real simulator: the generated terms give what driving the floors gives."""
    text = DRIVE_SPEC + (
        "robot { drive all }\n"
        "fitness { solvable required  controller straight fails  controller purepursuit time 1..3 }\n"
    )
    problem = build_problem(text, tmp_path)
    pop = decoded(problem, 24, seed=11)
    scores = problem.fitness_module.terms(pop)
    driven = np.flatnonzero(pop.valid & ~problem.fitness_module.rejected(pop))
    assert driven.size >= 5
    episodes = simulation.drive(pop, robot=problem.spec.robot, controller="straight", indices=driven)
    assert np.array_equal(scores["straight_fails"][driven], episodes.failed.astype(float))
    pursuit = simulation.drive(pop, robot=problem.spec.robot, controller="purepursuit", indices=driven)
    ratio = np.where(pursuit.failed, problem.spec.robot.timeout, pursuit.time / pursuit.optimal_time)
    assert np.allclose(scores["purepursuit_time"][driven], metrics.closeness(ratio, 1.0, 3.0))
    assert not scores["straight_fails"][np.setdiff1d(np.arange(pop.size), driven)].any()


def test_a_run_of_a_driving_spec_waits_for_the_simulators_kernels(driving, tmp_path):
    from mazegen.runtime import CONTROLLER_KERNELS, EVERY_RUN_KERNELS, POLICY_KERNEL, run_kernels

    named = {CONTROLLER_KERNELS[name] for name in driving.spec.drive_controllers}
    assert run_kernels(driving.spec) == EVERY_RUN_KERNELS + tuple(sorted(named))
    plain = build_problem(DRIVE_SPEC + "robot { drive all }\nfitness { count }\n", tmp_path)
    assert run_kernels(plain.spec) == EVERY_RUN_KERNELS
    policy = dataclasses.replace(
        driving.spec, fitness=(FitnessTerm("drive", metric="fails", controllers=("my.pkg:policy",)),)
    )
    assert run_kernels(policy) == (*EVERY_RUN_KERNELS, POLICY_KERNEL)


def test_a_policy_a_build_cannot_find_is_said_as_the_simulator_says_it_not_as_fitness_py(driving, tmp_path):
    """A build's spec.json is not read by the language, which would have named the spec's line."""
    from mazegen.errors import MazeError
    from mazegen.generator.build import build
    from mazegen.runtime.engine._problem import Problem

    term = FitnessTerm("drive", metric="fails", controllers=("nosuch_policy_module:policy",))
    build(dataclasses.replace(driving.spec, fitness=(term,)), tmp_path)
    problem = Problem.from_build_dir(tmp_path)
    with pytest.raises(MazeError) as raised:
        problem.score(decoded(problem, 24))
    assert str(raised.value) == (
        "controller nosuch_policy_module:policy: cannot load it (No module named 'nosuch_policy_module'): "
        "a policy's module is looked for in the current folder, PYTHONPATH or the installed packages"
    )


def test_the_first_run_says_it_compiles_when_only_the_simulator_is_missing(driving, monkeypatch, capsys):
    import mazegen.runtime
    from mazegen.cli.launching import compile_first
    from mazegen.runtime import EVERY_RUN_KERNELS
    from mazegen.runtime.runs._progress import FIRST_COMPILE_NOTE, QuietReporter

    asked: list[tuple[str, ...]] = []

    def cached(kernels=()):
        asked.append(kernels)
        return not any(kernel.startswith(("_controllers.", "_dwa.", "_vfh.")) for kernel in kernels)

    compiled = []
    monkeypatch.setattr(mazegen.runtime, "kernels_cached", cached)
    monkeypatch.setattr(
        "mazegen.runtime.runs._warmup.compile_kernels", lambda problem: compiled.append(problem.spec.name)
    )
    compile_first(driving, "serial", QuietReporter())
    assert set(asked[-1]) > set(EVERY_RUN_KERNELS)
    assert compiled == [driving.spec.name]
    assert FIRST_COMPILE_NOTE in capsys.readouterr().err


def test_the_warm_up_drives_each_controller_once(driving, fake_drive):
    from mazegen.runtime.runs._warmup import compile_path_kernels

    compile_path_kernels(driving.spec)
    assert [name for name, _ in fake_drive.calls] == ["dwa", "straight"]
    fake_drive.calls.clear()
    compile_path_kernels(dataclasses.replace(driving.spec, fitness=(FitnessTerm("count"),)))
    assert fake_drive.calls == []


def test_outside_a_search_every_individual_kept_is_driven(driving, fake_drive):
    rng = np.random.default_rng(3)
    codons = ops.random_codons(rng, 60, driving.spec.evolution.genome, driving.spec.evolution.codon_max)
    genes = ops.random_genes(rng, 60, driving.slots)
    evaluation = driving.evaluate(codons, genes)
    pop = evaluation.population
    kept = np.flatnonzero(pop.valid & ~driving.fitness_module.rejected(pop))
    assert np.array_equal(fake_drive.calls[0][1], kept)
    driving.evaluate(codons, genes, searching=True)
    assert fake_drive.calls[-1][1].size == math.ceil(0.25 * 60) < kept.size


def fails_in_document(problem, document) -> bool:
    """Whether the fake fails on a scenario document's floor (decoded from its genome) with a path."""
    codons = np.array([document["origin"]["codons"]])
    genes = np.array([document["origin"]["placement"]])
    floor = problem.decode(codons, genes)[1]
    return has_path(floor, 0) and outcome_of(floor, 0) != ARRIVED


def test_the_best_scenarios_written_carry_their_whole_fitness(tmp_path, fake_drive):
    from mazegen.runtime.documents._best import best_documents

    problem = build_problem(DRIVING.replace("drive best 0.25", "drive best 0.1"), tmp_path)
    result = evolve(problem, Evolution(population=40, generations=2), np.random.default_rng(2))
    documents = best_documents(problem, result, count=10, origin={})
    assert len(documents) >= 6
    assert sum(document["terms"]["dwa_fails"] > 0 for document in documents) > 4  # more than 0.1 × 40
    for document in documents:
        genome = np.flatnonzero(
            (result.codons == document["origin"]["codons"]).all(axis=1)
            & (result.genes == np.array(document["origin"]["placement"])).all(axis=(1, 2))
        )
        # Every scenario written is driven: its fitness is the run's when the run drove it, more when
        # the run scored it on its static terms alone; never a static-only score for a driven floor.
        assert document["fitness"] >= result.fitness[genome[0]] - 1e-9
        assert document["terms"]["dwa_fails"] == 2.0 * fails_in_document(problem, document)
