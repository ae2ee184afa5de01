"""Train a navigation policy on MazeGen's floors with an evolution strategy, in NumPy alone, and compare
two curricula: uniform floors, and a prioritised level sampler fed by the mutator (ACCEL-style).

Usage:
    python examples/learning/train.py                  # both curricula, a few minutes on 2 cores
    python examples/learning/train.py --iterations 3 --candidates 4 --levels 4 --held-out 16   # a quick look

The policy is a small network (lidar sectors, the goal, a waypoint 1 m ahead along the level's path and
the velocity in; speed and turn rate out) whose weights an OpenAI-style evolution strategy searches:
antithetic Gaussian perturbations, centred ranks, Adam. Each iteration plays every candidate on the
same few levels at once, in one ``FloorVectorEnv`` (candidates x levels sub-environments); a
candidate's fitness is its mean episode return. Both curricula train on the floors of a few graded
suites of the bundled training spec (``mazegen suite``, each with a seed of its own: floors spread over
difficulty and element count, where fresh random floors of the spec are mostly near-empty). The
uniform curriculum draws them uniformly every iteration; the prioritised one draws them from a
``LevelSampler`` scored by learnability (``p (1 - p)``, ``p`` the share of candidates that arrive:
floors some candidates solve and some do not), into which the mutator adds children of the floors it
replays. Both policies then drive in the environment, and ``straight`` and ``purepursuit`` through
``mazegen``'s ``drive`` (the same simulator), over a held-out suite (a suite of the same spec, a seed of
its own): success, BARN's score, and success on the hardest quarter by MazeGen's difficulty.
Writes ``examples/learning/out/`` (``--out``): the policies' weights and the figures.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from mazegen.gym import (
    TRAINING_SPEC,
    FloorVectorEnv,
    LevelMutator,
    LevelPool,
    Levels,
    LevelSampler,
    SpecLevels,
    file_levels,
)
from mazegen.runtime.simulation import ARRIVED, barn_score, drive

BEAMS, SECTORS, HIDDEN = 64, 16, 16
WAYPOINT = 1.0
"""Metres ahead along the level's path (MazeGen's, kept clear) of the waypoint the policy sees, as BARN's
learned planners read the global plan."""
INPUTS = SECTORS + 8  # lidar sectors; goal and waypoint (squashed distance, cosine, sine); velocity
SIZES = [(INPUTS, HIDDEN), (HIDDEN,), (HIDDEN, 2), (2,)]
PARAMETERS = sum(math.prod(shape) for shape in SIZES)
OUT = Path(__file__).with_name("out")


def features(seen: dict[str, np.ndarray], reach: float, limits: np.ndarray) -> np.ndarray:
    """The network's inputs: the nearest range in each of ``SECTORS`` sectors over the lidar's range;
    the goal's and the waypoint's distances squashed by the range and their bearings' cosines and sines;
    the velocity over the robot's limits."""
    sectors = seen["scan"].reshape(len(seen["scan"]), SECTORS, -1).min(axis=2) / reach
    goal, waypoint = seen["goal"], seen["waypoint"]
    squashed = np.tanh(np.column_stack([goal[:, 0], waypoint[:, 0]]) / (4 * reach))
    speed = seen["velocity"] / np.array([limits[0], limits[2]])
    return np.hstack([sectors, squashed, goal[:, 1:], waypoint[:, 1:], speed])


def act(weights: np.ndarray, inputs: np.ndarray, limits: np.ndarray) -> np.ndarray:
    """Commands ``(v, w)`` of networks ``weights`` (``[n, PARAMETERS]``, one per row of ``inputs``)."""
    at, layers = 0, []
    for shape in SIZES:
        size = math.prod(shape)
        layers.append(weights[:, at : at + size].reshape(len(weights), *shape))
        at += size
    w1, b1, w2, b2 = layers
    hidden = np.tanh(np.einsum("ni,nih->nh", inputs, w1) + b1)
    out = np.einsum("nh,nho->no", hidden, w2) + b2
    return np.column_stack([limits[0] / (1 + np.exp(-out[:, 0])), limits[2] * np.tanh(out[:, 1])])


