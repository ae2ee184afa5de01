"""Overlap and containment of elements, counted per individual of a population.

Arrays are as in :mod:`mazegen.runtime.geometry._elements`. Elements are first compared by
bounding circles, which need no trigonometry, so elements far from all others are
never transformed; those that may touch are tested part against part with an exact
separating-axis test.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numba import njit

from mazegen.runtime.geometry._elements import ElementTable, population_arrays, world_element
from mazegen.runtime.threads import in_blocks


def overlapping_pairs(
    table: ElementTable, element_ids: np.ndarray, n_elements: np.ndarray, params: np.ndarray
) -> np.ndarray:
    """Count, per individual, the element pairs whose interiors intersect.

    Two elements overlap when any part of one overlaps any part of the other
    (exact separating-axis test); touching boundaries do not count.

    Args:
        table: Parts of the element types.
        element_ids: int32[N, K] type ids, -1 padding.
        n_elements: int32[N] used entries per individual.
        params: float64[N, K, 5] ``(x, y, sx, sy, theta)``.

    Returns:
        int32[N] pair counts.

    Raises:
        ValueError: If the arrays' shapes, counts or ids are inconsistent.
    """
    return _count(_overlap_kernel, table, element_ids, n_elements, params)


def elements_outside(
    table: ElementTable,
    element_ids: np.ndarray,
    n_elements: np.ndarray,
    params: np.ndarray,
    width: float,
    height: float,
) -> np.ndarray:
    """Count, per individual, the elements with a vertex outside ``[0, width] × [0, height]``.

    A vertex on the boundary is inside. Arguments are as for
    :func:`overlapping_pairs`, plus the arena size.

    Returns:
        int32[N] element counts.
    """
    return _count(_outside_kernel, table, element_ids, n_elements, params, float(width), float(height))


def _count(
    kernel: Callable[..., None],
    table: ElementTable,
    element_ids: np.ndarray,
    n_elements: np.ndarray,
    params: np.ndarray,
    *settings: float,
) -> np.ndarray:
    """int32[N]: what ``kernel`` counts per individual, on the checked population arrays."""
    ids, n_el, prm = population_arrays(table, element_ids, n_elements, params)
    out = np.zeros(ids.shape[0], np.int32)
    if ids.shape[0]:
        shapes = table.shapes
        in_blocks(
            kernel,
            ids.shape[0],
            shapes,
            table.unit_radius,
            table.offset_radius,
            ids,
            n_el,
            prm,
            *settings,
            out,
        )
    return out


# Widens bounding circles so that rounding never puts a vertex outside one.
_REACH_MARGIN = 1.0 + 1e-9


@njit(cache=True, inline="always")
def _reach(unit_radius, offset_radius, e, sx, sy):
    """Radius around its position that contains element type ``e`` at scale ``(sx, sy)``."""
    return (unit_radius[e] * max(sx, sy) + offset_radius[e]) * _REACH_MARGIN


@njit(cache=True, inline="always")
def _boxes_meet(box, a, b):
    """True if two boxes' interiors intersect (touching boxes do not meet).

    Non-short-circuit ``&``: random boxes make the branches of ``and``
    unpredictable, which cost more than the comparisons.
    """
    return (
        (box[a, 0] < box[b, 2]) & (box[b, 0] < box[a, 2]) & (box[a, 1] < box[b, 3]) & (box[b, 1] < box[a, 3])
    )


@njit(cache=True, inline="always")
def edge_separates(wv, ka, pa, na, kb, pb, nb):
    """True if some edge line of convex CCW polygon A has all of B on its outer side.

    For convex polygons this one-sided test over the edges of A and of B is the
    full separating-axis test: A's projection on an outward edge normal ends at
    that edge. A vertex exactly on the line counts as outside, so touching
    polygons are separated.
    """
    for i in range(na):
        j = i + 1 if i + 1 < na else 0
        x0 = wv[ka, pa, i, 0]
        y0 = wv[ka, pa, i, 1]
        nx = wv[ka, pa, j, 1] - y0  # outward normal of a CCW edge: (ey, -ex)
        ny = x0 - wv[ka, pa, j, 0]
        # A full min (no break) keeps the inner loop free of unpredictable branches.
        lowest = np.inf
        for v in range(nb):
            lowest = min(lowest, (wv[kb, pb, v, 0] - x0) * nx + (wv[kb, pb, v, 1] - y0) * ny)
        if lowest >= 0.0:
            return True
    return False


@njit(cache=True, inline="always")
def _elements_overlap(n_parts, n_vertices, ea, a, eb, b, wv, pbox, ebox):
    """True if some part of element ``a`` (type ``ea``) overlaps some part of ``b`` (type ``eb``)."""
    for pa in range(n_parts[ea]):
        # A part clear of b's whole box meets none of b's parts (bars of figures often are).
        if not (
            (pbox[a, pa, 0] < ebox[b, 2])
            & (ebox[b, 0] < pbox[a, pa, 2])
            & (pbox[a, pa, 1] < ebox[b, 3])
            & (ebox[b, 1] < pbox[a, pa, 3])
        ):
            continue
        for pb in range(n_parts[eb]):
            if not (
                (pbox[a, pa, 0] < pbox[b, pb, 2])
                & (pbox[b, pb, 0] < pbox[a, pa, 2])
                & (pbox[a, pa, 1] < pbox[b, pb, 3])
                & (pbox[b, pb, 1] < pbox[a, pa, 3])
            ):
                continue
            na = n_vertices[ea, pa]
            nb = n_vertices[eb, pb]
            if not (edge_separates(wv, a, pa, na, b, pb, nb) or edge_separates(wv, b, pb, nb, a, pa, na)):
                return True
    return False


@njit(cache=True, nogil=True)
def _overlap_kernel(first, last, shapes, unit_radius, offset_radius, ids, n_el, params, out):
    n_parts, n_vertices, unit = shapes[0], shapes[1], shapes[2]
    k_max = ids.shape[1]
    wv = np.empty((k_max, unit.shape[1], unit.shape[2], 2))
    pbox = np.empty((k_max, unit.shape[1], 4))
    ebox = np.empty((k_max, 4))
    radius = np.empty(k_max)
    placed = np.empty(k_max, np.bool_)
    pairs = np.empty((k_max * (k_max - 1) // 2, 2), np.int64)
    for i in range(first, last):
        m = n_el[i]
        for k in range(m):
            radius[k] = _reach(unit_radius, offset_radius, ids[i, k], params[i, k, 2], params[i, k, 3])
            placed[k] = False
        # Bounding circles need no trigonometry, so elements far from all
        # others are never transformed. Candidates are collected without a
        # branch: few circles meet, at random.
        n_pairs = 0
        for a in range(m):
            for b in range(a + 1, m):
                dx = params[i, a, 0] - params[i, b, 0]
                dy = params[i, a, 1] - params[i, b, 1]
                reach = radius[a] + radius[b]
                pairs[n_pairs, 0] = a
                pairs[n_pairs, 1] = b
                n_pairs += dx * dx + dy * dy < reach * reach
        count = 0
        for q in range(n_pairs):
            for side in range(2):
                k = pairs[q, side]
                if not placed[k]:
                    world_element(shapes, ids[i, k], params[i, k], wv, pbox, ebox, k)
                    placed[k] = True
            a = pairs[q, 0]
            b = pairs[q, 1]
            if _boxes_meet(ebox, a, b):
                ea, eb = ids[i, a], ids[i, b]
                count += _elements_overlap(n_parts, n_vertices, ea, a, eb, b, wv, pbox, ebox)
        out[i] = count


@njit(cache=True, nogil=True)
def _outside_kernel(first, last, shapes, unit_radius, offset_radius, ids, n_el, params, width, height, out):
    unit = shapes[2]
    wv = np.empty((1, unit.shape[1], unit.shape[2], 2))
    pbox = np.empty((1, unit.shape[1], 4))
    ebox = np.empty((1, 4))
    for i in range(first, last):
        count = 0
        for k in range(n_el[i]):
            x = params[i, k, 0]
            y = params[i, k, 1]
            r = _reach(unit_radius, offset_radius, ids[i, k], params[i, k, 2], params[i, k, 3])
            if x - r >= 0.0 and y - r >= 0.0 and x + r <= width and y + r <= height:
                continue  # the bounding circle is inside: no need to transform
            world_element(shapes, ids[i, k], params[i, k], wv, pbox, ebox, 0)
            count += (ebox[0, 0] < 0.0) | (ebox[0, 1] < 0.0) | (ebox[0, 2] > width) | (ebox[0, 3] > height)
        out[i] = count
