"""Homotopy classes on floors whose answer is known: counted by hand, invariant under translation,
jitter and renumbering, changed by moving an obstacle across the route."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from mazegen.runtime.geometry._cspace import Grid
from mazegen.runtime.navigation._classes import floor_topology, topology
from mazegen.runtime.navigation._sides import narrowest_width, sides
from mazegen.spec import Arena
from tests.runtime.floors import population

HALL = Arena("hall", 1000, 600, "cm", (50, 300), (950, 300), 20, 10)
"""Start and goal on one line across the middle; a robot 40 wide on a 10 cm grid."""


def box(x, y, width, depth):
    return ("vwall", x, y, width, depth, 0)


def classes(*elements, arena=HALL, detour=1.5):
    return floor_topology(population(arena, [list(elements)]), Grid.from_arena(arena), 0, detour=detour)


@pytest.mark.parametrize(
    ("name", "elements", "count"),
    [
        ("open floor", [], 1),
        ("one obstacle between start and goal", [box(500, 300, 100, 100)], 2),
        ("a wall with two gaps", [box(500, 50, 20, 100), box(500, 300, 20, 200), box(500, 550, 20, 100)], 2),
        ("two obstacles one behind the other", [box(350, 300, 100, 100), box(650, 300, 100, 100)], 4),
        (
            "the same two, their gap narrower than the robot",
            [box(440, 300, 100, 100), box(570, 300, 120, 100)],
            2,
        ),
        ("two side by side across the route", [box(500, 180, 100, 100), box(500, 420, 100, 100)], 3),
    ],
)
def test_hand_made_floors_have_the_classes_counted_by_hand(name, elements, count):
    found = classes(*elements)
    assert len(found.classes) == count, (name, found.signature)
    assert len({c.signature for c in found.classes}) == count  # each class named apart


def test_a_door_in_a_wall_is_the_narrowest_gap():
    """One door, 80 wide, in a wall from edge to edge: one class, through the door."""
    found = classes(box(500, 130, 20, 260), box(500, 470, 20, 260))
    assert len(found.classes) == 1 and found.classes[0].narrowest == pytest.approx(80, abs=20)


def reference_narrowest(points: np.ndarray, free: np.ndarray) -> float:
    """The narrowest width along ``points`` (cells) by plain NumPy and Python: the polyline sampled at
    ``max(2, ⌊4 · length⌋ + 1)`` points a segment, the cells it passes each once in a row, and at each
    the free run across its direction, stepped half a cell at a time."""
    cells: list[tuple[int, int]] = []
    for start, end in itertools.pairwise(points):
        samples = max(2, int(4 * np.hypot(*(end - start))) + 1)
        for t in np.linspace(0.0, 1.0, samples):
            cell = (
                int(np.floor(start[1] + (end[1] - start[1]) * t)),
                int(np.floor(start[0] + (end[0] - start[0]) * t)),
            )
            if not cells or cells[-1] != cell:
                cells.append(cell)
    narrowest = np.inf
    for k, (row, col) in enumerate(cells):
        a, b = cells[max(k - 2, 0)], cells[min(k + 2, len(cells) - 1)]
        along = np.array([b[0] - a[0], b[1] - a[1]], float)
        if not along.any():
            continue
        normal = np.array([-along[1], along[0]]) / np.hypot(*along)
        width = 1.0
        for way in (1.0, -1.0):
            t = 0.5
            while True:
                r, c = (int(np.floor(v)) for v in np.array([row, col]) + 0.5 + way * t * normal)
                if not (0 <= r < free.shape[0] and 0 <= c < free.shape[1]) or not free[r, c]:
                    break
                t += 0.5
            width += t - 0.5
        narrowest = min(narrowest, width)
    return narrowest


@pytest.mark.parametrize("seed", range(6))
def test_the_narrowest_gap_is_the_plain_references(seed):
    rng = np.random.default_rng(seed)
    free = rng.random((30, 40)) > 0.15
    points = np.column_stack([rng.uniform(0, 40, 5), rng.uniform(0, 30, 5)])
    assert narrowest_width(points, free) == reference_narrowest(points, free)


def test_a_blocked_floor_has_no_class():
    assert classes(box(500, 300, 20, 600)).classes == ()


def test_classes_are_named_by_the_sides_of_their_obstacles():
    """Below both, above both and the two weaves; the first obstacle's letter first."""
    found = classes(box(350, 300, 100, 100), box(650, 300, 100, 100))
    assert found.signature == "4:LL,LR,RL,RR"
    assert found.groups == 2
    for c in found.classes:  # a path passing an obstacle on its left has it at larger y than the path
        for letter, x in zip(c.signature, (350, 650)):
            y = np.interp(x, c.path[:, 0], c.path[:, 1])
            assert (y < 300) == (letter == "L"), (c.signature, x, y)


