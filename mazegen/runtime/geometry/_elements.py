"""Where elements are: the element table and world transforms of whole populations.

A population of ``N`` individuals with at most ``K`` elements each is stored as

* ``element_ids`` int32[N, K]: element type ids (rows of an :class:`ElementTable`),
  ``-1`` padding after the used entries (which must hold valid ids);
* ``n_elements`` int32[N]: how many leading entries of each row are used;
* ``params`` float64[N, K, 5]: ``(x, y, sx, sy, theta)``, theta in radians,
  counter-clockwise; ``sx`` and ``sy`` are positive.

A part vertex in the world is ``R(theta) · (u · (sx, sy) + o) + (x, y)`` (see
:mod:`mazegen.spec`). The kernels run in parallel over blocks of individuals;
each block owns a scratch buffer for the world vertices of one individual, so
nothing of size N×K×P×V is ever built. :mod:`mazegen.runtime.geometry._overlap` counts
overlaps and elements outside the arena with these transforms.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numba import njit

from mazegen.runtime.threads import in_blocks
from mazegen.spec import ElementType


@dataclass(frozen=True, eq=False)
class ElementTable:
    """The parts of every element type as padded arrays (E types, P parts, V vertices).

    Attributes:
        n_parts: int32[E], number of parts of each type.
        n_vertices: int32[E, P], number of vertices of each part (0 for padding).
        unit: float64[E, P, V, 2], unit coordinates, zero padded.
        offset: float64[E, P, V, 2], absolute offsets, zero padded.
        unit_radius: float64[E], largest ``|u|`` of a type's vertices.
        offset_radius: float64[E], largest ``|o|``; an element lies within
            ``unit_radius · max(sx, sy) + offset_radius`` of its position.
        names: The types' names (what an arena's zones name them by).
    """

    n_parts: np.ndarray
    n_vertices: np.ndarray
    unit: np.ndarray
    offset: np.ndarray
    unit_radius: np.ndarray
    offset_radius: np.ndarray
    names: tuple[str, ...] = ()

    @classmethod
    def from_types(cls, types: Sequence[ElementType]) -> ElementTable:
        """Build the table; the id of a type is its index in ``types``."""
        n_p = max((len(t.parts) for t in types), default=1)
        n_v = max((len(p.unit) for t in types for p in t.parts), default=3)
        n_parts = np.zeros(len(types), np.int32)
        n_vertices = np.zeros((len(types), n_p), np.int32)
        unit = np.zeros((len(types), n_p, n_v, 2))
        offset = np.zeros((len(types), n_p, n_v, 2))
        for e, element_type in enumerate(types):
            n_parts[e] = len(element_type.parts)
            for p, part in enumerate(element_type.parts):
                n_vertices[e, p] = len(part.unit)
                unit[e, p, : len(part.unit)] = part.unit
                offset[e, p, : len(part.offset)] = part.offset
        unit_radius = np.linalg.norm(unit, axis=-1).reshape(len(types), -1).max(axis=1, initial=0.0)
        offset_radius = np.linalg.norm(offset, axis=-1).reshape(len(types), -1).max(axis=1, initial=0.0)
        names = tuple(t.name for t in types)
        return cls(n_parts, n_vertices, unit, offset, unit_radius, offset_radius, names)

    @property
    def shapes(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(n_parts, n_vertices, unit, offset)``: what the compiled kernels place elements with."""
        return self.n_parts, self.n_vertices, self.unit, self.offset


def element_bounds(
    table: ElementTable, element_ids: np.ndarray, n_elements: np.ndarray, params: np.ndarray
) -> np.ndarray:
    """World bounding boxes of every element (arrays as in this module's doc).

    Returns:
        float64[N, K, 4] as ``(xmin, ymin, xmax, ymax)``, NaN for padding.
    """
    ids, n_el, prm = population_arrays(table, element_ids, n_elements, params)
    out = np.full((*ids.shape, 4), np.nan)
    if ids.shape[0]:
        in_blocks(_bounds_kernel, ids.shape[0], table.shapes, ids, n_el, prm, out)
    return out


def world_parts(table: ElementTable, element_id: int, param_row: Sequence[float]) -> list[np.ndarray]:
    """World vertices of one element, one float64 (n, 2) array per part (see :func:`world_vertices`)."""
    wv = world_vertices(table, np.array([element_id]), np.asarray([param_row], np.float64))[0]
    return [wv[p, : table.n_vertices[element_id, p]].copy() for p in range(table.n_parts[element_id])]


def world_vertices(table: ElementTable, element_ids: np.ndarray, params: np.ndarray) -> np.ndarray:
    """World vertices of several elements, computed exactly as the kernels do, in one call.

    Args:
        table: Parts of the element types.
        element_ids: ``int[M]`` rows of ``table``.
        params: ``float64[M, 5]``: x, y, sx, sy and theta of each element.

    Returns:
        ``float64[M, P, V, 2]``: element ``k``'s part ``p`` is counter-clockwise in
        ``[k, p, :table.n_vertices[e, p]]`` for ``p < table.n_parts[e]``; the rest is padding.
    """
    ids = np.ascontiguousarray(element_ids, np.int32)
    rows = np.ascontiguousarray(params, np.float64).reshape(ids.shape[0], 5)
    if ids.size and (ids.min() < 0 or ids.max() >= len(table.n_parts)):
        raise ValueError(f"element ids must lie in [0, {len(table.n_parts)})")
    wv = np.zeros((ids.shape[0], *table.unit.shape[1:]))
    _world_elements(table.shapes, ids, rows, wv)
    return wv


