"""Placement: each element's position, size and rotation, decoded from its placement genes.

A gene ``g`` (``0..GENE_MAX``) is scaled into its range as ``low + (high - low) · g / GENE_MAX``,
or, on a step (``at step``, ``size LOW..HIGH step S``, a row's ``spacing ... step S``), picks one of
the range's ``n`` values on the step, value ``(g · n) >> 16``: every individual lies exactly on its
step, with no repair afterwards. An element ``against wall`` stands with its back to the wall its
rotation names, its position along that wall drawn as any other's (within the walls' box). A row
(:class:`~mazegen.spec.Row`) is placed by the genes of its first member's slot: that member as a lone
element of its type would be, with the row's rotation; the others follow it along the row's line
(its members' own x axis), one member's width plus a gap apart, the gap drawn from the x gene of the
row's second slot. Steps, walls and rows are a second pass over the elements placed alone, which a spec
without them neither runs nor compiles.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numba import njit

from mazegen.runtime.compiling import inner_kernel
from mazegen.runtime.geometry import world_element
from mazegen.runtime.threads import in_blocks
from mazegen.spec import Box, Spec, placing_area, step_span, walls_reached

if TYPE_CHECKING:
    from mazegen.runtime.engine._mapping import PopulationMap
    from mazegen.runtime.geometry import ElementTable

GENE_MAX = 65535
"""Placement genes are integers 0..GENE_MAX, scaled into each element's ranges."""

PLACEMENT_GENES = 5
"""Genes per element slot: x, y, size (width for rect), depth (rect only), rotation."""

X, Y, SX, SY, THETA = range(5)

CONTINUOUS = (0.0, 0.0, 0.0)
"""A ladder (:attr:`Ranges.ladders`) of a range drawn anywhere, not on a step."""

NUDGES = 8
"""Most times an element against a wall is moved off it by what rounding put beyond it."""


def ladder(low: float, high: float, step: float | None) -> tuple[float, float, float]:
    """``(first, step, count)`` of the values ``low + j · step`` within ``[low, high]`` (a billionth of a
    step of rounding either way), or :data:`CONTINUOUS` without a step."""
    if step is None:
        return CONTINUOUS
    return (low, step, float(np.floor((high - low) / step + 1e-9)) + 1.0)


def grid_ladder(low: float, high: float, step: float | None) -> tuple[float, float, float]:
    """The ladder of the multiples of ``step`` within ``[low, high]`` (:func:`~mazegen.spec.step_span`):
    positions ``at step``."""
    if step is None:
        return CONTINUOUS
    first, count = step_span(low, high, step)
    return (first * step, step, float(count))


