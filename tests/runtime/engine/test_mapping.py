"""Tests of the genotype to phenotype mapping: reference mapper and numba kernel."""

from __future__ import annotations

import itertools
from collections import deque
from pathlib import Path

import numpy as np
import pytest

from mazegen.runtime.engine._bnf import Grammar, Symbol, parse_bnf, read_bnf
from mazegen.runtime.engine._compiled_grammar import compile_grammar
from mazegen.runtime.engine._mapping import (
    ALONE,
    MapResult,
    extract_elements,
    map_genome,
    map_population,
    phenotype,
)

GRAMMARS = Path(__file__).parent / "grammars"
PAPER = read_bnf(GRAMMARS / "paper.bnf")
PAPER_ELEMENTS = ("angle", "square", "eshape", "lshape")
# name -> (grammar, element names)
CASES = {
    "paper": (PAPER, PAPER_ELEMENTS),
    "placed": (read_bnf(GRAMMARS / "placed.bnf"), ("cobot", "wall", "box2", "angle")),
    "tricky": (read_bnf(GRAMMARS / "tricky.bnf"), ("cobot", "wall", "cobot2", "x1", "b")),
    "deep": (read_bnf(GRAMMARS / "deep.bnf"), ("x",)),
    "rows": (read_bnf(GRAMMARS / "rows.bnf"), ("box", "slab")),
}
ROWS = {"rows": (("line", 1, 2, 4), ("pair", 0, 2, 2))}
"""The rows of a case's grammar (RowToken: name, members' element id, fewest, most)."""
TWO_T = parse_bnf("<e> ::= <t><t>\n<t> ::= x | y")


def ponyge2(grammar: Grammar, genome: list[int], max_tree_depth: int = 90) -> tuple[str | None, int]:
    """PonyGE2's ``map_ind_from_genome`` loop with ``MAX_WRAPS=0``, written from its description."""
    n = len(genome)
    used, max_depth, wraps, max_wraps = 0, 1, -1, 0
    output: list[str] = []
    stack = deque([(Symbol(grammar.start, True), 1)])
    while wraps < max_wraps and stack and max_depth <= max_tree_depth:
        if used % n == 0 and used > 0 and any(s.nonterminal for s, _ in stack):
            wraps += 1
        symbol, depth = stack.popleft()
        max_depth = max(max_depth, depth)
        if symbol.nonterminal:
            choices = grammar.rules[symbol.text]
            chosen = choices[genome[used % n] % len(choices)]
            used += 1
            stack.extendleft((s, depth + 1) for s in reversed(chosen))
        else:
            output.append(symbol.text)
    return (None if stack else "".join(output)), used


def textbook(
    grammar: Grammar, genome: list[int], consume: str, wraps: int, max_depth: int
) -> tuple[str | None, int]:
    """The usual mapping, rewriting a sentential form left to right (PonyGE2's depth rule)."""
    form, i, used, deepest = [Symbol(grammar.start, True)], 0, 0, 1
    depths = [1]
    while i < len(form) and deepest <= max_depth:
        deepest = max(deepest, depths[i])
        if not form[i].nonterminal:
            i += 1
            continue
        choices = grammar.rules[form[i].text]
        if consume == "lazy" and len(choices) == 1:
            chosen = choices[0]
        elif used == len(genome) * (wraps + 1):
            break
        else:
            chosen = choices[genome[used % len(genome)] % len(choices)]
            used += 1
        form[i : i + 1] = chosen
        depths[i : i + 1] = [depths[i] + 1] * len(chosen)
    return (None if i < len(form) else "".join(s.text for s in form)), used


def test_paper_example() -> None:
    genome = [34, 10, 200, 80, 5, 70, 45, 43]
    assert map_genome(PAPER, genome) == MapResult("eshape(angle)", True, 3)
    result = map_population(compile_grammar(PAPER, PAPER_ELEMENTS), np.array([genome]), max_elements=8)
    assert (result.valid[0], result.used_codons[0], result.n_elements[0]) == (True, 3, 2)
    assert list(result.element_ids[0, :3]) == [2, 0, -1]
    assert np.isnan(result.numbers[0]).all()