def test_each_class_keeps_its_shortest_path_and_narrowest_gap():
    """A wall with a 100-wide gap near the top and a 60-wide one near the bottom."""
    found = classes(box(500, 35, 20, 70), box(500, 275, 20, 290), box(500, 560, 20, 80))
    by_length = sorted(found.classes, key=lambda c: c.length)
    assert [c.length for c in found.classes] == [c.length for c in by_length]
    narrowest = sorted(round(c.narrowest) for c in found.classes)
    assert narrowest[0] == pytest.approx(60, abs=20) and narrowest[1] == pytest.approx(100, abs=20)
    for c in found.classes:
        assert c.length >= np.hypot(*(np.subtract(HALL.goal, HALL.start))) - 1e-9
        assert c.path[0].tolist() == list(HALL.start) and c.path[-1].tolist() == list(HALL.goal)


def test_translating_the_whole_floor_keeps_its_classes():
    elements = [box(350, 300, 100, 100), box(650, 300, 100, 100), box(500, 150, 60, 60)]
    moved = Arena("hall", 1000, 600, "cm", (50 + 30, 300 - 40), (950 + 30, 300 - 40), 20, 10)
    shifted = [(name, x + 30, y - 40, w, d, a) for name, x, y, w, d, a in elements]
    wider = Arena("hall", 1100, 600, "cm", moved.start, moved.goal, 20, 10)
    assert classes(*elements).signature == classes(*shifted, arena=wider).signature


def test_small_jitter_that_opens_no_gap_keeps_the_classes():
    """Seven classes 1.02 to 1.33 times the shortest path long, and a weave about 1.5 times: the
    detour kept is 1.4, so that no jitter moves a class across it."""
    rng = np.random.default_rng(3)
    elements = [box(350, 300, 100, 100), box(650, 300, 100, 100), box(500, 180, 100, 60)]
    signature = classes(*elements, detour=1.4).signature
    assert signature.startswith("7:")
    for _ in range(5):
        jittered = [
            (n, x + rng.uniform(-8, 8), y + rng.uniform(-8, 8), w, d, a) for n, x, y, w, d, a in elements
        ]
        assert classes(*jittered, detour=1.4).signature == signature


def test_renumbering_the_elements_keeps_the_classes():
    elements = [box(350, 300, 100, 100), box(650, 300, 100, 100), box(500, 480, 60, 60)]
    assert classes(*elements).signature == classes(*elements[::-1]).signature


def test_moving_an_obstacle_across_the_route_changes_the_class():
    """Beside the route, the shortest path passes it on one side; moved across, on the other. The
    floors are each other's mirror image: one canonical class, told apart by the shortest path's."""
    above, below = classes(box(500, 360, 60, 60)), classes(box(500, 240, 60, 60))
    assert above.classes[0].signature == "L" and below.classes[0].signature == "R"
    assert above.signature == below.signature == "2:L,R"


def test_a_trajectory_is_told_its_class():
    found = classes(box(500, 300, 100, 100))
    above = [(500.0, 400.0)]
    below = [(500.0, 200.0)]
    assert {found.class_of(np.array(above)), found.class_of(np.array(below))} == {"L", "R"}
    assert found.class_of(np.array(above)) != found.class_of(np.array(below))


def test_sides_agree_with_the_side_of_a_straight_path():
    marks = np.array([[5.0, 1.0], [5.0, -1.0], [-3.0, 2.0], [12.0, -2.0]])
    start, goal = np.array([0.0, 0.0]), np.array([10.0, 0.0])
    straight = np.array([start, goal])
    assert sides(straight, marks, start, goal).tolist() == [1, -1, 1, -1]
    detour = np.array([start, [5.0, 3.0], goal])  # passes above the first mark
    assert sides(detour, marks, start, goal).tolist() == [-1, -1, 1, -1]


def test_the_free_space_alone_gives_the_classes():
    """A grid drawn by hand: a pillar between start and goal in a walled room."""
    free = np.ones((30, 60), bool)
    free[0], free[-1], free[:, 0], free[:, -1] = False, False, False, False
    free[12:18, 28:32] = False
    found = topology(free, cells=((15, 3), (15, 56)), ends=((3.5, 15.5), (56.5, 15.5)), cell=1.0, radius=0.0)
    assert found.signature == "2:L,R"