@dataclass(frozen=True)
class Ranges:
    """Per element type ranges, as arrays indexed by element id; rotations also per row (index
    ``E + r`` for row ``r``)."""

    size: np.ndarray  # float64[E, 2]
    depth: np.ndarray  # float64[E, 2] (rect) or the size range again
    uniform: np.ndarray  # bool[E]
    aspect: np.ndarray  # float64[E]: depth / width at mid ranges (grammar placement of rects)
    rot_lo: np.ndarray  # float64[E + R] degrees (continuous)
    rot_hi: np.ndarray
    rot_free: np.ndarray  # bool[E + R] continuous rotation
    rotations: np.ndarray  # float64[E + R, A] discrete angles, padded by repetition
    n_rotations: np.ndarray  # int32[E + R]
    area: np.ndarray  # float64[E, 4]: (x, y) low and high of positions, the arena or the zones holding it
    ladders: np.ndarray  # float64[E, 4, 3]: x, y, size and depth on a step (:func:`ladder`), or not
    against: np.ndarray  # bool[E]: stands against a wall
    walls: np.ndarray  # float64[4]: the box whose sides are the walls (the arena, or a map's free cells)
    gaps: np.ndarray  # float64[R, 2]: each row's range of gaps between members
    gap_ladders: np.ndarray  # float64[R, 1, 3]

    @classmethod
    def from_spec(cls, spec: Spec) -> Ranges:
        """Gather the ranges of the scenario's element types and rows."""
        types, rows, arena = spec.scenario_elements, spec.scenario.rows, spec.arena
        walls = _walls(spec)
        turning = [(t.name, t.rotations, t.rotation_range) for t in types]
        turning += [(r.member, r.rotations, r.rotation_range) for r in rows]
        turns = [(_reached(spec, name, walls, angles), span) for name, angles, span in turning]
        width = max(len(angles) for angles, _ in turns)
        size = np.array([t.size for t in types], dtype=np.float64)
        depth = np.array([t.size2 or t.size for t in types], dtype=np.float64)
        area = [placing_area(arena, t, walls) for t in types]
        return cls(
            size=size,
            depth=depth,
            uniform=np.array([t.uniform for t in types]),
            aspect=depth.mean(axis=1) / size.mean(axis=1),
            rot_lo=np.array([(span or (0.0, 0.0))[0] for _, span in turns]),
            rot_hi=np.array([(span or (0.0, 0.0))[1] for _, span in turns]),
            rot_free=np.array([span is not None for _, span in turns]),
            rotations=np.array(
                [list(angles) + [angles[0]] * (width - len(angles)) for angles, _ in turns], dtype=np.float64
            ),
            n_rotations=np.array([len(angles) for angles, _ in turns], dtype=np.int32),
            area=np.array(area, dtype=np.float64),
            ladders=np.array(
                [
                    (
                        grid_ladder(box[0], box[2], t.position_step),
                        grid_ladder(box[1], box[3], t.position_step),
                        ladder(*t.size, t.size_step),
                        ladder(*(t.size2 or t.size), t.depth_step),
                    )
                    for t, box in zip(types, area)
                ],
                dtype=np.float64,
            ).reshape(len(types), 4, 3),
            against=np.array([t.against_wall for t in types]),
            walls=np.array(walls, dtype=np.float64),
            gaps=np.array([r.spacing for r in rows], dtype=np.float64).reshape(len(rows), 2),
            gap_ladders=np.array(
                [ladder(*r.spacing, r.spacing_step) for r in rows], dtype=np.float64
            ).reshape(len(rows), 1, 3),
        )

    def structure(self, mapped: PopulationMap, table: ElementTable) -> tuple[Any, ...] | None:
        """What the placement kernel reads to put elements on steps and walls and rows' members in
        their lines, or None for a spec without any (whose kernel then compiles without them)."""
        if not (self.gaps.size or self.against.any() or self.ladders[..., 2].any()):
            return None
        steps = (self.ladders, self.against, self.walls, self.gaps, self.gap_ladders)
        return (mapped.membership, table.shapes, *steps)


def _walls(spec: Spec) -> Box:
    """The box whose sides an element against a wall stands at: the arena's, or on a map the box
    around its free cells (:func:`mazegen.maps.free_box`)."""
    arena = spec.arena
    if arena.base is None:
        return (0.0, 0.0, arena.width, arena.height)
    from mazegen.maps import free_box

    return free_box(arena.base)


def _reached(spec: Spec, name: str, walls: Box, angles: tuple[float, ...]) -> tuple[float, ...]:
    """The rotations of an element of type ``name`` (alone or in a row) that turn it to a wall its
    area reaches, when it stands against one (the language refuses a type that reaches none)."""
    element = spec.element(name)
    if not element.against_wall:
        return angles
    return walls_reached(placing_area(spec.arena, element, walls), walls, angles) or angles


@njit(cache=True, inline="always")
def _scaled(gene, low, high):  # pragma: no cover - compiled
    """A gene's value scaled into ``[low, high]``."""
    return low + (high - low) * (gene / GENE_MAX)


@njit(cache=True, inline="always")
def _drawn(gene, low, high, ladders, e, axis):  # pragma: no cover - compiled
    """A gene's value in ``[low, high]``: scaled into it, or one of the values of ladder ``ladders[e,
    axis]`` (indexed here: a view of it would cost a reference count per element)."""
    count = ladders[e, axis, 2]
    if count > 0.0:
        return ladders[e, axis, 0] + ladders[e, axis, 1] * ((np.int64(gene) * np.int64(count)) >> 16)
    return _scaled(gene, low, high)


@njit(cache=True, inline="always")
def _turned(gene, turn, rot_lo, rot_hi, rot_free, rotations, n_rotations):  # pragma: no cover - compiled
    """The rotation (degrees) a gene gives type or row ``turn``."""
    if rot_free[turn]:
        return _scaled(gene, rot_lo[turn], rot_hi[turn])
    return rotations[turn, gene % n_rotations[turn]]


