"""Tests of the PonyGE2-dialect BNF reader."""

from __future__ import annotations

from pathlib import Path

import pytest

from mazegen.errors import MazeError
from mazegen.runtime.engine._bnf import Grammar, Symbol, parse_bnf, read_bnf

GRAMMARS = Path(__file__).parent / "grammars"


def T(text: str) -> Symbol:
    return Symbol(text, False)


def N(name: str) -> Symbol:
    return Symbol(name, True)


def alternatives(text: str, rule: str | None = None) -> tuple[tuple[Symbol, ...], ...]:
    grammar = parse_bnf(text)
    return grammar.rules[rule or grammar.start]


def test_paper_grammar() -> None:
    grammar = read_bnf(GRAMMARS / "paper.bnf")
    assert isinstance(grammar, Grammar)
    assert grammar.start == "<scenario>"
    assert list(grammar.rules) == ["<scenario>", "<composedFigures>"]
    assert grammar.rules["<scenario>"] == (
        (T("angle"),),
        (T("square"),),
        (T("eshape"),),
        (T("lshape"),),
        (N("<composedFigures>"),),
    )
    assert grammar.rules["<composedFigures>"][2] == (T("eshape("), N("<scenario>"), T(")"))


def test_rules_keep_file_order_and_first_is_start() -> None:
    grammar = parse_bnf("<b> ::= <a> | <c>\n<c> ::= z\n<a> ::= y\n")
    assert grammar.start == "<b>"
    assert list(grammar.rules) == ["<b>", "<c>", "<a>"]


def test_multi_line_rule() -> None:
    text = "<a> ::= x\n      | y\n\n      | z |\n<b> ::= w"
    assert alternatives(text) == ((T("x"),), (T("y"),), (T("z"),))
    assert alternatives("<a>\n  ::=\n  x |\n  y") == ((T("x"),), (T("y"),))


def test_alternative_spanning_lines_keeps_the_line_break() -> None:
    assert alternatives("<a> ::= x  \n   y | <a>  \n  z") == ((T("x  \ny"),), (N("<a>"), T("\nz")))


def test_comments() -> None:
    text = "# heading <x> ::= not a rule\n<a> ::= x # first | not an alternative\n | y#second\n# <b> ::= q\n"
    assert parse_bnf(text).rules == {"<a>": ((T("x"),), (T("y"),))}


def test_comment_ends_an_alternative_like_a_bar() -> None:
    assert alternatives("<a> ::= x # note\n  y") == ((T("x"),), (T("y"),))


def test_unquoted_text_is_literal_and_stripped() -> None:
    assert alternatives("<a> ::=   move( <b> ,  2 )  \n<b> ::= q") == ((T("move( "), N("<b>"), T(" ,  2 )")),)


def test_quoted_terminals_protect_bar_hash_and_angles() -> None:
    text = """<a> ::= 'x|y' | "#1" | '<a>' | "it's" | 'say "hi"'"""
    assert alternatives(text) == ((T("x|y"),), (T("#1"),), (T("<a>"),), (T("it's"),), (T('say "hi"'),))


def test_adjacent_terminal_pieces_merge() -> None:
    assert alternatives("<a> ::= ab 'c d' \"e\"f<a>g 'h'") == ((T("ab c d ef"), N("<a>"), T("g h")),)


def test_escapes_are_decoded() -> None:
    assert alternatives(r"""<a> ::= 'a\nb' | "\t" | x\u00e9 | '\\' | \d""") == (
        (T("a\nb"),),
        (T("\t"),),
        (T("xé"),),
        (T("\\"),),
        (T("\\d"),),
    )


def test_non_ascii_text_is_kept() -> None:
    assert alternatives("<a> ::= café | 'naïve\\n'") == ((T("café"),), (T("naïve\n"),))


def test_blank_alternatives_are_skipped_and_empty_quotes_are_terminals() -> None:
    assert alternatives("<a> ::= | x | |  | y |") == ((T("x"),), (T("y"),))
    assert alternatives("<a> ::= '' | x''") == ((T(""),), (T("x"),))


def test_lone_angle_brackets_are_text() -> None:
    assert alternatives("<a> ::= x < y | << | a<=b | <") == (
        (T("x < y"),),
        (T("<<"),),
        (T("a<=b"),),
        (T("<"),),
    )


def test_crlf_line_endings() -> None:
    assert parse_bnf("<a> ::= x\r\n | <b>\r\n<b> ::= y\r\n").rules == {
        "<a>": ((T("x"),), (N("<b>"),)),
        "<b>": ((T("y"),),),
    }


ERRORS = [
    ("", "g.bnf:1:1: no rules found (expected '<name> ::= ...')"),
    ("# only a comment\n\n", "g.bnf:1:1: no rules found (expected '<name> ::= ...')"),
    ("<a> ::= x | <b>", "g.bnf:1:13: non-terminal <b> is used but never defined"),
    ("<a> ::= x\n<b> ::= y\n  | z(<c>)", "g.bnf:3:7: non-terminal <c> is used but never defined"),
    ("<a> ::= x\n<b> ::= y\n<a> ::= z", "g.bnf:3:1: rule <a> is defined twice (first at line 1)"),
    ("<a> ::= x\n  | 'y\n<b> ::= z", "g.bnf:2:5: unbalanced quote: ' is not closed on this line"),
    ('<a> ::= "x" | "y', 'g.bnf:1:15: unbalanced quote: " is not closed on this line'),
    ("<a> ::= x\n<b> ::= | # nothing\n", "g.bnf:2:1: rule <b> has no alternatives"),
    ("<a> ::=", "g.bnf:1:1: rule <a> has no alternatives"),
    ("hello\n<a> ::= x", "g.bnf:1:1: expected a rule '<name> ::=' before this text"),
    ("<a> ::= 'x\\", "g.bnf:1:9: unbalanced quote: ' is not closed on this line"),
    ("<a> ::= x\\", "g.bnf:1:9: bad escape in terminal 'x\\\\': \\ at end of string"),
    ("<a> ::= ok | '\\x4'", "g.bnf:1:14: bad escape in terminal '\\\\x4': truncated \\xXX escape"),
]


@pytest.mark.parametrize(("text", "message"), ERRORS)
def test_errors(text: str, message: str) -> None:
    with pytest.raises(MazeError) as caught:
        parse_bnf(text, filename="g.bnf")
    assert str(caught.value) == message


def test_read_bnf_names_the_file_in_errors(tmp_path: Path) -> None:
    path = tmp_path / "bad.bnf"
    path.write_text("<a> ::= <missing>\n", encoding="utf-8")
    with pytest.raises(MazeError) as caught:
        read_bnf(path)
    assert (caught.value.filename, caught.value.line, caught.value.col) == (str(path), 1, 9)
