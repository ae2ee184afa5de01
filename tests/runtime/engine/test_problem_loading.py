"""Loading a build: the grammar and the fitness module are parsed once per process and text."""

from __future__ import annotations

import mazegen
from mazegen.generator.build import build
from mazegen.runtime.engine._problem import Problem
from mazegen.runtime.runs._worker import BuildFiles, problem_of
from tests.conftest import EXAMPLES


def built(tmp_path):
    build(mazegen.load(EXAMPLES / "mazegen1.maze"), tmp_path)
    return tmp_path


def test_a_build_loaded_again_shares_its_module_until_fitness_py_is_edited(tmp_path):
    folder = built(tmp_path)
    first, again = Problem.from_build_dir(folder), Problem.from_build_dir(folder)
    assert again.fitness_module is first.fitness_module and again.compiled is first.compiled
    fitness = folder / "fitness.py"
    fitness.write_text(fitness.read_text(encoding="utf-8") + "\nEDITED = True\n", encoding="utf-8")
    edited = Problem.from_build_dir(folder)
    assert edited.fitness_module is not first.fitness_module
    assert edited.fitness_module.EDITED and not hasattr(first.fitness_module, "EDITED")


def test_a_worker_loads_the_grammar_and_fitness_once_whatever_the_seed(tmp_path):
    folder = built(tmp_path)
    problem = Problem.from_build_dir(folder)
    texts = {name: (folder / name).read_text(encoding="utf-8") for name in ("grammar.bnf", "fitness.py")}

    def files(seed: int, fitness: str = texts["fitness.py"]) -> BuildFiles:
        return BuildFiles(problem.spec.with_evolution(seed=seed), texts["grammar.bnf"], fitness)

    one, other = problem_of(files(1)), problem_of(files(2))
    assert other.fitness_module is one.fitness_module and other.compiled is one.compiled
    assert (one.spec.evolution.seed, other.spec.evolution.seed) == (1, 2)
    assert files(1).digest == files(1).digest != files(2).digest  # checkpoints tell the runs apart
    edited = problem_of(files(1, texts["fitness.py"] + "\nEDITED = True\n"))
    assert edited.fitness_module is not one.fitness_module and edited.fitness_module.EDITED
