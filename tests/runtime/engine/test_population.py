"""Decoding genomes into element parameters, and the metrics fitness terms read."""

from __future__ import annotations

import numpy as np
import pytest

import mazegen
from mazegen.generator.build import build
from mazegen.runtime import metrics
from mazegen.runtime.engine._placement import GENE_MAX, SX, SY, THETA, X, Y
from mazegen.runtime.engine._problem import Problem
from tests.conftest import EXAMPLES


def problem_of(path, tmp_path) -> Problem:
    build(mazegen.load(path), tmp_path)
    return Problem.from_build_dir(tmp_path)


def test_grammar_placement_reads_size_and_position_from_the_phenotype(tmp_path):
    problem = problem_of(EXAMPLES / "table1" / "exp1.maze", tmp_path)
    # <scenario>: 1 -> square(<size>,<number>,<number>); size 3 -> "4"; x 6 -> 700; y 7 -> 800.
    codons = np.array([[1, 3, 6, 7]], dtype=np.int32)
    genes = np.zeros((1, problem.slots, 5), dtype=np.uint16)
    mapped, population = problem.decode(codons, genes)
    assert mapped.valid[0] and population.n_elements[0] == 1
    assert population.params[0, 0, [X, Y, SX, SY]].tolist() == [700.0, 800.0, 200.0, 200.0]


def test_placement_genes_span_the_ranges(tmp_path):
    problem = problem_of(EXAMPLES / "factory.maze", tmp_path)
    names = problem.spec.scenario.elements
    codons = np.array([[names.index("vwall"), 0], [names.index("cobot"), 0]], dtype=np.int32)
    genes = np.zeros((2, problem.slots, 5), dtype=np.uint16)
    genes[:, 0] = [GENE_MAX, 0, GENE_MAX, 0, GENE_MAX]
    _, population = problem.decode(codons, genes)
    wall, cobot = population.params[0, 0], population.params[1, 0]
    assert wall[[X, Y, SX, SY, THETA]].tolist() == [1400.0, 0.0, 20.0, 150.0, 0.0]  # rect: width x depth
    assert cobot[SX] == cobot[SY] == 120.0
    assert cobot[THETA] == pytest.approx(np.radians(360.0))  # rotation any: 0..360


def test_size_limit_and_outside_metrics(tmp_path):
    problem = problem_of(EXAMPLES / "mazegen15.maze", tmp_path)
    # flat: square() twice -> two elements.
    codons = np.array([[5, 1]], dtype=np.int32)
    genes = np.zeros((1, problem.slots, 5), dtype=np.uint16)
    genes[0, 0] = [GENE_MAX // 2, GENE_MAX // 2, GENE_MAX, 0, 0]  # centred, size 800 > 500
    genes[0, 1] = [0, GENE_MAX // 2, 0, 0, 0]  # on the left wall, size 40
    _, population = problem.decode(codons, genes)
    assert population.n_elements[0] == 2
    assert metrics.elements_over_size(population, 500.0).tolist() == [1.0]
    assert metrics.elements_outside(population).tolist() == [1.0]
    fitness, terms = problem.score(population)
    assert fitness[0] == -np.inf  # mazegen15 rejects any element over 500
    assert terms["count"].tolist() == [2.0]


def reference_params(mapped, genes, ranges, grammar_scale):
    """Plain NumPy placement decoding, the reference the numba kernel must equal."""
    ids = np.maximum(mapped.element_ids, 0)
    unit = genes.astype(np.float64) / GENE_MAX
    size, depth, uniform = ranges.size[ids], ranges.depth[ids], ranges.uniform[ids]
    area = ranges.area[ids]
    x = area[..., 0] + (area[..., 2] - area[..., 0]) * unit[..., 0]
    y = area[..., 1] + (area[..., 3] - area[..., 1]) * unit[..., 1]
    sx = size[..., 0] + (size[..., 1] - size[..., 0]) * unit[..., 2]
    sy = np.where(uniform, sx, depth[..., 0] + (depth[..., 1] - depth[..., 0]) * unit[..., 3])
    free = ranges.rot_lo[ids] + (ranges.rot_hi[ids] - ranges.rot_lo[ids]) * unit[..., 4]
    pick = genes[..., 4].astype(np.int64) % ranges.n_rotations[ids]
    discrete = np.take_along_axis(ranges.rotations[ids], pick[..., None], axis=-1)[..., 0]
    angle = np.where(ranges.rot_free[ids], free, discrete)
    if grammar_scale is not None:
        n = mapped.numbers
        has = ~np.isnan(n)
        sx = np.where(has[..., 0], n[..., 0] * grammar_scale, sx)
        sy = np.where(has[..., 0], np.where(uniform, sx, sx * ranges.aspect[ids]), sy)
        x, y = np.where(has[..., 1], n[..., 1], x), np.where(has[..., 2], n[..., 2], y)
        angle = np.where(has[..., 3], n[..., 3], angle)
    params = np.stack([x, y, sx, sy, np.radians(angle)], axis=-1)
    present = np.arange(ids.shape[1])[None, :] < mapped.n_elements[:, None]
    return np.where(present[..., None], params, 0.0)


# Steps, walls and rows (the warehouse's runs of racks) have their own reference in test_placement.py.
@pytest.mark.parametrize("example", ["factory.maze", "mazegen1.maze", "table1/exp1.maze", "layout.maze"])
def test_placement_kernel_equals_numpy_reference(example, tmp_path):
    from mazegen.runtime.engine._placement import placement_params

    problem = problem_of(EXAMPLES / example, tmp_path)
    rng = np.random.default_rng(11)
    codons = rng.integers(0, 256, size=(3000, problem.spec.evolution.genome), dtype=np.int32)
    genes = rng.integers(0, GENE_MAX + 1, size=(3000, problem.slots, 5), dtype=np.uint16)
    mapped, _ = problem.decode(codons, genes)
    assert mapped.n_elements.max() >= 3
    placement = problem.spec.scenario.placement
    scale = None if placement is None else placement.scale
    expected = reference_params(mapped, genes, problem.ranges, scale)
    assert np.array_equal(placement_params(mapped, genes, problem.ranges, problem.table, scale), expected)
    stale = np.full_like(expected, 7.0)  # a reused array: every slot is overwritten, padding zeroed
    placement_params(mapped, genes, problem.ranges, problem.table, scale, stale)
    assert np.array_equal(stale, expected)


@pytest.mark.parametrize("limit", [0.0, 100.0, 500.0, 1e9])
def test_size_limit_kernel_equals_numpy_reference(limit, tmp_path):
    problem = problem_of(EXAMPLES / "table1" / "exp8.maze", tmp_path)
    rng = np.random.default_rng(4)
    codons = rng.integers(0, 256, size=(2000, problem.spec.evolution.genome), dtype=np.int32)
    genes = rng.integers(0, GENE_MAX + 1, size=(2000, problem.slots, 5), dtype=np.uint16)
    _, population = problem.decode(codons, genes)
    params = population.params
    present = np.arange(params.shape[1])[None, :] < population.n_elements[:, None]
    expected = (present & (np.maximum(params[..., 2], params[..., 3]) > limit)).sum(axis=1)
    assert metrics.elements_over_size(population, limit).tolist() == expected.astype(float).tolist()
    assert 0 < expected.sum() < present.sum() or limit in (0.0, 1e9)
