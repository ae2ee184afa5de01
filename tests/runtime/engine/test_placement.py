"""Steps, walls and rows decoded: the placement kernel against a plain-Python reference, and evolved floors
checked with NumPy and shapely alone, not MazeGen's geometry."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon

from mazegen.dsl.loader import load_spec
from mazegen.generator.build import build
from mazegen.runtime.engine import Problem, evolve
from mazegen.runtime.engine._placement import GENE_MAX, SX, SY, THETA, X, Y, placement_params
from mazegen.spec import ElementType, Spec, step_span

SPEC = """units cm
element rack { shape rect  size 200..400 step 50 x 80..110  rotation 0, 90 }
element crate { shape square  size 40..60 step 5  at step 50 }
element locker { shape rect  size 60..100 x 40..50  against wall }
element bin { shape bars (0, 0)-(1, 0) (1, 0)-(1, 1) thickness 8  size 50..80
              rotation -90, 0, 90, 180  against wall }
element cone { shape triangle  size 30..50  rotation any }
row rackRow of rack { count 2..5  spacing 40..80 step 10 }
row lockers of locker { count 2..4  spacing 5..20 }
row cones of cone { count 2..3  spacing 0.1..0.3 m }

arena hall { size 2000 x 1500 cm  start (100, 100)  goal (1900, 1400)  robot radius 25 }
scenario store on hall { elements rackRow, crate, lockers, cones, bin, cone  max elements 24 }
fitness { count  overlap reject  outside reject }
evolution { population 1000  generations 2  genome 24  seed 5 }
"""


@pytest.fixture(scope="module")
def problem(tmp_path_factory) -> Problem:
    folder = tmp_path_factory.mktemp("structure")
    (folder / "store.maze").write_text(SPEC, encoding="utf-8")
    build(load_spec(folder / "store.maze"), folder / "build")
    return Problem.from_build_dir(folder / "build")


def outline(kind: ElementType, sx: float, sy: float) -> np.ndarray:
    """``float[V, 2]``: every vertex of ``kind`` at size ``sx, sy`` in its own frame."""
    return np.array(
        [
            (ux * sx + ox, uy * sy + oy)
            for part in kind.parts
            for (ux, uy), (ox, oy) in zip(part.unit, part.offset)
        ]
    )


def drawn(gene: int, low: float, high: float, step: float | None, *, grid: bool = False) -> float:
    """A gene's value as docs/language.md says: scaled into the range, or one of its values on the step."""
    if step is None:
        return low + (high - low) * gene / GENE_MAX
    if grid:  # multiples of the step
        first, count = step_span(low, high, step)
        return (first + gene * count // 65536) * step
    count = math.floor((high - low) / step + 1e-9) + 1
    return low + step * (gene * count // 65536)


def turned(gene: int, rotations: tuple[float, ...], span: tuple[float, float] | None) -> float:
    return span[0] + (span[1] - span[0]) * gene / GENE_MAX if span else rotations[gene % len(rotations)]


def reference_row(
    spec: Spec, kind: ElementType, genes: np.ndarray, slot: int, rotation, row=None, count: int = 1
) -> tuple[list[float], np.ndarray]:
    """x, y, sx, sy and rotation (radians) of an element alone, or of the first of a row's ``count``
    members (``row`` its Row), from the genes of ``slot``; ``rotation``: the rotations it turns by.
    Also the pitch from one member to the next (zero alone)."""
    g = [int(v) for v in genes[slot]]
    width, height = spec.arena.width, spec.arena.height
    sx = drawn(g[2], *kind.size, kind.size_step)
    sy = sx if kind.uniform else drawn(g[3], *kind.size2, kind.depth_step)
    angle = turned(g[4], *rotation)
    pitch = np.zeros(2)
    ranges = [[0.0, width], [0.0, height]]
    if row is not None:
        lows_highs = outline(kind, sx, sy)[:, 0]
        gap = drawn(int(genes[slot + 1, 0]), *row.spacing, row.spacing_step)
        theta = math.radians(angle)
        pitch = (lows_highs.max() - lows_highs.min() + gap) * np.array([math.cos(theta), math.sin(theta)])
        for axis, (low, high) in enumerate(ranges):  # the last member within the arena too, if it fits
            span = (count - 1) * pitch[axis]
            first, last = low - min(span, 0.0), high - max(span, 0.0)
            if first <= last:
                ranges[axis] = [first, last]
    x = drawn(g[0], *ranges[0], kind.position_step, grid=True)
    y = drawn(g[1], *ranges[1], kind.position_step, grid=True)
    if kind.against_wall:
        back = -outline(kind, sx, sy)[:, 1].min()
        wall = round(angle / 90) % 4
        x, y = [(x, back), (width - back, y), (x, height - back), (back, y)][wall]
    return [x, y, sx, sy, math.radians(angle)], pitch


def reference_params(spec: Spec, mapped, genes: np.ndarray) -> np.ndarray:
    """Plain-Python placement of every element, the rows' members included (docs/language.md)."""
    types, rows = spec.scenario_elements, spec.scenario.rows
    params = np.zeros((*mapped.element_ids.shape, 5))
    pitch = np.zeros(2)  # from one member of the row being placed to the next
    for i in range(params.shape[0]):
        for k in range(mapped.n_elements[i]):
            kind = types[mapped.element_ids[i, k]]
            line, member, count = mapped.membership[i, k]
            if member > 0:
                first = params[i, k - member]
                params[i, k] = first
                params[i, k, :2] += member * pitch
                continue
            turn = rows[line] if line >= 0 else kind
            rotation = (turn.rotations, turn.rotation_range)
            row = rows[line] if line >= 0 else None
            params[i, k], pitch = reference_row(spec, kind, genes[i], k, rotation, row, int(count))
    return params


def test_the_placement_kernel_equals_the_reference(problem):
    rng = np.random.default_rng(3)
    codons = rng.integers(0, 256, size=(2000, problem.spec.evolution.genome), dtype=np.int32)
    genes = rng.integers(0, GENE_MAX + 1, size=(2000, problem.slots, 5), dtype=np.uint16)
    mapped, _ = problem.decode(codons, genes)
    assert (mapped.membership[..., 0] >= 0).sum() > 1000  # many rows' members
    params = placement_params(mapped, genes, problem.ranges, problem.table, None)
    expected = reference_params(problem.spec, mapped, genes)
    # At right angles the kernel's rows run exactly along the axes, and walls are touched exactly as
    # the geometry kernels compute the elements: a few units of the last place apart.
    assert np.allclose(params, expected, rtol=0, atol=1e-9)


def world(kind: ElementType, row: np.ndarray) -> np.ndarray:
    """The element's vertices on the floor, by plain NumPy."""
    c, s = math.cos(row[THETA]), math.sin(row[THETA])
    local = outline(kind, row[SX], row[SY])
    return np.stack(
        [row[X] + c * local[:, 0] - s * local[:, 1], row[Y] + s * local[:, 0] + c * local[:, 1]], 1
    )


def shapes(kind: ElementType, row: np.ndarray) -> shapely.Geometry:
    """The element as one shapely geometry (the union of its convex parts)."""
    c, s = math.cos(row[THETA]), math.sin(row[THETA])
    polygons = []
    for part in kind.parts:
        local = [(ux * row[SX] + ox, uy * row[SY] + oy) for (ux, uy), (ox, oy) in zip(part.unit, part.offset)]
        polygons.append(Polygon([(row[X] + c * lx - s * ly, row[Y] + s * lx + c * ly) for lx, ly in local]))
    return shapely.union_all(polygons)


@pytest.fixture(scope="module")
def evolved(problem):
    """1,000 floors of the spec's last generation, decoded."""
    result = evolve(problem, problem.spec.evolution, np.random.default_rng(problem.spec.evolution.seed))
    mapped, population = problem.decode(result.codons, result.genes)
    return mapped, population, np.isfinite(result.fitness)


def rows_of(mapped, i: int) -> list[list[int]]:
    """The slots of each row of floor ``i``, in order."""
    found: list[list[int]] = []
    for k in range(mapped.n_elements[i]):
        line, member, count = mapped.membership[i, k]
        if line >= 0 and member == 0:
            found.append(list(range(k, k + count)))
    return found


def test_evolved_rows_are_equally_spaced_aligned_and_within_their_spacing(problem, evolved):
    mapped, population, _ = evolved
    spec, types = problem.spec, problem.spec.scenario_elements
    params = population.params
    scale = max(spec.arena.width, spec.arena.height)
    checked = 0
    for i in range(population.size):
        for slots in rows_of(mapped, i):
            row = spec.scenario.rows[mapped.membership[i, slots[0], 0]]
            kind = types[population.element_ids[i, slots[0]]]
            members = params[i, slots]
            assert np.all(
                members[:, [SX, SY, THETA]] == members[0, [SX, SY, THETA]]
            )  # one size, one rotation
            centres = members[:, [X, Y]]
            steps = np.diff(centres, axis=0)
            direction = np.array([math.cos(members[0, THETA]), math.sin(members[0, THETA])])
            assert np.allclose(steps, steps[0], rtol=0, atol=1e-9 * scale)  # equally spaced
            offsets = centres - centres[0]
            across = offsets[:, 0] * direction[1] - offsets[:, 1] * direction[0]
            assert np.allclose(across, 0, rtol=0, atol=1e-9 * scale)  # on one line
            assert np.all(steps @ direction > 0)  # along its line, first to last
            outlines = [shapes(kind, member) for member in members]
            for a, b in itertools.pairwise(outlines):
                gap = a.distance(b)
                low, high = row.spacing
                assert low - 1e-7 <= gap <= high + 1e-7
                if row.spacing_step is not None:
                    ratio = (gap - low) / row.spacing_step
                    assert abs(ratio - round(ratio)) < 1e-6
            checked += 1
    assert checked > 300


def test_evolved_floors_hold_their_members_as_any_element(problem, evolved):
    """Valid floors (overlap and outside reject) have every member inside the arena and clear of every
    other element, by shapely."""
    mapped, population, valid = evolved
    spec, types = problem.spec, problem.spec.scenario_elements
    arena = shapely.box(0, 0, spec.arena.width, spec.arena.height).buffer(1e-9)
    members = 0
    for i in np.flatnonzero(valid):
        count = population.n_elements[i]
        outlines = [
            shapes(types[e], row)
            for e, row in zip(population.element_ids[i, :count], population.params[i, :count])
        ]
        assert all(arena.contains(outline) for outline in outlines)
        for a in range(count):
            for b in range(a + 1, count):
                assert outlines[a].intersection(outlines[b]).area < 1e-6
        members += int((mapped.membership[i, :count, 0] >= 0).sum())
    assert members > 1000


def test_evolved_steps_and_walls(problem, evolved):
    _, population, _ = evolved
    spec, types = problem.spec, problem.spec.scenario_elements
    width, height = spec.arena.width, spec.arena.height
    seen = {"crate": 0, "locker": 0, "bin": 0}
    for i in range(population.size):
        for e, row in zip(population.element_ids[i, : population.n_elements[i]], population.params[i]):
            kind = types[e]
            if kind.name == "crate":  # centre on the 50 cm grid, size 40 + 5 k
                assert np.allclose(row[[X, Y]] / 50, np.round(row[[X, Y]] / 50), rtol=0, atol=1e-9)
                assert abs((row[SX] - 40) / 5 - round((row[SX] - 40) / 5)) < 1e-9
            if kind.against_wall:  # its back on the wall its rotation names, by plain NumPy
                points = world(kind, row)
                wall = round(math.degrees(row[THETA]) / 90) % 4
                reach = [
                    points[:, 1].min(),
                    width - points[:, 0].max(),
                    height - points[:, 1].max(),
                    points[:, 0].min(),
                ]
                assert abs(reach[wall]) < 1e-9
            seen[kind.name] = seen.get(kind.name, 0) + 1
    assert min(seen.values()) > 50


def against_wall_floors(folder, arena: str) -> tuple[Problem, np.ndarray]:
    """Lockers against a wall of ``arena``, placed by 3,000 random genomes: each one's world vertices."""
    spec_text = "units cm\nelement locker { shape rect  size 20..40 x 10..20  against wall }\n"
    spec_text += arena + "scenario s on hall { elements locker  grammar list  max elements 4 }\n"
    (folder / "s.maze").write_text(spec_text, encoding="utf-8")
    build(load_spec(folder / "s.maze"), folder / "build")
    problem = Problem.from_build_dir(folder / "build")
    rng = np.random.default_rng(2)
    codons = rng.integers(0, 256, size=(3000, 8), dtype=np.int32)
    genes = rng.integers(0, GENE_MAX + 1, size=(3000, 4, 5), dtype=np.uint16)
    _, population = problem.decode(codons, genes)
    kind = problem.spec.element("locker")
    placed = [
        world(kind, population.params[i, k]) for i in range(3000) for k in range(population.n_elements[i])
    ]
    assert len(placed) > 1000
    return problem, np.array(placed)


def touching(points: np.ndarray, box: tuple[float, float, float, float]) -> np.ndarray:
    """Which side of ``box`` (bottom, right, top, left) each element, of vertices ``points``, touches from
    inside, or -1."""
    reach = np.stack(
        [
            points[..., 1].min(-1) - box[1],
            box[2] - points[..., 0].max(-1),
            box[3] - points[..., 1].max(-1),
            points[..., 0].min(-1) - box[0],
        ],
        -1,
    )
    side = np.abs(reach).argmin(-1)
    return np.where(np.abs(np.take_along_axis(reach, side[:, None], -1)[:, 0]) < 1e-9, side, -1)


def test_on_a_map_the_walls_are_the_box_of_its_free_cells(tmp_path):
    from tests.map_files import hall_pixels, write_map

    write_map(
        tmp_path, hall_pixels(gap=None)
    )  # 40 x 30 cells of 0.1 m, walls around: free 10..390 x 10..290 cm
    arena = 'arena hall { map "hall.yaml" cm  start (50, 50)  goal (300, 250)  robot radius 5 }\n'
    problem, placed = against_wall_floors(tmp_path, arena)
    assert problem.ranges.walls.tolist() == [10.0, 10.0, 390.0, 290.0]
    walls = touching(placed, (10.0, 10.0, 390.0, 290.0))
    assert (walls >= 0).all() and set(walls.tolist()) == {0, 1, 2, 3}
    centres = placed.mean(axis=1)  # along its wall, within the box
    assert (centres >= 10.0 - 1e-9).all() and (centres[:, 0] <= 390.0 + 1e-9).all()


def test_a_held_element_stands_against_the_walls_its_zones_reach(tmp_path):
    arena = (
        "arena hall { size 400 x 300 cm  start (50, 150)  goal (350, 150)  robot radius 5\n"
        "  zone bays rect (100, 0) (300, 60) holds locker }\n"  # on the bottom wall only
    )
    problem, placed = against_wall_floors(tmp_path, arena)
    assert problem.ranges.rotations[0, : problem.ranges.n_rotations[0]].tolist() == [0.0]
    assert (touching(placed, (0.0, 0.0, 400.0, 300.0)) == 0).all()
    assert placed[..., 0].min() >= 100 - 20 and placed[..., 0].max() <= 300 + 20  # along the zone
