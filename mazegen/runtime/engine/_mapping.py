"""Genotype to phenotype mapping for grammatical evolution.

A genome is a sequence of integer codons. Mapping is a leftmost (depth-first)
derivation from the start rule: the leftmost non-terminal is expanded with the
alternative ``codon % number_of_alternatives`` read from the next codon. Every
symbol has a depth (the start symbol 1, children one more than their parent).

Two rule sets, chosen by the options:

* ``consume="eager", wraps=0`` (the default) is exactly PonyGE2's
  ``map_ind_from_genome`` with ``MAX_WRAPS=0`` and ``MAX_TREE_DEPTH=max_depth``,
  quirks included. One-alternative rules consume a codon. A wrap is counted
  when all ``n`` codons are used while a non-terminal is still on the stack,
  and the loop ends only after the item popped then is processed: if it is a
  non-terminal it still reads codon 0, so ``used_codons`` is ``n + 1``. Such an
  individual is invalid all the same; with only terminals left, an exhausted
  genome is valid. (An empty genome is invalid; PonyGE2 would fail on it.)
* Any other combination is the usual definition: ``consume="lazy"`` lets rules
  with one alternative consume no codon (alogos' convention); codon ``i`` reads
  ``genome[i % n]`` and mapping is invalid once more than ``n * (wraps + 1)``
  codons would be needed.

Both apply PonyGE2's depth limit: a popped symbol deeper than ``max_depth`` is
still processed, then mapping stops, and it is valid only if nothing is left
(so a final terminal at depth ``max_depth + 1`` passes).

:func:`map_genome` is the readable reference; :func:`map_population` maps a whole
population with a numba kernel that gives the same results and extracts the
scenario elements (see :func:`extract_elements`) on the fly, a row's name and the
number after it becoming that many members of the row's element type.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numba import njit

from mazegen.runtime.engine._bnf import Grammar, Symbol
from mazegen.runtime.engine._compiled_grammar import (
    CHOICE_CODONS,
    CLASSES,
    DIGIT,
    DOT,
    FRACTION,
    IDLE,
    INT,
    LETTER,
    MINUS,
    NAME,
    POINT,
    SIGN,
    CompiledGrammar,
    RowToken,
)
from mazegen.runtime.threads import in_blocks

NUMBERS_PER_ELEMENT = 4
NO_ELEMENT = np.iinfo(np.int32).max
"""``element_codons`` of a slot without an element: beyond every cut."""
ALONE = (-1, 0, 1)
"""``membership`` of an element placed alone (and of a slot without an element): a row of one."""
NO_ROW, BROKEN = -1, -2
"""While mapping: no row awaits its member count; a row's name was not followed by a count within its
bounds (the individual is invalid). A row awaiting its count is its index, from 0."""
_TOKEN = re.compile(r"(?P<name>[A-Za-z_][A-Za-z0-9_]*)|(?P<number>-?[0-9]+(?:\.[0-9]+)?)")


@dataclass(frozen=True)
class MapResult:
    """The outcome of mapping one genome.

    Attributes:
        phenotype: The derived string, or ``None`` when invalid.
        valid: True when the derivation completed.
        used_codons: Codons read (counting re-reads after wrapping).
    """

    phenotype: str | None
    valid: bool
    used_codons: int


@dataclass(frozen=True)
class PopulationMap:
    """What :func:`map_population` extracts from N genomes.

    Attributes:
        valid: ``bool[N]``; derivation completed with at most ``max_elements``.
        used_codons: ``int32[N]``, as :attr:`MapResult.used_codons`.
        n_elements: ``int32[N]``; 0 for invalid individuals.
        element_ids: ``int32[N, max_elements]``, indices into the element
            names, -1 padded.
        numbers: ``float64[N, max_elements, 4]``: the numbers that follow each
            element in the phenotype (the first four), NaN padded; ``[N, 0, 4]``
            when the numbers were not asked for.
        element_codons: ``int32[N, max_elements]``: codons read when each element's
            name was completed (a row's members: its count), :data:`NO_ELEMENT` padded (all of
            an invalid individual's slots): the genome prefix an element comes from, which
            crossover keeps whole.
        membership: ``int32[N, max_elements, 3]``: the row each element is a member of (an index
            of the grammar's rows), its place in the row and the row's member count, or
            :data:`ALONE`; ``[N, 0, 3]`` for a grammar without rows.
    """

    valid: np.ndarray
    used_codons: np.ndarray
    n_elements: np.ndarray
    element_ids: np.ndarray
    numbers: np.ndarray
    element_codons: np.ndarray
    membership: np.ndarray


def _check_options(wraps: int, consume: str, max_depth: int) -> None:
    if consume not in ("eager", "lazy"):
        raise ValueError(f"consume must be 'eager' or 'lazy', not {consume!r}")
    if wraps < 0 or max_depth < 1:
        raise ValueError("wraps must be >= 0 and max_depth >= 1")


def _codon_limit(n: int, wraps: int, consume: str) -> int:
    """Codons that may be read: PonyGE2 reads one past the end (see module doc)."""
    if consume == "eager" and wraps == 0:
        return n + 1 if n else 0
    return n * (wraps + 1)


def map_genome(
    grammar: Grammar, genome: Sequence[int], *, wraps: int = 0, consume: str = "eager", max_depth: int = 90
) -> MapResult:
    """Map one genome with the pure-Python reference mapper.

    Args:
        grammar: The grammar.
        genome: Integer codons.
        wraps: Extra passes over the genome allowed (0: PonyGE2-exact when eager).
        consume: ``"eager"`` (every rule reads a codon, PonyGE2) or ``"lazy"``
            (rules with a single alternative read none).
        max_depth: Derivation depth limit (PonyGE2's ``MAX_TREE_DEPTH``).

    Returns:
        The phenotype (``None`` if invalid), validity and codons used.
    """
    _check_options(wraps, consume, max_depth)
    codons = [int(c) for c in genome]
    n = len(codons)
    pony = consume == "eager" and wraps == 0
    limit = _codon_limit(n, wraps, consume)
    stack: list[tuple[Symbol, int]] = [(Symbol(grammar.start, True), 1)]  # leftmost item last
    output: list[str] = []
    used, deepest, pending = 0, 1, 1  # pending: non-terminals on the stack
    while stack and deepest <= max_depth:
        wrapped = pony and used > 0 and used % n == 0 and pending > 0
        symbol, depth = stack.pop()
        deepest = max(deepest, depth)
        if not symbol.nonterminal:
            output.append(symbol.text)
        else:
            pending -= 1
            alternatives = grammar.rules[symbol.text]
            if consume == "lazy" and len(alternatives) == 1:
                chosen = alternatives[0]
            elif used >= limit:
                stack.append((symbol, depth))  # left unexpanded: invalid
                break
            else:
                chosen = alternatives[codons[used % n] % len(alternatives)]
                used += 1
            stack.extend((s, depth + 1) for s in reversed(chosen))
            pending += sum(s.nonterminal for s in chosen)
        if wrapped:
            break
    if stack:
        return MapResult(None, False, used)
    return MapResult("".join(output), True, used)


def phenotype(grammar: Grammar, genome: Sequence[int], **options: object) -> str | None:
    """The phenotype of ``genome`` (``None`` if invalid); options as :func:`map_genome`."""
    return map_genome(grammar, genome, **options).phenotype  # type: ignore[arg-type]


def extract_elements(
    text: str, element_names: Sequence[str], rows: Sequence[RowToken] = ()
) -> list[tuple[int, tuple[float, ...], tuple[int, int, int]]] | None:
    """Tokenise a phenotype into elements and their numbers (reference for the kernel).

    Identifiers ``[A-Za-z_][A-Za-z0-9_]*`` equal to an element name are elements;
    numbers ``-?[0-9]+(.[0-9]+)?`` outside identifiers attach, in order and at
    most four, to the latest element; everything else is ignored. A row's name
    stands for as many members of its element type as the number after it says.

    Args:
        text: A phenotype.
        element_names: The element names; an element's id is its index.
        rows: The rows (:data:`~mazegen.runtime.engine._compiled_grammar.RowToken`).

    Returns:
        ``(element_id, numbers, membership)`` for every element, in order, membership as
        :attr:`PopulationMap.membership`; ``None`` when a row's name is not followed by a
        whole number of members within its bounds before the next name or the end.
    """
    ids = {name: i for i, name in enumerate(element_names)}
    row_ids = {row[0]: r for r, row in enumerate(rows)}
    found: list[tuple[int, list[float], tuple[int, int, int]]] = []
    pending = None
    for token in _TOKEN.finditer(text):
        word = token.group()
        if token.lastgroup == "name" and (word in ids or word in row_ids):
            if pending is not None:
                return None
            if word in row_ids:
                pending = row_ids[word]
            else:
                found.append((ids[word], [], ALONE))
        elif token.lastgroup == "number" and pending is not None:
            _, member, fewest, most = rows[pending]
            count = float(word)
            if not (count.is_integer() and fewest <= count <= most):
                return None
            found += [(member, [], (pending, m, int(count))) for m in range(int(count))]
            pending = None
        elif token.lastgroup == "number" and found and len(found[-1][1]) < NUMBERS_PER_ELEMENT:
            found[-1][1].append(float(word))
    if pending is not None:
        return None
    return [(element, tuple(numbers), membership) for element, numbers, membership in found]


def map_population(
    compiled: CompiledGrammar,
    codons: np.ndarray,
    *,
    wraps: int = 0,
    consume: str = "eager",
    max_elements: int,
    max_depth: int = 90,
    numbers: bool = True,
    out: PopulationMap | None = None,
) -> PopulationMap:
    """Map every row of ``codons`` and extract its elements, in parallel.

    Validity and ``used_codons`` equal :func:`map_genome` with the same options
    (also when the element limit makes an individual invalid, or a row its count);
    the elements, numbers and row membership equal :func:`extract_elements` of the
    reference phenotype, tokens spanning several terminals included (numbers are
    exact up to 15 digits).

    Args:
        compiled: The grammar from :func:`~mazegen.runtime.engine._compiled_grammar.compile_grammar`.
        codons: ``N x L`` integer array, one genome per row.
        wraps: As :func:`map_genome`.
        consume: As :func:`map_genome`.
        max_elements: Element slots; an individual deriving more is invalid.
        max_depth: As :func:`map_genome`.
        numbers: Extract the numbers after each element; without them (grammars that
            carry no placement) ``numbers`` is empty and costs no memory.
        out: Arrays to overwrite instead of allocating new ones (same shapes and
            dtypes as the result), e.g. to spare fresh memory every generation.

    Returns:
        The population's arrays (``out`` if given).
    """
    _check_options(wraps, consume, max_depth)
    codons = np.ascontiguousarray(codons)
    if codons.ndim != 2 or codons.dtype.kind not in "iu" or max_elements < 0:
        raise ValueError("codons must be a 2-D integer array and max_elements >= 0")
    codons = _kernel_codons(codons)
    n = codons.shape[0]
    layout = [
        ((n,), np.bool_),
        ((n,), np.int32),
        ((n,), np.int32),
        ((n, max_elements), np.int32),
        ((n, max_elements if numbers else 0, NUMBERS_PER_ELEMENT), np.float64),
        ((n, max_elements), np.int32),
        ((n, max_elements if compiled.row_member.size else 0, 3), np.int32),
    ]
    result = out or PopulationMap(*(np.empty(shape, dtype) for shape, dtype in layout))
    arrays = (
        result.valid,
        result.used_codons,
        result.n_elements,
        result.element_ids,
        result.numbers,
        result.element_codons,
        result.membership,
    )
    if any(
        a.shape != shape or a.dtype != dtype or not a.flags.c_contiguous
        for a, (shape, dtype) in zip(arrays, layout)
    ):
        raise ValueError("out does not fit this population and max_elements")
    c = compiled
    grammar = (
        c.start,
        c.rule_alts,
        c.alt_symbols,
        c.alt_nonterminals,
        c.symbols,
        c.choice,
        c.term_chars,
        c.chars,
        c.trie,
        c.trie_element,
        CLASSES,
        c.term_fast,
        c.term_emits,
        c.emits,
        c.term_end_mode,
        c.term_end_node,
        (len(c.element_names), c.row_member, c.row_count),
    )
    options = (
        (max_depth + 3) * c.max_alt_len + 1,
        consume == "lazy",
        consume == "eager" and wraps == 0,
        _codon_limit(codons.shape[1], wraps, consume),
        max_depth,
    )
    in_blocks(_map_all, n, codons, grammar, options, arrays)
    return result


def _kernel_codons(codons: np.ndarray) -> np.ndarray:
    """``codons`` as the kernel takes them: the engine's ``int32`` as they are, any other integers as
    ``int64``, so that the kernel compiles for two types, not one per type a caller has.

    Raises:
        ValueError: For unsigned codons beyond ``int64``.
    """
    if codons.dtype == np.int32 or codons.dtype == np.int64:
        return codons
    if codons.dtype == np.uint64 and codons.size and codons.max() > np.iinfo(np.int64).max:
        raise ValueError("codons must fit in a 64-bit signed integer")
    return codons.astype(np.int64)


@njit(cache=True, nogil=True)
def _map_all(first, last, codons, grammar, options, out):  # pragma: no cover - compiled
    """Map genomes ``first`` to ``last - 1`` with one preallocated stack."""
    capacity = options[0]
    valid, used, n_elements = out[0], out[1], out[2]
    stack, depths = np.empty(capacity, np.int32), np.empty(capacity, np.int32)
    for i in range(first, last):
        valid[i], used[i], n_elements[i] = _map_one(codons, i, grammar, options, stack, depths, out)


@njit(cache=True, inline="always")
def _map_one(codons, i, grammar, options, stack, depths, out):  # pragma: no cover - compiled
    """Map genome ``i`` as :func:`map_genome` does, tokenising terminals as they are popped.

    The chosen alternative is read in place (``cur`` up to ``cur_end``) rather than pushed:
    only what follows a non-terminal goes on the stack, when that non-terminal expands,
    so leading terminals and the first non-terminal of each alternative skip the stack.
    """
    start, rule_alts, alt_symbols, alt_nts, symbols, choice = grammar[:6]
    term_chars, chars, trie, trie_element, classes = grammar[6:11]
    term_fast, term_emits, emits, term_end_mode, term_end_node, rows = grammar[11:]
    lazy, pony, limit, max_depth = options[1], options[2], options[3], options[4]
    element_ids, numbers = out[3], out[4]
    n, slots = codons.shape[1], element_ids.shape[1]
    stack[0], depths[0] = start, 1
    sp, used, pos, deepest, pending = 1, 0, 0, 1, 1
    cur, cur_end, cur_depth, stuck = 0, 0, 0, False
    mode, node, sign, mant, scale, count, n_num, row = IDLE, 0, 1.0, 0.0, 1.0, 0, 0, NO_ROW
    while (cur < cur_end or sp > 0) and deepest <= max_depth:
        wrapped = pony and used > 0 and pos == 0 and pending > 0
        if cur < cur_end:
            symbol, depth = symbols[cur], cur_depth
            cur += 1
        else:
            sp -= 1
            symbol, depth = stack[sp], depths[sp]
        deepest = max(deepest, depth)
        if symbol < 0 and mode == IDLE and term_fast[-1 - symbol]:
            for q in range(term_emits[-1 - symbol], term_emits[-symbol]):
                count, n_num, row = _emit(emits[q], rows, out, i, count, used, row)
            mode, node = term_end_mode[-1 - symbol], term_end_node[-1 - symbol]
        elif symbol < 0:
            for p in range(term_chars[-1 - symbol], term_chars[-symbol]):
                code = chars[p]
                kind = classes[code]
                if mode == NAME and LETTER <= kind <= DIGIT:
                    node = trie[node, code] if node >= 0 else -1
                    continue
                if kind == DIGIT and mode >= SIGN:
                    mant = mant * 10.0 + (code - 48)
                    scale = scale * 10.0 if mode >= POINT else scale
                    mode = FRACTION if mode >= POINT else INT
                    continue
                if kind == DOT and mode == INT:
                    mode = POINT
                    continue
                count, n_num, row = _finish(
                    mode, node, sign * mant / scale, trie_element, rows, out, i, count, n_num, used, row
                )
                mode, node, sign, mant, scale = IDLE, 0, 1.0, 0.0, 1.0
                if kind == LETTER:
                    mode, node = NAME, trie[0, code]
                elif kind == DIGIT:
                    mode, mant = INT, code - 48.0
                elif kind == MINUS:
                    mode, sign = SIGN, -1.0
        else:
            pending -= 1
            first = rule_alts[symbol]
            k = rule_alts[symbol + 1] - first
            if lazy and k == 1:
                chosen = first
            elif used >= limit:
                stuck = True  # left unexpanded: invalid
                break
            else:
                codon = np.int64(codons[i, pos])
                chosen = first + (choice[symbol, codon] if 0 <= codon < CHOICE_CODONS else codon % k)
                used += 1
                pos = 0 if pos + 1 == n else pos + 1
            for j in range(cur_end - 1, cur - 1, -1):  # the rest of the alternative being read
                stack[sp], depths[sp] = symbols[j], cur_depth
                sp += 1
            cur, cur_end, cur_depth = alt_symbols[chosen], alt_symbols[chosen + 1], depth + 1
            pending += alt_nts[chosen]
        if wrapped:
            break
    ok = sp == 0 and cur == cur_end and not stuck
    if ok:
        count, n_num, row = _finish(
            mode, node, sign * mant / scale, trie_element, rows, out, i, count, n_num, used, row
        )
    if not ok or count > slots or row != NO_ROW:
        ok, count = False, 0
    element_codons, membership = out[5], out[6]
    for e in range(count, slots):
        element_ids[i, e] = -1
        element_codons[i, e] = NO_ELEMENT
    for e in range(count, numbers.shape[1]):
        for j in range(NUMBERS_PER_ELEMENT):
            numbers[i, e, j] = np.nan
    for e in range(count, membership.shape[1]):
        membership[i, e, 0], membership[i, e, 1], membership[i, e, 2] = ALONE
    return ok, used, count


@njit(cache=True, inline="always")
def _finish(
    mode, node, value, trie_element, rows, out, i, count, n_num, used, row
):  # pragma: no cover - compiled
    """Emit the token that just ended; a ``count`` beyond the slots means overflow. ``row``: the row
    awaiting its count (:data:`NO_ROW`, :data:`BROKEN`)."""
    numbers = out[4]
    if mode == NAME and node >= 0 and trie_element[node] >= 0:
        return _emit(trie_element[node], rows, out, i, count, used, row)
    if mode >= INT and row >= 0:
        return _members(row, value, rows, out, i, count, used)
    if mode >= INT and 0 < count <= numbers.shape[1] and n_num < NUMBERS_PER_ELEMENT:
        numbers[i, count - 1, n_num] = value
        return count, n_num + 1, row
    return count, n_num, row


@njit(cache=True, inline="always")
def _emit(element, rows, out, i, count, used, row):  # pragma: no cover - compiled
    """Record element number ``count`` of genome ``i``, completed after ``used`` codons (slots past the
    end only count); a row's name awaits its count, and breaks a row awaiting one."""
    first_row = rows[0]
    if row != NO_ROW:
        return count, 0, BROKEN
    if element >= first_row:
        return count, 0, element - first_row
    _put_slot(element, out, i, count, used, -1, 0, 1)
    return count + 1, 0, NO_ROW


@njit(cache=True, inline="always")
def _members(row, value, rows, out, i, count, used):  # pragma: no cover - compiled
    """Record the members of row ``row`` whose count ``value`` just ended, or break it when the count is
    not a whole number within its bounds."""
    row_member, row_count = rows[1], rows[2]
    if not (row_count[row, 0] <= value <= row_count[row, 1]) or value != np.floor(value):
        return count, 0, BROKEN
    members = np.int64(value)
    for m in range(members):
        _put_slot(row_member[row], out, i, count + m, used, row, m, members)
    return count + members, 0, NO_ROW


@njit(cache=True, inline="always")
def _put_slot(element, out, i, slot, used, row, member, members):  # pragma: no cover - compiled
    """Write element ``element`` into slot ``slot`` of genome ``i`` (if there is one), member ``member``
    of ``members`` of row ``row`` (-1: placed alone)."""
    element_ids, numbers, membership = out[3], out[4], out[6]  # numbers and membership may have 0 slots
    if slot < element_ids.shape[1]:
        element_ids[i, slot] = element
        out[5][i, slot] = used
    if slot < numbers.shape[1]:
        for k in range(NUMBERS_PER_ELEMENT):
            numbers[i, slot, k] = np.nan
    if slot < membership.shape[1]:
        membership[i, slot, 0], membership[i, slot, 1], membership[i, slot, 2] = row, member, members