@pytest.mark.parametrize(
    ("genome", "options", "expected"),
    [
        # Two codons run out before the second <t>: PonyGE2 counts a wrap, pops "y" and stops.
        ([0, 1], {}, MapResult(None, False, 2)),
        # The genome runs out right before a non-terminal: it still reads codon 0 (n + 1 codons).
        ([5], {}, MapResult(None, False, 2)),
        ([0, 1, 0], {}, MapResult("yx", True, 3)),
        # With one wrap the genome is read again from the start.
        ([0, 1], {"wraps": 1}, MapResult("yx", True, 3)),
        ([5], {"wraps": 1}, MapResult(None, False, 2)),
        ([5], {"wraps": 2}, MapResult("yy", True, 3)),
    ],
)
def test_ponyge2_wrap_quirk(genome: list[int], options: dict, expected: MapResult) -> None:
    assert map_genome(TWO_T, genome, **options) == expected


def test_exhausted_genome_with_only_terminals_left_is_valid() -> None:
    assert map_genome(parse_bnf("<e> ::= <t>z\n<t> ::= x | y"), [0, 1]) == MapResult("yz", True, 2)


def test_empty_genome_is_invalid() -> None:
    assert map_genome(TWO_T, []) == MapResult(None, False, 0)
    assert map_genome(TWO_T, [], consume="lazy", wraps=3) == MapResult(None, False, 0)
    assert map_genome(parse_bnf("<e> ::= z"), [], consume="lazy") == MapResult("z", True, 0)


def test_lazy_unit_rules_consume_no_codon() -> None:
    grammar = parse_bnf("<s> ::= [<xs>]\n<xs> ::= <x> | <x>,<xs>\n<x> ::= a | b")
    assert map_genome(grammar, [1, 0, 0, 1]) == MapResult("[a]", True, 3)
    assert map_genome(grammar, [1, 0, 0, 1], consume="lazy") == MapResult("[a,b]", True, 4)
    assert map_genome(grammar, [1, 0], consume="lazy") == MapResult(None, False, 2)


@pytest.mark.parametrize(
    ("consume", "wraps", "expected"),
    [
        ("eager", 0, MapResult(None, False, 2)),
        ("eager", 2, MapResult(None, False, 3)),
        ("eager", 3, MapResult("yyy", True, 4)),
        ("lazy", 0, MapResult(None, False, 1)),
        ("lazy", 1, MapResult(None, False, 2)),
        ("lazy", 2, MapResult("yyy", True, 3)),
    ],
)
def test_wraps(consume: str, wraps: int, expected: MapResult) -> None:
    grammar = parse_bnf("<e> ::= <t><t><t>\n<t> ::= x | y")
    assert map_genome(grammar, [1], consume=consume, wraps=wraps) == expected


def test_codons_run_out() -> None:
    assert map_genome(PAPER, [4, 4]) == MapResult(None, False, 2)
    assert map_genome(PAPER, [4, 4], wraps=1) == MapResult(None, False, 4)
    assert map_genome(PAPER, [4, 4, 1], wraps=1) == MapResult("angle(square)", True, 3)


@pytest.mark.parametrize("options", [{}, {"wraps": 1}, {"consume": "lazy"}])
def test_depth_limit(options: dict) -> None:
    right = parse_bnf("<e> ::= a<e> | b")
    # PonyGE2 processes the symbol that breaks the limit, then stops: a last terminal may pass.
    assert map_genome(right, [0, 1], max_depth=2, **options) == MapResult("ab", True, 2)
    assert map_genome(right, [0, 0, 1], max_depth=2, **options) == MapResult(None, False, 2)
    assert map_genome(right, [0, 0, 1], max_depth=3, **options) == MapResult("aab", True, 3)
    left = parse_bnf("<e> ::= <e>a | b")
    assert map_genome(left, [0, 1], max_depth=2, **options) == MapResult(None, False, 2)
    assert map_genome(left, [0, 1], max_depth=3, **options) == MapResult("ba", True, 2)


