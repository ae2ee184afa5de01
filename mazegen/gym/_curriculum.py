"""The curriculum's interface: a mutator of levels, a comparator, a prioritised level sampler and the
scores that feed it.

The generator is :class:`~mazegen.gym._sources.SpecLevels` (``sample(rng, n)``: fresh floors of a
spec). :class:`LevelMutator` edits levels as ACCEL does, through their genomes: an int-flip mutation
of the structure codons and placement genes, mapped through the spec's grammar again, so that a
child is still a valid floor of the spec. :class:`LevelSampler` keeps a buffer of levels with scores
and draws replay levels as jaxued's ``LevelSampler`` does (PLR: rank or top-k prioritisation mixed
with staleness); it is also a level source, so an environment's automatic resets draw from it.
"""

from __future__ import annotations

import numpy as np

from mazegen.errors import MazeError
from mazegen.gym._levels import Levels
from mazegen.gym._sources import LevelSource, SpecLevels
from mazegen.runtime.engine import mutate, mutation_draws
from mazegen.runtime.simulation import ARRIVED, REWARD_TERMS, Slots, beam_angles


class LevelMutator:
    """Children of levels by GE mutation of their genomes (``rate`` per codon and placement gene,
    default the spec's mutation rate); a child that maps to no valid floor with a path is mutated
    again from its parent, up to ``tries`` times, and is its parent unchanged after that. A child
    plays its parent's task."""

    def __init__(self, generator: SpecLevels, *, rate: float | None = None, tries: int = 32) -> None:
        self.generator = generator
        self.rate = generator.spec.evolution.mutation if rate is None else rate
        if not 0 < self.rate <= 1:
            raise MazeError(f"the mutation rate must be within (0, 1], got {self.rate}")
        self.tries = tries

    def mutate(self, rng: np.random.Generator, levels: Levels, n: int) -> Levels:
        """``n`` children of parents drawn uniformly from ``levels``."""
        spec = self.generator.spec
        if not levels.has_genomes or levels.spec != spec.scenario.name:
            raise MazeError(f"only levels with genomes of spec {spec.scenario.name} mutate through it")
        assert levels.codons is not None and levels.genes is not None
        parents = rng.integers(0, len(levels), size=n)
        tasks = _task_indices(levels.task[parents], [task.name for task in spec.arena.tasks])
        children: list[Levels | None] = [None] * n
        todo = np.arange(n)
        for _ in range(self.tries):
            codons = levels.codons[parents[todo]].copy()
            genes = levels.genes[parents[todo]].copy()
            draws = mutation_draws(
                rng, todo.size, codons.shape[1], genes.shape[1], self.rate, spec.evolution.codon_max
            )
            mutate(draws, codons, genes)
            kept, found = self.generator.decoded(codons, genes, tasks[todo])
            for row, child in zip(kept.tolist(), range(len(found))):
                children[todo[row]] = found.take([child])
            todo = todo[np.setdiff1d(np.arange(todo.size), kept)]
            if not todo.size:
                break
        for k in todo.tolist():
            children[k] = levels.take([parents[k]])
        return Levels.joined([child for child in children if child is not None])


def _task_indices(names: np.ndarray, tasks: list[str]) -> np.ndarray:
    return np.array([tasks.index(name) if tasks else 0 for name in names.tolist()], np.int64)


def duplicates(levels: Levels, against: Levels | None = None) -> np.ndarray:
    """``bool[n]``: whether each level is the same level (same hash: the same parts, arena, start, goal
    and robot) as one before it in ``levels`` or one of ``against``."""
    seen = set() if against is None else set(against.hashes.tolist())
    found = np.zeros(len(levels), np.bool_)
    for k, digest in enumerate(levels.hashes.tolist()):
        found[k] = digest in seen
        seen.add(digest)
    return found