def play(
    env: FloorVectorEnv, weights: np.ndarray, levels: Levels
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each sub-environment's first episode on ``levels`` with its row of ``weights``: its return,
    whether it arrived, and its steps."""
    observation, _ = env.reset(options={"levels": levels})
    limits, reach = levels.rows.limits[0], float(levels.rows.reach[0])
    total, steps = np.zeros(env.num_envs), np.zeros(env.num_envs)
    done = np.zeros(env.num_envs, bool)
    arrived = np.zeros(env.num_envs, bool)
    while not done.all():
        observation, reward, terminated, truncated, info = env.step(
            act(weights, features(observation, reach, limits), limits)
        )
        total += np.where(done, 0.0, reward)
        steps += ~done
        ending = (terminated | truncated) & ~done
        arrived |= ending & (info["outcome"] == ARRIVED)
        done |= ending
    return total, arrived, steps


class Adam:
    def __init__(self, size: int, rate: float) -> None:
        self.m, self.v, self.t, self.rate = np.zeros(size), np.zeros(size), 0, rate

    def step(self, gradient: np.ndarray) -> np.ndarray:
        self.t += 1
        self.m = 0.9 * self.m + 0.1 * gradient
        self.v = 0.999 * self.v + 0.001 * gradient**2
        m, v = self.m / (1 - 0.9**self.t), self.v / (1 - 0.999**self.t)
        return self.rate * m / (np.sqrt(v) + 1e-8)


def centred_ranks(values: np.ndarray) -> np.ndarray:
    ranks = np.empty(len(values))
    ranks[np.argsort(values, kind="stable")] = np.arange(len(values))
    return ranks / (len(values) - 1) - 0.5


def train(
    curriculum: str, generator: SpecLevels, floors: LevelPool, args: argparse.Namespace
) -> tuple[np.ndarray, list[dict]]:
    """The weights an evolution strategy finds under ``curriculum`` (``uniform`` or ``prioritised``) on
    the training ``floors``."""
    rng = np.random.default_rng(args.seed)
    theta = rng.normal(0.0, 0.1, PARAMETERS)
    adam = Adam(PARAMETERS, args.rate)
    pairs = args.candidates // 2
    env = FloorVectorEnv(
        2 * pairs * args.levels, levels=generator, beams=BEAMS, waypoint=WAYPOINT, seed=args.seed
    )
    sampler = LevelSampler(capacity=400, replay_prob=0.8, minimum_fill_ratio=0.05, generator=floors)
    mutator = LevelMutator(generator)
    history = []
    for iteration in range(args.iterations):
        levels = (
            floors.sample(rng, args.levels) if curriculum == "uniform" else sampler.sample(rng, args.levels)
        )
        noise = rng.normal(size=(pairs, PARAMETERS))
        candidates = np.vstack([theta + args.sigma * noise, theta - args.sigma * noise])
        weights = np.repeat(candidates, args.levels, axis=0)  # candidate c plays every level
        returns, arrived, _ = play(
            env, weights, levels.take(np.tile(np.arange(args.levels), len(candidates)))
        )
        fitness = returns.reshape(len(candidates), args.levels).mean(axis=1)
        ranks = centred_ranks(fitness)
        gradient = (ranks[:pairs] - ranks[pairs:]) @ noise / (pairs * args.sigma)
        theta = theta + adam.step(gradient - 0.005 * theta)
        success = arrived.reshape(len(candidates), args.levels).mean(axis=0)  # per level, over candidates
        if curriculum == "prioritised":
            held = sampler.index_of(levels.hashes)
            sampler.update(held[held >= 0], (success * (1 - success))[held >= 0])
            learnable = np.flatnonzero((success > 0) & (success < 1))
            if learnable.size:
                children = mutator.mutate(rng, levels.take(learnable), learnable.size)
                sampler.insert(children, 0.25)
        history.append(
            {"iteration": iteration, "fitness": float(fitness.mean()), "success": float(success.mean())}
        )
        mean, share = fitness.mean(), success.mean()
        print(f"{curriculum:11s} iteration {iteration:3d}: mean return {mean:7.2f}, arrived {share:.2f}")
    return theta, history


def suite(generator: SpecLevels, name: str, seed: int, args: argparse.Namespace) -> Levels:
    """A graded suite of the training spec made by ``mazegen suite`` with ``seed``: floors spread over
    difficulty and element count (its archive holds about a hundred)."""
    folder = args.out / name
    command = [sys.executable, "-m", "mazegen", "suite", str(TRAINING_SPEC), "--size", str(args.held_out)]
    command += ["--seed", str(seed), "--iterations", str(args.suite_iterations)]
    subprocess.run([*command, "-o", str(folder), "--force", "--quiet"], check=True)
    return file_levels(folder, robot=generator.robot)


def training_floors(generator: SpecLevels, args: argparse.Namespace) -> LevelPool:
    """The floors both curricula train on: ``--training-suites`` suites, each with a seed of its own."""
    seeds = range(args.seed + 2000, args.seed + 2000 + args.training_suites)
    return LevelPool(Levels.joined([suite(generator, f"training-suite-{k}", k, args) for k in seeds]))


def held_out_table(
    generator: SpecLevels, policies: dict[str, np.ndarray], args: argparse.Namespace
) -> list[dict]:
    """Success and BARN's score of each controller on the held-out suite (all, and its hardest quarter)."""
    levels = suite(generator, "held-out-suite", args.seed + 1000, args)
    _, floors = generator.problem.decode(levels.codons, levels.genes)
    hard = levels.difficulty >= np.quantile(levels.difficulty, 0.75)
    outcomes = {
        name: drive(floors, robot=generator.robot, controller=name) for name in ("straight", "purepursuit")
    }
    found = {name: (e.outcome == ARRIVED, e.score()) for name, e in outcomes.items()}
    env = FloorVectorEnv(len(levels), levels=levels, beams=BEAMS, waypoint=WAYPOINT)
    for name, theta in policies.items():
        _, arrived, steps = play(env, np.tile(theta, (len(levels), 1)), levels)
        time = steps * levels.rows.limits[:, 5]
        found[f"ES, {name}"] = (arrived, barn_score(arrived, time, levels.rows.optimal_time))
    rows = []
    for name, (arrived, score) in found.items():
        rows.append({
            "controller": name, "success": float(arrived.mean()), "score": float(score.mean()),
            "hard success": float(arrived[hard].mean()), "floors": len(levels),
            "hard floors": int(hard.sum()),
        })  # fmt: skip
    return rows


def main(argv: list[str] | None = None) -> list[dict]:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--iterations", type=int, default=100)
    parser.add_argument("--candidates", type=int, default=24, help="ES population (even)")
    parser.add_argument("--levels", type=int, default=8, help="levels every candidate plays per iteration")
    parser.add_argument("--sigma", type=float, default=0.1)
    parser.add_argument("--rate", type=float, default=0.05)
    parser.add_argument("--held-out", type=int, default=100, help="floors of the held-out suite")
    parser.add_argument("--training-suites", type=int, default=4, help="suites the training floors come from")
    parser.add_argument("--suite-iterations", type=int, default=100, help="batches each suite breeds")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, default=OUT, help="where the policies and results go")
    args = parser.parse_args(argv)
    started = time.perf_counter()
    base = SpecLevels(TRAINING_SPEC)
    generator = SpecLevels(TRAINING_SPEC, robot=dataclasses.replace(base.robot, beams=BEAMS, timeout=3.0))
    floors = training_floors(generator, args)
    print(f"training on {len(floors.levels)} floors of {args.training_suites} suites")
    policies, histories = {}, {}
    for curriculum in ("uniform", "prioritised"):
        policies[curriculum], histories[curriculum] = train(curriculum, generator, floors, args)
    rows = held_out_table(generator, policies, args)
    floors, hard = rows[0]["floors"], rows[0]["hard floors"]
    print(f"\nheld-out suite: {floors} floors of the training spec ({hard} in the hardest quarter)")
    print("| controller | success | BARN score | success, hardest quarter |\n|---|---|---|---|")
    for row in rows:
        print(
            f"| {row['controller']} | {row['success']:.2f} | {row['score']:.3f} | {row['hard success']:.2f} |"
        )
    print(f"\n{time.perf_counter() - started:.0f} s")
    args.out.mkdir(parents=True, exist_ok=True)
    np.savez(args.out / "policies.npz", **policies)
    (args.out / "results.json").write_text(
        json.dumps({"held_out": rows, "training": histories}, indent=1) + "\n"
    )
    return rows


if __name__ == "__main__":
    main()