@njit(cache=True, inline="always")
def _extent(shapes, e, sx, sy, axis):  # pragma: no cover - compiled
    """The lowest and highest coordinate along its own ``axis`` of an element of type ``e`` at size ``sx,
    sy``, before rotation."""
    n_parts, n_vertices, unit, offset = shapes
    scale = sx if axis == 0 else sy
    low, high = np.inf, -np.inf
    for p in range(n_parts[e]):
        for v in range(n_vertices[e, p]):
            value = unit[e, p, v, axis] * scale + offset[e, p, v, axis]
            low, high = min(low, value), max(high, value)
    return low, high


@njit(cache=True, inline="always")
def _direction(angle):  # pragma: no cover - compiled
    """``(cos, sin)`` of ``angle`` degrees, exact at right angles (a row along a wall stays on it)."""
    quarter = angle / 90.0
    if quarter == np.floor(quarter):
        turn = np.int64(quarter) % 4
        return ((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0))[turn]
    theta = np.radians(angle)
    return np.cos(theta), np.sin(theta)


@njit(cache=True, inline="always")
def _against_wall(shapes, e, row, walls, scratch):  # pragma: no cover - compiled
    """Put the element of type ``e`` placed by ``row`` (x, y, sx, sy, radians) with its back to the wall
    its rotation names, touching it: its nearest vertex exactly as the geometry kernels compute it."""
    wv, pbox, ebox = scratch
    wall = np.int64(np.floor(np.degrees(row[4]) / 90.0 + 0.5)) % 4
    back = -_extent(shapes, e, row[2], row[3], 1)[0]
    axis = 1 if wall % 2 == 0 else 0  # the coordinate that moves the element off the wall
    inward = 1.0 if wall == 0 or wall == 3 else -1.0
    side = walls[1] if wall == 0 else walls[2] if wall == 1 else walls[3] if wall == 2 else walls[0]
    row[axis] = side + inward * back
    for _ in range(NUDGES):
        world_element(shapes, e, row, wv, pbox, ebox, 0)
        reach = ebox[0, axis] if inward > 0.0 else ebox[0, axis + 2]
        beyond = (side - reach) * inward
        if beyond <= 0.0:
            return
        row[axis] += inward * max(beyond, abs(row[axis]) * 2.3e-16)


@njit(cache=True, nogil=True)
def _placement_kernel(
    first, last, ids, n_elements, genes, numbers, sizes, turns, area, structure, grammar_scale, out
):  # pragma: no cover
    """Every element placed alone (``structure`` None: a spec without steps, walls or rows, whose kernel
    compiles without them), then by :func:`_place_structure`."""
    size, depth, uniform, aspect = sizes  # unpacked once, out of the loops
    rot_lo, rot_hi, rot_free, rotations, n_rotations = turns
    for i in range(first, last):
        for k in range(n_elements[i]):
            e = ids[i, k]
            g = genes[i, k]
            x = _scaled(g[0], area[e, 0], area[e, 2])
            y = _scaled(g[1], area[e, 1], area[e, 3])
            sx = _scaled(g[2], size[e, 0], size[e, 1])
            sy = sx if uniform[e] else _scaled(g[3], depth[e, 0], depth[e, 1])
            angle = _turned(g[4], e, rot_lo, rot_hi, rot_free, rotations, n_rotations)
            if grammar_scale > 0.0:
                nums = numbers[i, k]
                if not np.isnan(nums[0]):
                    sx = nums[0] * grammar_scale
                    sy = sx if uniform[e] else sx * aspect[e]
                if not np.isnan(nums[1]):
                    x = nums[1]
                if not np.isnan(nums[2]):
                    y = nums[2]
                if not np.isnan(nums[3]):
                    angle = nums[3]
            out[i, k, 0] = x
            out[i, k, 1] = y
            out[i, k, 2] = sx
            out[i, k, 3] = sy
            out[i, k, 4] = np.radians(angle)
        out[i, n_elements[i] :] = 0.0
    if structure is not None:
        _place_structure(first, last, ids, n_elements, genes, sizes, turns, area, structure, out)


@njit(cache=True, inline="always")
def _leaving_room(low, high, span):  # pragma: no cover - compiled
    """The range of a row's first member's coordinate, ``[low, high]`` cut by the row's ``span`` along it
    (its last member's offset from its first), so that the last stays within ``[low, high]`` too; the
    whole range when the row is longer than it."""
    first, last = low - min(span, 0.0), high - max(span, 0.0)
    return (first, last) if first <= last else (low, high)