class LevelSampler:
    """A buffer of at most ``capacity`` levels with scores, drawn for replay with jaxued's
    ``LevelSampler`` semantics (Prioritized Level Replay, Jiang et al. 2021).

    A level's replay probability is ``(1 - staleness_coef) · P_score + staleness_coef · P_staleness``:
    ``P_score`` is ``rank(score)^(-1/temperature)`` normalised (``prioritization="rank"``), or uniform
    over the ``topk_k`` best (``"topk"``); ``P_staleness`` is proportional to the episodes since the
    level was last drawn or scored. A level inserted into a full buffer replaces the one of the lowest
    score when its own is higher; with ``duplicate_check`` a level already held only has its score
    updated.

    As a level source (``sample``): each level is a replay level with probability ``replay_prob`` once
    the buffer is ``minimum_fill_ratio`` full, else a new level from ``generator`` (inserted with score
    ``new_score``: the first score comes with :meth:`update`).
    """

    def __init__(
        self,
        *,
        capacity: int = 4000,
        replay_prob: float = 0.5,
        staleness_coef: float = 0.3,
        minimum_fill_ratio: float = 1.0,
        prioritization: str = "rank",
        temperature: float = 0.3,
        topk_k: int = 4,
        duplicate_check: bool = True,
        generator: LevelSource | None = None,
        new_score: float = 0.0,
    ) -> None:
        if prioritization not in ("rank", "topk"):
            raise MazeError(f"prioritization must be rank or topk, got {prioritization!r}")
        if capacity < 1 or not 0 <= replay_prob <= 1 or not 0 <= staleness_coef <= 1 or temperature <= 0:
            raise MazeError("capacity >= 1, replay_prob and staleness_coef within [0, 1], temperature > 0")
        self.capacity, self.replay_prob, self.staleness_coef = capacity, replay_prob, staleness_coef
        self.minimum_fill_ratio, self.prioritization = minimum_fill_ratio, prioritization
        self.temperature, self.topk_k, self.duplicate_check = temperature, topk_k, duplicate_check
        self.generator, self.new_score = generator, new_score
        self.levels: Levels | None = None
        self._digests: list[str] = []  # each buffer index's level's hash
        self._positions: dict[str, int] = {}  # a held level's buffer index, by its hash
        self.scores = np.zeros(0)
        self.last_seen = np.zeros(0, np.int64)
        self.episodes = 0

    @property
    def size(self) -> int:
        """Levels held."""
        return len(self.scores)

    def insert(self, levels: Levels, scores: np.ndarray | float) -> np.ndarray:
        """Offer ``levels`` with ``scores``; returns each one's index in the buffer, -1 where it was not
        kept (a full buffer whose lowest score is not below it)."""
        scores = np.broadcast_to(np.asarray(scores, np.float64), (len(levels),))
        where = np.full(len(levels), -1, np.int64)
        held = self.size
        rows = list(range(held))  # the row of [held levels, levels] each buffer index holds
        for k, digest in enumerate(levels.hashes.tolist()):
            self.episodes += 1
            known = self._positions.get(digest, -1) if self.duplicate_check else -1
            if known >= 0:
                self._score(known, scores[k])
                where[k] = known
                continue
            if len(rows) < self.capacity:
                position = len(rows)
                rows.append(held + k)
                self._digests.append(digest)
                self.scores = np.append(self.scores, scores[k])
                self.last_seen = np.append(self.last_seen, self.episodes)
            elif scores[k] > self.scores.min():
                position = int(np.argmin(self.scores))
                self._positions.pop(self._digests[position], None)
                self._digests[position] = digest
                rows[position] = held + k
                self._score(position, scores[k])
            else:
                continue
            self._positions[digest] = position
            where[k] = position
        if (where >= 0).any():
            offered = levels if self.levels is None else Levels.joined([self.levels, levels])
            self.levels = offered.take(np.array(rows, np.int64))
        return where

    def update(self, index: np.ndarray, scores: np.ndarray) -> None:
        """New scores for buffer levels ``index`` (after they were played).

        Raises:
            MazeError: for an index the buffer does not hold, or scores that do not match the indices.
        """
        at = np.asarray(index, np.int64).reshape(-1)
        given = np.asarray(scores, np.float64).reshape(-1)
        if given.size == 1:
            given = np.full(at.size, given[0])
        if given.size != at.size or (at.size and not 0 <= at.min() <= at.max() < self.size):
            raise MazeError(f"update takes buffer indices within [0, {self.size}) and one score each")
        for k, score in zip(at.tolist(), given.tolist()):
            self.episodes += 1
            self._score(k, score)

    def weights(self) -> np.ndarray:
        """``float64[size]``: each level's replay probability."""
        if not self.size:
            return np.zeros(0)
        if self.prioritization == "rank":
            ranks = np.empty(self.size)
            ranks[np.argsort(-self.scores, kind="stable")] = np.arange(1, self.size + 1)
            score = ranks ** (-1.0 / self.temperature)
        else:
            score = np.zeros(self.size)
            score[np.argsort(-self.scores, kind="stable")[: self.topk_k]] = 1.0
        score /= score.sum()
        stale = (self.episodes - self.last_seen).astype(np.float64)
        stale = stale / stale.sum() if stale.sum() > 0 else np.full(self.size, 1.0 / self.size)
        return (1 - self.staleness_coef) * score + self.staleness_coef * stale

    def sample_replay_levels(self, rng: np.random.Generator, n: int) -> tuple[np.ndarray, Levels]:
        """``n`` buffer levels drawn by :meth:`weights` (with replacement), and their indices."""
        if self.levels is None:
            raise MazeError("the level sampler holds no level to replay yet")
        index = rng.choice(self.size, size=n, p=self.weights())
        self.last_seen[index] = self.episodes
        return index, self.levels.take(index)

    def replay_ready(self) -> bool:
        """Whether the buffer is full enough to replay from."""
        return self.size >= self.minimum_fill_ratio * self.capacity

    def sample(self, rng: np.random.Generator, n: int) -> Levels:
        """``n`` levels to play: replay levels and new ones (see the class)."""
        replay = rng.random(n) < self.replay_prob if self.replay_ready() else np.zeros(n, np.bool_)
        if not replay.all() and self.generator is None:
            raise MazeError("a level sampler without a generator only replays: fill it first")
        parts, order = [], []
        if replay.any():
            parts.append(self.sample_replay_levels(rng, int(replay.sum()))[1])
            order.append(np.flatnonzero(replay))
        if not replay.all():
            assert self.generator is not None
            fresh = self.generator.sample(rng, int((~replay).sum()))
            self.insert(fresh, self.new_score)
            parts.append(fresh)
            order.append(np.flatnonzero(~replay))
        return Levels.joined(parts).take(np.argsort(np.concatenate(order), kind="stable"))

    def index_of(self, hashes: np.ndarray) -> np.ndarray:
        """Buffer indices of the levels of ``hashes`` (as in ``info["hash"]``), -1 where not held."""
        return np.array([self._positions.get(digest, -1) for digest in np.asarray(hashes).tolist()], np.int64)

    def _score(self, index: int, score: float) -> None:
        self.scores[index] = score
        self.last_seen[index] = self.episodes


