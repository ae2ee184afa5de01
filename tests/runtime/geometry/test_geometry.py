"""Tests of the element table, world transforms and bounds."""

from __future__ import annotations

import math

import numpy as np
import pytest
from shapely.geometry import Polygon

from mazegen.runtime.geometry._elements import element_bounds, world_parts
from mazegen.runtime.geometry._overlap import elements_outside, overlapping_pairs
from tests.runtime.elements import TABLE, TYPES, random_population


def test_table_is_padded_to_the_largest_type() -> None:
    assert TABLE.n_parts[[0, 1, 2, 4, 5]].tolist() == [1, 1, 1, 2, 4]
    assert TABLE.n_parts[3] >= 2
    assert TABLE.unit.shape == TABLE.offset.shape == (6, 4, 6, 2)
    assert TABLE.n_vertices[2].tolist() == [6, 0, 0, 0]
    assert TABLE.n_vertices.dtype == TABLE.n_parts.dtype == np.int32
    assert np.all(TABLE.unit[0, 1:] == 0)
    assert TABLE.offset_radius[4] == pytest.approx(3 * math.sqrt(2))


def test_world_parts_rotate_scale_and_translate() -> None:
    rng = np.random.default_rng(1)
    for _ in range(200):
        e = int(rng.integers(0, len(TYPES)))
        x, y, sx, sy, theta = rng.uniform(-500, 500), rng.uniform(-500, 500), 50.0, 30.0, rng.uniform(-9, 9)
        rot = np.array([[math.cos(theta), -math.sin(theta)], [math.sin(theta), math.cos(theta)]])
        got = world_parts(TABLE, e, (x, y, sx, sy, theta))
        assert len(got) == len(TYPES[e].parts)
        for part, vertices in zip(TYPES[e].parts, got, strict=True):
            local = np.asarray(part.unit) * (sx, sy) + np.asarray(part.offset)
            assert np.allclose(vertices, local @ rot.T + (x, y), rtol=0, atol=1e-9)
            assert Polygon(vertices).exterior.is_ccw


def test_element_bounds_match_world_parts() -> None:
    rng = np.random.default_rng(4)
    ids, n_elements, params = random_population(rng, 200, 5, 500.0, 500.0)
    bounds = element_bounds(TABLE, ids, n_elements, params)
    assert bounds.shape == (200, 5, 4)
    for i in range(len(ids)):
        for k in range(5):
            if k < n_elements[i]:
                vertices = np.concatenate(world_parts(TABLE, ids[i, k], params[i, k]))
                np.testing.assert_array_equal(bounds[i, k], [*vertices.min(axis=0), *vertices.max(axis=0)])
            else:
                assert np.isnan(bounds[i, k]).all()


@pytest.mark.parametrize(
    ("ids", "n_elements", "params", "message"),
    [
        (np.zeros((2, 3)), np.zeros(3), np.zeros((2, 3, 5)), "disagree"),
        (np.zeros((2, 3)), np.zeros(2), np.zeros((2, 3, 4)), "disagree"),
        (np.zeros((2, 3)), np.array([1, 4]), np.zeros((2, 3, 5)), "n_elements"),
        (np.full((2, 3), 6), np.array([1, 3]), np.zeros((2, 3, 5)), "element ids"),
    ],
)
def test_inconsistent_population_is_rejected(ids, n_elements, params, message: str) -> None:
    # Every entry point checks the arrays before its kernel indexes them without bounds checks.
    for count in (element_bounds, overlapping_pairs, lambda *arrays: elements_outside(*arrays, 10, 10)):
        with pytest.raises(ValueError, match=message):
            count(TABLE, ids, n_elements, params)