@njit(cache=True)
def _world_elements(shapes, ids, params, wv):  # pragma: no cover - compiled
    pbox = np.empty((ids.shape[0], wv.shape[1], 4))
    ebox = np.empty((ids.shape[0], 4))
    for k in range(ids.shape[0]):
        world_element(shapes, ids[k], params[k], wv, pbox, ebox, k)


def population_arrays(
    table: ElementTable, element_ids: np.ndarray, n_elements: np.ndarray, params: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Check the population arrays and return them contiguous with the kernels' dtypes."""
    ids = np.ascontiguousarray(element_ids, np.int32)
    n_el = np.ascontiguousarray(n_elements, np.int32)
    prm = np.ascontiguousarray(params, np.float64)
    if ids.ndim != 2 or n_el.shape != ids.shape[:1] or prm.shape != (*ids.shape, 5):
        raise ValueError(
            f"population arrays disagree: element_ids {ids.shape}, "
            f"n_elements {n_el.shape}, params {prm.shape}"
        )
    # The kernels index without bounds checks: a bad count or id would write out of bounds.
    if n_el.size and (n_el.min() < 0 or n_el.max() > ids.shape[1]):
        raise ValueError(f"n_elements must lie in [0, {ids.shape[1]}]")
    if ids.size and (ids.min() < -1 or ids.max() >= len(table.n_parts)):
        raise ValueError(f"element ids must lie in [0, {len(table.n_parts)}) or be -1")
    return ids, n_el, prm


# Cephes sin/cos: polynomials on a quarter octant after an extended-precision
# reduction; libm's sin and cos cost as much as all the rest of a transform.
_FOUR_OVER_PI = 1.2732395447351628
_DP1 = 7.85398125648498535156e-1
_DP2 = 3.77489470793079817668e-8
_DP3 = 2.69515142907905952645e-15


@njit(cache=True, inline="always")
def _sincos(x):
    """Return ``(sin x, cos x)`` to about one ulp for ``|x| < 1e8``."""
    sign = math.copysign(1.0, x)
    x = abs(x)
    j = int(x * _FOUR_OVER_PI)
    j += j & 1
    y = float(j)
    z = ((x - y * _DP1) - y * _DP2) - y * _DP3
    zz = z * z
    ps = z + z * zz * (
        (
            (
                (
                    (1.58962301576546568060e-10 * zz - 2.50507477628578072866e-8) * zz
                    + 2.75573136213857245213e-6
                )
                * zz
                - 1.98412698295895385996e-4
            )
            * zz
            + 8.33333333332211858878e-3
        )
        * zz
        - 1.66666666666666307295e-1
    )
    pc = (
        1.0
        - 0.5 * zz
        + zz
        * zz
        * (
            (
                (
                    (
                        (-1.13585365213876817300e-11 * zz + 2.08757008419747316778e-9) * zz
                        - 2.75573141792967388112e-7
                    )
                    * zz
                    + 2.48015872888517045348e-5
                )
                * zz
                - 1.38888888888730564116e-3
            )
            * zz
            + 4.16666666666665929218e-2
        )
    )
    # Octants 0, 2, 4, 6 by arithmetic rather than branches (theta is random).
    swap = (j >> 1) & 1
    s = (pc if swap else ps) * sign * (1 - 2 * ((j >> 2) & 1))
    c = (ps if swap else pc) * (1 - 2 * (((j >> 1) ^ (j >> 2)) & 1))
    return s, c


@njit(cache=True, inline="always")
def world_element(shapes, e, row, wv, pbox, ebox, k):
    """Write element ``e``'s world vertices, part boxes and box to ``wv[k]``, ``pbox[k]``, ``ebox[k]``.

    ``shapes`` is :attr:`ElementTable.shapes`; ``row`` holds the element's x, y, sx, sy
    and rotation (radians).
    """
    n_parts, n_vertices, unit, offset = shapes
    x, y, sx, sy = row[0], row[1], row[2], row[3]
    s, c = _sincos(row[4])
    exmin = np.inf
    eymin = np.inf
    exmax = -np.inf
    eymax = -np.inf
    for p in range(n_parts[e]):
        xmin = np.inf
        ymin = np.inf
        xmax = -np.inf
        ymax = -np.inf
        for v in range(n_vertices[e, p]):
            lx = unit[e, p, v, 0] * sx + offset[e, p, v, 0]
            ly = unit[e, p, v, 1] * sy + offset[e, p, v, 1]
            wx = x + c * lx - s * ly
            wy = y + s * lx + c * ly
            wv[k, p, v, 0] = wx
            wv[k, p, v, 1] = wy
            xmin = min(xmin, wx)
            ymin = min(ymin, wy)
            xmax = max(xmax, wx)
            ymax = max(ymax, wy)
        pbox[k, p, 0] = xmin
        pbox[k, p, 1] = ymin
        pbox[k, p, 2] = xmax
        pbox[k, p, 3] = ymax
        exmin = min(exmin, xmin)
        eymin = min(eymin, ymin)
        exmax = max(exmax, xmax)
        eymax = max(eymax, ymax)
    ebox[k, 0] = exmin
    ebox[k, 1] = eymin
    ebox[k, 2] = exmax
    ebox[k, 3] = eymax


@njit(cache=True, nogil=True)
def _bounds_kernel(first, last, shapes, ids, n_el, params, out):
    unit = shapes[2]
    k_max = ids.shape[1]
    wv = np.empty((k_max, unit.shape[1], unit.shape[2], 2))
    pbox = np.empty((k_max, unit.shape[1], 4))
    for i in range(first, last):
        for k in range(n_el[i]):
            world_element(shapes, ids[i, k], params[i, k], wv, pbox, out[i], k)