def positive_value_loss(
    rewards: np.ndarray,
    values: np.ndarray,
    dones: np.ndarray,
    last_values: np.ndarray,
    *,
    gamma: float = 0.99,
    lam: float = 0.95,
) -> np.ndarray:
    """PLR's regret estimate per sub-environment: the mean over a rollout's steps of the positive part of
    the GAE advantage. ``rewards``, ``values``, ``dones``: ``[T, n]`` (``dones[t]`` the step ended an
    episode); ``last_values``: ``[n]``, the value after the last step."""
    advantage = _gae(rewards, values, dones, last_values, gamma, lam)
    return np.maximum(advantage, 0.0).mean(axis=0)


def max_monte_carlo(returns: np.ndarray, values: np.ndarray, best: np.ndarray) -> np.ndarray:
    """The MaxMC regret estimate per sub-environment: the mean over steps of the level's best return seen
    so far (``best``, ``[n]``) less the value predicted (``values``, ``[T, n]``); ``returns`` (``[T, n]``,
    discounted returns of the rollout) raise ``best`` first."""
    top = np.maximum(best, np.max(returns, axis=0))
    return (top[None, :] - values).mean(axis=0)


def _gae(
    rewards: np.ndarray,
    values: np.ndarray,
    dones: np.ndarray,
    last_values: np.ndarray,
    gamma: float,
    lam: float,
) -> np.ndarray:
    advantage = np.zeros_like(np.asarray(rewards, np.float64))
    running = np.zeros(advantage.shape[1])
    following = np.asarray(last_values, np.float64)
    for t in range(advantage.shape[0] - 1, -1, -1):
        going = 1.0 - np.asarray(dones[t], np.float64)
        delta = rewards[t] + gamma * following * going - values[t]
        running = delta + gamma * lam * going * running
        advantage[t] = running
        following = values[t]
    return advantage


def controller_failure(levels: Levels, controller: str = "straight", *, beams: int = 360) -> np.ndarray:
    """``float64[n]``: 1 where bundled ``controller`` (one that reads neither path nor fields: ``straight``,
    ``vfh``) fails to arrive on the level, else 0: a score of how hard the level is for a fixed robot."""
    n = len(levels)
    slots = Slots(n, beam_angles(beams, 2 * np.pi))
    slots.load(np.arange(n), levels.rows)
    weights = np.zeros(len(REWARD_TERMS))
    while slots.playing():
        slots.step(slots.commands(controller), weights)
    return (slots.robots.outcome != ARRIVED).astype(np.float64)