@inner_kernel
def _place_structure(
    first, last, ids, n_elements, genes, sizes, turns, area, structure, out
):  # pragma: no cover
    """Put elements on their steps and walls, and rows' members in their lines, over the placement of
    :func:`_placement_kernel` (``structure``: membership, shapes, ladders, against, walls, gaps and
    gap ladders)."""
    size, depth, uniform = sizes[0], sizes[1], sizes[2]
    rot_lo, rot_hi, rot_free, rotations, n_rotations = turns
    membership, shapes, ladders, against, walls, gaps, gap_ladders = structure
    unit = shapes[2]
    scratch = (
        np.empty((1, unit.shape[1], unit.shape[2], 2)),
        np.empty((1, unit.shape[1], 4)),
        np.empty((1, 4)),
    )
    dx, dy = 0.0, 0.0  # from one member of the row being placed to the next
    for i in range(first, last):
        for k in range(n_elements[i]):
            e = ids[i, k]
            line, member = -1, 0
            if membership.shape[1] > 0:
                line, member = membership[i, k, 0], membership[i, k, 1]
            row = out[i, k]
            if member > 0:  # a row's later member: where its first is, moved along the row
                lead = out[i, k - member]
                row[0], row[1] = lead[0] + member * dx, lead[1] + member * dy
                row[2], row[3], row[4] = lead[2], lead[3], lead[4]
                continue
            g = genes[i, k]
            row[2] = _drawn(g[2], size[e, 0], size[e, 1], ladders, e, 2)
            row[3] = row[2] if uniform[e] else _drawn(g[3], depth[e, 0], depth[e, 1], ladders, e, 3)
            x_low, y_low, x_high, y_high = area[e, 0], area[e, 1], area[e, 2], area[e, 3]
            if line >= 0:  # a row turns as the row; the gap from the x gene of the row's second slot
                turn = uniform.shape[0] + line
                row[4] = np.radians(_turned(g[4], turn, rot_lo, rot_hi, rot_free, rotations, n_rotations))
                gap = _drawn(genes[i, k + 1, 0], gaps[line, 0], gaps[line, 1], gap_ladders, line, 0)
                low, high = _extent(shapes, e, row[2], row[3], 0)
                cos, sin = _direction(np.degrees(row[4]))
                dx, dy = (high - low + gap) * cos, (high - low + gap) * sin
                # The first member where the last one stays in the area too, when the row fits in it.
                last = membership[i, k, 2] - 1
                x_low, x_high = _leaving_room(x_low, x_high, last * dx)
                y_low, y_high = _leaving_room(y_low, y_high, last * dy)
            row[0] = _drawn(g[0], x_low, x_high, ladders, e, 0)
            row[1] = _drawn(g[1], y_low, y_high, ladders, e, 1)
            if against[e]:
                _against_wall(shapes, e, row, walls, scratch)


def placement_params(
    mapped: PopulationMap,
    genes: np.ndarray,
    ranges: Ranges,
    table: ElementTable,
    grammar_scale: float | None,
    out: np.ndarray | None = None,
) -> np.ndarray:
    """Element parameters from placement genes, or from grammar numbers where present.

    Slots past an individual's element count are zero.

    Args:
        mapped: Result of mapping the structure codons (with its row membership, for rows).
        genes: ``uint16[N, K, 5]`` placement genes.
        ranges: Element ranges (positions span each type's :attr:`Ranges.area`).
        table: The element types' outlines (a row's pitch, a wall's touch).
        grammar_scale: Multiplier of grammar size numbers, or ``None`` for gene placement.
        out: A C-contiguous ``float64[N, K, 5]`` array to overwrite instead of a new one.
    """
    shape = (*mapped.element_ids.shape, PLACEMENT_GENES)
    params = np.empty(shape, dtype=np.float64) if out is None else out
    if params.shape != shape or params.dtype != np.float64 or not params.flags.c_contiguous:
        raise ValueError("out does not fit the population")
    in_blocks(
        _placement_kernel,
        shape[0],
        mapped.element_ids,
        mapped.n_elements,
        genes,
        mapped.numbers,
        (ranges.size, ranges.depth, ranges.uniform, ranges.aspect),
        (ranges.rot_lo, ranges.rot_hi, ranges.rot_free, ranges.rotations, ranges.n_rotations),
        ranges.area,
        ranges.structure(mapped, table),
        -1.0 if grammar_scale is None else float(grammar_scale),
        params,
    )
    return params
