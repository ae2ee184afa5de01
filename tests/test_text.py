"""Text from users' files made safe to print: escaped control characters, cut long tokens."""

from __future__ import annotations

import pytest

from mazegen.errors import MazeError
from mazegen.text import printable, quoted


@pytest.mark.parametrize(
    ("text", "shown"),
    [
        ("plain text, ünïcode", "plain text, ünïcode"),
        ("a\nb\r\tc", "a\\nb\\r\\tc"),
        ("\x1b]0;TITLE\x07", "\\x1b]0;TITLE\\x07"),
        ("nul\x00", "nul\\x00"),
        ("c1\x9b", "c1\\x9b"),
        ("bidi\u202eevil", "bidi\\u202eevil"),
    ],
)
def test_control_characters_are_escaped(text, shown):
    assert printable(text) == shown


def test_a_long_text_is_cut_with_an_ellipsis_without_splitting_an_escape():
    assert printable("x" * 100, limit=40) == "x" * 40 + "..."
    assert printable("x" * 39 + "\n", limit=40) == "x" * 39 + "..."
    assert printable("x" * 40, limit=40) == "x" * 40
    assert quoted("y" * 1000) == "'" + "y" * 40 + "...'"


def test_a_maze_error_stays_one_short_line():
    error = MazeError("bad \x1b]0;TITLE\x07 text\n" + "z" * 100_000, filename="we\x01ird.maze", line=1, col=2)
    shown = str(error)
    assert shown.startswith("we\\x01ird.maze:1:2: bad \\x1b]0;TITLE\\x07 text\\n")
    assert "\n" not in shown and "\x1b" not in shown
    assert len(shown) < 600