def test_lazy_unit_cycle_stops_at_the_depth_limit() -> None:
    grammar = parse_bnf("<s> ::= <loop> | z\n<loop> ::= <loop>")
    assert map_genome(grammar, [0], consume="lazy") == MapResult(None, False, 1)
    result = map_population(
        compile_grammar(grammar, ()), np.array([[0], [1]]), consume="lazy", max_elements=1
    )
    assert list(result.valid) == [False, True]
    assert list(result.used_codons) == [1, 1]


def test_phenotype() -> None:
    assert phenotype(PAPER, [34, 10, 200]) == "eshape(angle)"
    assert phenotype(PAPER, [4, 4]) is None
    assert phenotype(PAPER, [4, 4, 1], wraps=1) == "angle(square)"


@pytest.mark.parametrize("name", sorted(CASES))
@pytest.mark.parametrize("max_depth", [90, 4])
def test_default_mode_equals_ponyge2(name: str, max_depth: int) -> None:
    grammar = CASES[name][0]
    rng = np.random.default_rng(7)
    for _ in range(1500):
        genome = [int(c) for c in rng.integers(0, 256, rng.integers(1, 12))]
        result = map_genome(grammar, genome, max_depth=max_depth)
        assert (result.phenotype, result.used_codons) == ponyge2(grammar, genome, max_depth), genome


@pytest.mark.parametrize("name", sorted(CASES))
@pytest.mark.parametrize(("consume", "wraps"), [("eager", 1), ("eager", 3), ("lazy", 0), ("lazy", 2)])
def test_other_modes_equal_textbook(name: str, consume: str, wraps: int) -> None:
    grammar = CASES[name][0]
    rng = np.random.default_rng(8)
    for _ in range(1000):
        genome = [int(c) for c in rng.integers(0, 256, rng.integers(1, 12))]
        max_depth = int(rng.choice([4, 90]))
        result = map_genome(grammar, genome, consume=consume, wraps=wraps, max_depth=max_depth)
        assert (result.phenotype, result.used_codons) == textbook(grammar, genome, consume, wraps, max_depth)


def test_extract_elements() -> None:
    text = "3 cobot(1, -2.5, 3, 4, 5) wall 7 x1 ; 8 walls wall(-0.25) cobot2 4. 1.2.3 --6"
    assert extract_elements(text, ("cobot", "wall")) == [
        (0, (1.0, -2.5, 3.0, 4.0), ALONE),
        (1, (7.0, 8.0), ALONE),
        (1, (-0.25, 4.0, 1.2, 3.0), ALONE),
    ]


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("box line(3) 5 box", [(0, ()), (1, (), 0, 0, 3), (1, (), 0, 1, 3), (1, (5.0,), 0, 2, 3), (0, ())]),
        ("pair(2),line 2.0", [(0, (), 1, 0, 2), (0, (), 1, 1, 2), (1, (), 0, 0, 2), (1, (), 0, 1, 2)]),
        ("lines 3 box", [(0, ())]),  # not a row's name: its number goes to no element
        ("line", None),  # no count
        ("line box 3", None),  # a name before the count
        ("line(5)", None),  # more than the most
        ("line(1)", None),  # fewer than the fewest
        ("line(2.5)", None),  # not whole
        ("line(-3)", None),
    ],
)
def test_extract_rows(text: str, expected: list | None) -> None:
    found = extract_elements(text, ("box", "slab"), ROWS["rows"])
    if expected is None:
        assert found is None
        return
    assert found == [(e, numbers, tuple(membership) or ALONE) for e, numbers, *membership in expected]


