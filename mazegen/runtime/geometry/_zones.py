"""An arena's zones and the elements that break their rules: an element overlapping a zone that does
not accept its type (``keep clear`` accepts none), or of a type some zone ``holds`` and lying wholly
inside none of them.

Overlap is the separating-axis test of :mod:`~mazegen.runtime.geometry._overlap` between an element's
convex parts and a zone's (touching is not overlapping). Containment is exact for simple polygons:
every vertex of the element inside the zone's outline or on it, and no edge of the element crossing
one of the outline's.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numba import njit

from mazegen.runtime.geometry._elements import ElementTable, population_arrays, world_element
from mazegen.runtime.geometry._overlap import edge_separates
from mazegen.runtime.threads import in_blocks
from mazegen.spec import Zone


@dataclass(frozen=True)
class ZoneArrays:
    """The zones of an arena as the kernel reads them, for the element types of one scenario.

    Attributes:
        parts: ``float64[Q, V, 2]``: every zone's convex parts, counter-clockwise, padded.
        count: ``int64[Q]``: vertices of each part.
        zone: ``int64[Q]``: the zone each part belongs to.
        box: ``float64[Q, 4]``: each part's ``(xmin, ymin, xmax, ymax)``.
        outline: ``float64[Z, W, 2]``: each zone's outline, padded; ``outline_count`` ``int64[Z]``.
        accepts: ``bool[Z, E]``: whether zone ``z`` lets elements of type ``e`` overlap it.
        holds: ``bool[Z, E]``: whether zone ``z`` is one that elements of type ``e`` must lie in.
    """

    parts: np.ndarray
    count: np.ndarray
    zone: np.ndarray
    box: np.ndarray
    outline: np.ndarray
    outline_count: np.ndarray
    accepts: np.ndarray
    holds: np.ndarray

    @classmethod
    @lru_cache(maxsize=16)
    def of(cls, zones: tuple[Zone, ...], types: tuple[str, ...]) -> ZoneArrays:
        """The arrays of ``zones`` for element types ``types`` (in the scenario's order)."""
        parts = [(z, part) for z, zone in enumerate(zones) for part in zone.parts]
        width = max(len(part) for _, part in parts)
        vertices = np.zeros((len(parts), width, 2))
        for q, (_, part) in enumerate(parts):
            vertices[q, : len(part)] = part
        longest = max(len(zone.outline) for zone in zones)
        outline = np.zeros((len(zones), longest, 2))
        for z, zone in enumerate(zones):
            outline[z, : len(zone.outline)] = zone.outline
        listed = np.array([[name in zone.types for name in types] for zone in zones], dtype=bool)
        rule = np.array([zone.rule for zone in zones])
        corners = [np.array(part) for _, part in parts]
        return cls(
            parts=vertices,
            count=np.array([len(part) for _, part in parts], np.int64),
            zone=np.array([z for z, _ in parts], np.int64),
            box=np.array([[*c.min(axis=0), *c.max(axis=0)] for c in corners]),
            outline=outline,
            outline_count=np.array([len(zone.outline) for zone in zones], np.int64),
            accepts=np.where((rule == "holds")[:, None], True, listed & (rule == "accepts")[:, None]),
            holds=listed & (rule == "holds")[:, None],
        )


def elements_off_zones(
    table: ElementTable,
    element_ids: np.ndarray,
    n_elements: np.ndarray,
    params: np.ndarray,
    zones: ZoneArrays,
    size: tuple[float, float],
) -> np.ndarray:
    """``bool[N, K]``: which elements inside the ``size`` rectangle break a zone's rule (an element
    outside it is :func:`~mazegen.runtime.geometry._overlap.elements_outside`'s)."""
    ids, n_el, prm = population_arrays(table, element_ids, n_elements, params)
    out = np.zeros(ids.shape, np.bool_)
    if ids.shape[0]:
        z = zones
        arrays = (z.parts, z.count, z.zone, z.box, z.outline, z.outline_count, z.accepts, z.holds)
        width, height = float(size[0]), float(size[1])
        in_blocks(_zones_kernel, ids.shape[0], table.shapes, ids, n_el, prm, *arrays, width, height, out)
    return out


@njit(cache=True, nogil=True)
def _zones_kernel(
    first,
    last,
    shapes,
    ids,
    n_el,
    params,
    parts,
    count,
    zone,
    box,
    outline,
    outline_count,
    accepts,
    holds,
    width,
    height,
    out,
):  # pragma: no cover - compiled
    n_parts, n_vertices, unit = shapes[0], shapes[1], shapes[2]
    # Slot 0 holds the element, slot 1 every zone part, so that one array serves the axis test.
    wv = np.zeros((2, max(unit.shape[1], parts.shape[0]), max(unit.shape[2], parts.shape[1]), 2))
    for q in range(parts.shape[0]):
        for v in range(count[q]):
            wv[1, q, v, 0] = parts[q, v, 0]
            wv[1, q, v, 1] = parts[q, v, 1]
    pbox = np.empty((1, unit.shape[1], 4))
    ebox = np.empty((1, 4))
    for i in range(first, last):
        for k in range(n_el[i]):
            e = ids[i, k]
            world_element(shapes, e, params[i, k], wv, pbox, ebox, 0)
            if ebox[0, 0] < 0.0 or ebox[0, 1] < 0.0 or ebox[0, 2] > width or ebox[0, 3] > height:
                continue
            broken = False
            for q in range(parts.shape[0]):
                if accepts[zone[q], e] or broken:
                    continue
                for p in range(n_parts[e]):
                    meet = (pbox[0, p, 0] < box[q, 2]) & (box[q, 0] < pbox[0, p, 2])
                    meet &= (pbox[0, p, 1] < box[q, 3]) & (box[q, 1] < pbox[0, p, 3])
                    n = n_vertices[e, p]
                    if meet and not (
                        edge_separates(wv, 0, p, n, 1, q, count[q])
                        or edge_separates(wv, 1, q, count[q], 0, p, n)
                    ):
                        broken = True
                        break
            held, inside = False, False
            for z in range(holds.shape[0]):
                if holds[z, e] and not inside:
                    held = True
                    inside = _inside(wv, n_parts[e], n_vertices[e], outline[z], outline_count[z])
            out[i, k] = broken or (held and not inside)


@njit(cache=True, inline="always")
def _inside(wv, n_parts, n_vertices, outline, n):  # pragma: no cover - compiled
    """Whether the element in ``wv[0]`` lies wholly inside the polygon ``outline[:n]`` (its boundary
    included): each vertex in it or on it, and no element edge crossing an outline edge."""
    for p in range(n_parts):
        m = n_vertices[p]
        for v in range(m):
            x, y = wv[0, p, v, 0], wv[0, p, v, 1]
            if not _point_in(outline, n, x, y):
                return False
            u = v + 1 if v + 1 < m else 0
            for j in range(n):
                jj = j + 1 if j + 1 < n else 0
                if _cross(x, y, wv[0, p, u, 0], wv[0, p, u, 1], outline[j], outline[jj]):
                    return False
    return True


@njit(cache=True, inline="always")
def _point_in(outline, n, x, y):  # pragma: no cover - compiled
    """Whether ``(x, y)`` lies inside the polygon ``outline[:n]`` or on its boundary (1e-9 of slack)."""
    inside = False
    for j in range(n):
        jj = j + 1 if j + 1 < n else 0
        ax, ay, bx, by = outline[j, 0], outline[j, 1], outline[jj, 0], outline[jj, 1]
        length = np.hypot(bx - ax, by - ay)
        side = (bx - ax) * (y - ay) - (by - ay) * (x - ax)
        along = (x - ax) * (bx - ax) + (y - ay) * (by - ay)
        if (
            abs(side) <= 1e-9 * max(length, 1.0) * max(length, 1.0)
            and -1e-9 <= along <= length * length + 1e-9
        ):
            return True  # on this edge
        if (ay > y) != (by > y) and x < ax + (y - ay) * (bx - ax) / (by - ay):
            inside = not inside
    return inside


@njit(cache=True, inline="always")
def _cross(px, py, qx, qy, r, s):  # pragma: no cover - compiled
    """Whether segments ``pq`` and ``rs`` cross properly (each one's ends strictly on both sides of the
    other's line)."""
    d1 = (s[0] - r[0]) * (py - r[1]) - (s[1] - r[1]) * (px - r[0])
    d2 = (s[0] - r[0]) * (qy - r[1]) - (s[1] - r[1]) * (qx - r[0])
    d3 = (qx - px) * (r[1] - py) - (qy - py) * (r[0] - px)
    d4 = (qx - px) * (s[1] - py) - (qy - py) * (s[0] - px)
    return ((d1 > 0.0 and d2 < 0.0) or (d1 < 0.0 and d2 > 0.0)) and (
        (d3 > 0.0 and d4 < 0.0) or (d3 < 0.0 and d4 > 0.0)
    )
