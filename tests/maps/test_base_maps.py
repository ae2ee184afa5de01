"""A map as an arena's base: map_server's semantics read into the spec, packed and unpacked, laid on a
navigation grid of another cell size."""

from __future__ import annotations

import numpy as np
import pytest

from mazegen.dsl.loader import load_spec
from mazegen.maps import base_cells, base_map_of, base_on_grid, read_base_map
from mazegen.spec import Spec
from tests.map_files import FREE, OCCUPIED, UNKNOWN, hall_pixels, hall_spec, write_map


def test_unknown_cells_are_blocked_unless_the_spec_frees_them(tmp_path):
    pixels = np.full((4, 6), FREE)
    pixels[0, :2] = OCCUPIED  # top row, image order
    pixels[3, 4:] = UNKNOWN
    yaml = write_map(tmp_path, pixels)
    blocked = base_cells(read_base_map(yaml, source="hall.yaml", units_per_metre=1.0))
    freed = base_cells(read_base_map(yaml, source="hall.yaml", units_per_metre=1.0, unknown="free"))
    expected = np.zeros((4, 6), bool)
    expected[3, :2] = True  # row 0 is the lowest: the image's top row is row 3
    assert (freed == expected).all()
    expected[0, 4:] = True
    assert (blocked == expected).all()


def test_negate_and_origin_follow_map_server(tmp_path):
    pixels = np.full((3, 5), 255 - FREE)  # negated: dark is free
    pixels[1, 2] = 255 - OCCUPIED
    yaml = write_map(tmp_path, pixels, negate=1, origin=(-1.5, 2.25), resolution=0.05)
    base = read_base_map(yaml, source="hall.yaml", units_per_metre=100.0)
    assert base.origin == (-1.5, 2.25)
    assert base.resolution == pytest.approx(5.0)  # cm per cell
    assert np.argwhere(base_cells(base)).tolist() == [[1, 2]]


def test_packed_cells_come_back_and_the_spec_round_trips(tmp_path):
    write_map(tmp_path, hall_pixels())
    (tmp_path / "spec.maze").write_text(hall_spec())
    spec = load_spec(tmp_path / "spec.maze")
    base = spec.arena.base
    assert base is not None and (base.rows, base.cols) == (30, 40)
    assert (base_cells(base) == (hall_pixels()[::-1] == OCCUPIED)).all()
    assert (spec.arena.width, spec.arena.height, spec.arena.unit) == (400.0, 300.0, "cm")
    assert Spec.from_json(spec.to_json()) == spec
    odd = np.random.default_rng(1).random((7, 13)) < 0.3
    assert (
        base_cells(base_map_of(odd, source="x", resolution=1.0, origin=(0, 0), unknown="blocked")) == odd
    ).all()


@pytest.mark.parametrize(("resolution", "cell"), [(1.0, 1.0), (1.0, 2.5), (1.0, 0.4), (0.3, 1.0)])
def test_a_grid_cell_is_blocked_where_a_blocked_cell_overlaps_it(resolution, cell):
    cells = np.random.default_rng(7).random((17, 23)) < 0.15
    base = base_map_of(cells, source="x", resolution=resolution, origin=(0, 0), unknown="blocked")
    rows, cols = int(np.ceil(17 * resolution / cell)), int(np.ceil(23 * resolution / cell))
    got = base_on_grid(base, cell, rows, cols)
    expected = np.zeros((rows, cols), bool)
    for r, c in np.argwhere(cells):  # overlap with area: open intervals meet
        y0, y1, x0, x1 = r * resolution, (r + 1) * resolution, c * resolution, (c + 1) * resolution
        for gr in range(rows):
            for gc in range(cols):
                if (
                    y0 < (gr + 1) * cell - 1e-9
                    and y1 > gr * cell + 1e-9
                    and x0 < (gc + 1) * cell - 1e-9
                    and x1 > gc * cell + 1e-9
                ):
                    expected[gr, gc] = True
    assert (got == expected).all()


def test_the_example_hall_is_what_its_script_makes(tmp_path):
    """examples/maps/hall.pgm and hall.yaml are the output of make_hall.py, byte for byte."""
    import runpy

    from tests.conftest import EXAMPLES

    make_hall = runpy.run_path(str(EXAMPLES / "maps" / "make_hall.py"))
    make_hall["write"](tmp_path)
    for name in ("hall.pgm", "hall.yaml"):
        assert (tmp_path / name).read_bytes() == (EXAMPLES / "maps" / name).read_bytes(), name