@pytest.mark.parametrize(
    ("text", "elements", "max_elements", "expected"),
    [
        (
            "3 cobot(1, -2.5, 3, 4, 5) wall 7 x1 ; 8 wall(-0.25) w 2",
            ("cobot", "wall"),
            3,
            [(0, (1.0, -2.5, 3.0, 4.0)), (1, (7.0, 8.0)), (1, (-0.25, 2.0))],
        ),
        ("co<t>\n<t> ::= bot 1<n>\n<n> ::= 2.5 | 9", ("cobot",), 1, [(0, (12.5,))]),
        ("wall wall wall", ("wall",), 3, [(0, ()), (0, ()), (0, ())]),
        ("wall wall wall", ("wall",), 2, None),
        ("<e>\n<e> ::= <e>", ("wall",), 2, None),
    ],
)
def test_kernel_elements(
    text: str, elements: tuple[str, ...], max_elements: int, expected: list | None
) -> None:
    grammar = parse_bnf("<s> ::= " + text)
    result = map_population(
        compile_grammar(grammar, elements), np.zeros((2, 3), np.int64), max_elements=max_elements
    )
    assert list(result.used_codons) == [map_genome(grammar, [0, 0, 0]).used_codons] * 2
    if expected is None:
        assert not result.valid.any()
        assert not result.n_elements.any()
        assert (result.element_ids == -1).all() and np.isnan(result.numbers).all()
        return
    assert result.valid.all()
    assert list(result.n_elements) == [len(expected)] * 2
    for e, (element, numbers) in enumerate(expected):
        assert result.element_ids[1, e] == element
        assert list(result.numbers[1, e, : len(numbers)]) == list(numbers)
        assert np.isnan(result.numbers[1, e, len(numbers) :]).all()
    assert (result.element_ids[:, len(expected) :] == -1).all()


def _check_kernel(
    grammar: Grammar,
    elements: tuple[str, ...],
    codons: np.ndarray,
    max_elements: int = 4,
    rows: tuple = (),
    **options: object,
) -> None:
    """Assert the kernel agrees with the reference mapper and tokeniser on every row."""
    compiled = compile_grammar(grammar, elements, rows)
    result = map_population(compiled, codons, max_elements=max_elements, **options)
    assert result.membership.shape == (codons.shape[0], max_elements if rows else 0, 3)
    for i, genome in enumerate(codons.tolist()):
        reference = map_genome(grammar, genome, **options)  # type: ignore[arg-type]
        found = extract_elements(reference.phenotype, elements, rows) if reference.valid else []
        valid = reference.valid and found is not None and len(found) <= max_elements
        assert (result.valid[i], result.used_codons[i]) == (valid, reference.used_codons), (genome, options)
        found = found if valid else []
        assert result.n_elements[i] == len(found)
        ids = [element for element, _, _ in found] + [-1] * (max_elements - len(found))
        assert list(result.element_ids[i]) == ids, (genome, options, reference.phenotype)
        numbers = np.full((max_elements, 4), np.nan)
        for e, (_, values, _) in enumerate(found):
            numbers[e, : len(values)] = values
        assert np.array_equal(result.numbers[i], numbers, equal_nan=True), (genome, reference.phenotype)
        if rows:
            membership = [m for _, _, m in found] + [ALONE] * (max_elements - len(found))
            assert [tuple(m) for m in result.membership[i].tolist()] == membership, reference.phenotype
    without = map_population(compiled, codons, max_elements=max_elements, numbers=False, **options)
    assert without.numbers.shape == (codons.shape[0], 0, 4)
    for name in ("valid", "used_codons", "n_elements", "element_ids", "membership"):
        assert np.array_equal(getattr(without, name), getattr(result, name)), name


@pytest.mark.parametrize("name", sorted(CASES))
@pytest.mark.parametrize(("consume", "wraps"), list(itertools.product(["eager", "lazy"], [0, 1, 2])))
def test_kernel_equals_reference(name: str, consume: str, wraps: int) -> None:
    grammar, elements = CASES[name]
    rng = np.random.default_rng([len(name), wraps, consume == "lazy"])
    for length, max_depth, max_elements in [(1, 90, 3), (3, 90, 4), (8, 5, 2), (16, 90, 4), (32, 8, 2)]:
        codons = rng.integers(0, 256, (300, length))
        _check_kernel(
            grammar,
            elements,
            codons,
            max_elements,
            ROWS.get(name, ()),
            consume=consume,
            wraps=wraps,
            max_depth=max_depth,
        )


@pytest.mark.parametrize("dtype", [np.uint8, np.int16, np.int32, np.uint32, np.int64])
def test_kernel_codon_dtypes(dtype: type) -> None:
    codons = np.random.default_rng(3).integers(0, 200, (400, 10)).astype(dtype)
    _check_kernel(CASES["placed"][0], CASES["placed"][1], codons)


def test_codons_beyond_64_bit_signed_integers_are_refused() -> None:
    compiled = compile_grammar(*CASES["placed"])
    with pytest.raises(ValueError, match="64-bit signed"):
        map_population(compiled, np.array([[2**64 - 1]], np.uint64), max_elements=3)


def test_kernel_negative_codons_and_empty_genomes() -> None:
    grammar, elements = CASES["tricky"]
    _check_kernel(grammar, elements, np.random.default_rng(5).integers(-300, 300, (500, 9)))
    _check_kernel(grammar, elements, np.zeros((3, 0), np.int64), consume="lazy", wraps=1)
    assert map_population(
        compile_grammar(grammar, elements), np.zeros((0, 5), np.int64), max_elements=2
    ).valid.shape == (0,)


def test_kernel_reuses_out_arrays() -> None:
    grammar, elements = CASES["placed"]
    compiled = compile_grammar(grammar, elements)
    rng = np.random.default_rng(11)
    first, second = rng.integers(0, 256, (2, 500, 24))
    out = map_population(compiled, first, max_elements=3)
    again = map_population(compiled, second, max_elements=3, out=out)
    fresh = map_population(compiled, second, max_elements=3)
    assert again is out
    for name in ("valid", "used_codons", "n_elements", "element_ids", "numbers"):
        assert np.array_equal(getattr(again, name), getattr(fresh, name), equal_nan=True), name
    with pytest.raises(ValueError, match="out does not fit"):
        map_population(compiled, second, max_elements=4, out=out)


NO_ELEMENTS = compile_grammar(PAPER, ())


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: map_genome(PAPER, [1], consume="greedy"), "consume must be"),
        (lambda: map_genome(PAPER, [1], wraps=-1), "wraps must be"),
        (lambda: map_genome(PAPER, [1], max_depth=0), "max_depth >= 1"),
        (lambda: map_population(NO_ELEMENTS, np.zeros(3, np.int64), max_elements=1), "2-D integer"),
        (lambda: map_population(NO_ELEMENTS, np.zeros((3, 2)), max_elements=1), "2-D integer"),
        (lambda: map_population(NO_ELEMENTS, np.zeros((3, 2), int), max_elements=-1), "max_elements"),
    ],
)
def test_bad_arguments(call, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        call()


def test_a_rows_members_take_a_slot_each_and_the_codons_of_its_count() -> None:
    grammar = parse_bnf("<s> ::= <e> | <e> <s>\n<e> ::= box | line(<n>)\n<n> ::= 2 | 3")
    compiled = compile_grammar(grammar, ("box", "slab"), (("line", 1, 2, 3),))
    genome = np.array([[1, 1, 1, 0, 0]])  # <e> <s>, line(<n>), 3, <e>, box
    result = map_population(compiled, genome, max_elements=4)
    assert map_genome(grammar, genome[0].tolist()).phenotype == "line(3) box"
    assert result.valid[0] and result.n_elements[0] == 4
    assert list(result.element_ids[0]) == [1, 1, 1, 0]
    assert list(result.element_codons[0]) == [3, 3, 3, 5]  # crossover keeps a row whole
    assert result.membership[0].tolist() == [[0, 0, 3], [0, 1, 3], [0, 2, 3], list(ALONE)]
    assert not map_population(compiled, genome, max_elements=3).valid[0]  # max elements counts members
