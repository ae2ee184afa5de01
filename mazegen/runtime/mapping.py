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
scenario elements (see :func:`extract_elements`) on the fly.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numba import get_num_threads, njit, prange

from mazegen.runtime.bnf import Grammar, Symbol

NUMBERS_PER_ELEMENT = 4
_TOKEN = re.compile(r"(?P<name>[A-Za-z_][A-Za-z0-9_]*)|(?P<number>-?[0-9]+(?:\.[0-9]+)?)")
# Character classes of the kernel's tokeniser (ASCII codes; other text is 0).
_OTHER, _LETTER, _DIGIT, _MINUS, _DOT = 0, 1, 2, 3, 4
_CLASSES = np.zeros(128, np.int8)
_CLASSES[[ord(c) for c in "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz_"]] = _LETTER
_CLASSES[[ord(c) for c in "0123456789"]] = _DIGIT
_CLASSES[ord("-")], _CLASSES[ord(".")] = _MINUS, _DOT
# Tokeniser states.
_IDLE, _NAME, _SIGN, _INT, _POINT, _FRACTION = range(6)
_CHOICE_CODONS = 256  # codons with a precomputed alternative per rule (the usual 0..255)


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
class CompiledGrammar:
    """A grammar as flat arrays for the kernel (see :func:`compile_grammar`).

    Symbols are ``int32`` codes: a rule index (``>= 0``) or ``-1 - terminal``.
    Rule ``r`` owns alternatives ``rule_alts[r]:rule_alts[r + 1]``; alternative
    ``a`` owns ``symbols[alt_symbols[a]:alt_symbols[a + 1]]`` and holds
    ``alt_nonterminals[a]`` non-terminals. Terminal ``t`` is the ASCII codes
    ``chars[term_chars[t]:term_chars[t + 1]]`` (other characters are 0).
    ``trie[node, code]`` is the next node of the element-name trie (-1 none) and
    ``trie_element[node]`` the element a name ending there denotes (-1 none).

    Terminals without digits, ``-`` or ``.`` are also tokenised once, here: read
    from the idle state, terminal ``t`` emits the elements
    ``emits[term_emits[t]:term_emits[t + 1]]`` and leaves the tokeniser in
    ``term_end_mode[t]``, ``term_end_node[t]``; ``term_fast[t]`` marks them.
    ``choice[r, c]`` is ``c % alternatives`` of rule ``r`` for codons ``c`` below
    256, a table lookup instead of an integer division per derivation step.
    """

    element_names: tuple[str, ...]
    start: int
    max_alt_len: int
    rule_alts: np.ndarray
    alt_symbols: np.ndarray
    alt_nonterminals: np.ndarray
    symbols: np.ndarray
    term_chars: np.ndarray
    chars: np.ndarray
    trie: np.ndarray
    trie_element: np.ndarray
    term_fast: np.ndarray
    term_emits: np.ndarray
    emits: np.ndarray
    term_end_mode: np.ndarray
    term_end_node: np.ndarray
    choice: np.ndarray


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
    """

    valid: np.ndarray
    used_codons: np.ndarray
    n_elements: np.ndarray
    element_ids: np.ndarray
    numbers: np.ndarray


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


def extract_elements(text: str, element_names: Sequence[str]) -> list[tuple[int, tuple[float, ...]]]:
    """Tokenise a phenotype into elements and their numbers (reference for the kernel).

    Identifiers ``[A-Za-z_][A-Za-z0-9_]*`` equal to an element name are elements;
    numbers ``-?[0-9]+(.[0-9]+)?`` outside identifiers attach, in order and at
    most four, to the latest element; everything else is ignored.

    Args:
        text: A phenotype.
        element_names: The element names; an element's id is its index.

    Returns:
        ``(element_id, numbers)`` for every element, in order.
    """
    ids = {name: i for i, name in enumerate(element_names)}
    found: list[tuple[int, list[float]]] = []
    for token in _TOKEN.finditer(text):
        if token.lastgroup == "name":
            if token.group() in ids:
                found.append((ids[token.group()], []))
        elif found and len(found[-1][1]) < NUMBERS_PER_ELEMENT:
            found[-1][1].append(float(token.group()))
    return [(element, tuple(numbers)) for element, numbers in found]


def compile_grammar(grammar: Grammar, element_names: Sequence[str]) -> CompiledGrammar:
    """Flatten a grammar into the arrays :func:`map_population` works on.

    Args:
        grammar: The grammar.
        element_names: Element names recognised in terminals; id = index.

    Returns:
        The compiled grammar.

    Raises:
        ValueError: If an element name is not an ASCII identifier or repeats.
    """
    if len(set(element_names)) != len(element_names):
        raise ValueError("element names repeat")
    rule_ids = {name: i for i, name in enumerate(grammar.rules)}
    terminals: dict[str, int] = {}
    rule_alts, alt_symbols, alt_nts, symbols = [0], [0], [], []
    for alternatives in grammar.rules.values():
        for alternative in alternatives:
            symbols += [
                rule_ids[s.text] if s.nonterminal else ~terminals.setdefault(s.text, len(terminals))
                for s in alternative
            ]
            alt_symbols.append(len(symbols))
            alt_nts.append(sum(s.nonterminal for s in alternative))
        rule_alts.append(len(alt_symbols) - 1)
    term_chars: list[int] = [0]
    chars: list[int] = []
    for text in terminals:
        chars.extend(ord(c) if ord(c) < 128 else 0 for c in text)
        term_chars.append(len(chars))
    trie = [[-1] * 128]
    trie_element = [-1]
    for element, name in enumerate(element_names):
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
            raise ValueError(f"element name {name!r} is not an identifier")
        node = 0
        for c in name:
            if trie[node][ord(c)] < 0:
                trie[node][ord(c)] = len(trie)
                trie.append([-1] * 128)
                trie_element.append(-1)
            node = trie[node][ord(c)]
        trie_element[node] = element
    fast, emit_offsets, emitted, end_modes, end_nodes = [], [0], [], [], []
    for text in terminals:
        scan = _scan_from_idle(text, trie, trie_element)
        fast.append(scan is not None)
        elements, end_mode, end_node = scan or ([], _IDLE, 0)
        emitted += elements
        emit_offsets.append(len(emitted))
        end_modes.append(end_mode)
        end_nodes.append(end_node)
    i32 = np.int32
    return CompiledGrammar(
        element_names=tuple(element_names),
        start=rule_ids[grammar.start],
        max_alt_len=max(len(a) for alts in grammar.rules.values() for a in alts),
        rule_alts=np.array(rule_alts, i32),
        alt_symbols=np.array(alt_symbols, i32),
        alt_nonterminals=np.array(alt_nts, i32),
        symbols=np.array(symbols, i32),
        term_chars=np.array(term_chars, i32),
        chars=np.array(chars, np.uint8),
        trie=np.array(trie, i32),
        trie_element=np.array(trie_element, i32),
        term_fast=np.array(fast, np.bool_),
        term_emits=np.array(emit_offsets, i32),
        emits=np.array(emitted, i32),
        term_end_mode=np.array(end_modes, i32),
        term_end_node=np.array(end_nodes, i32),
        choice=np.arange(_CHOICE_CODONS)[None, :] % np.diff(rule_alts)[:, None].astype(i32),
    )


def _scan_from_idle(
    text: str, trie: list[list[int]], trie_element: list[int]
) -> tuple[list[int], int, int] | None:
    """Tokenise a terminal from the idle state as the kernel would; ``None`` if it holds number characters.

    Returns:
        The elements completed inside the terminal, and the tokeniser's final mode and trie node.
    """
    codes = [ord(c) if ord(c) < 128 else 0 for c in text]
    if any(_CLASSES[code] in (_DIGIT, _MINUS, _DOT) for code in codes):
        return None
    mode, node, elements = _IDLE, 0, []
    for code in codes:
        letter = _CLASSES[code] == _LETTER
        if mode == _NAME and letter:
            node = trie[node][code] if node >= 0 else -1
            continue
        if mode == _NAME and node >= 0 and trie_element[node] >= 0:
            elements.append(trie_element[node])
        mode, node = (_NAME, trie[0][code]) if letter else (_IDLE, 0)
    return elements, mode, node


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
    (also when the element limit makes an individual invalid); the elements and
    numbers equal :func:`extract_elements` of the reference phenotype, tokens
    spanning several terminals included (numbers are exact up to 15 digits).

    Args:
        compiled: The grammar from :func:`compile_grammar`.
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
    n = codons.shape[0]
    layout = [
        ((n,), np.bool_),
        ((n,), np.int32),
        ((n,), np.int32),
        ((n, max_elements), np.int32),
        ((n, max_elements if numbers else 0, NUMBERS_PER_ELEMENT), np.float64),
    ]
    result = out or PopulationMap(*(np.empty(shape, dtype) for shape, dtype in layout))
    arrays = (result.valid, result.used_codons, result.n_elements, result.element_ids, result.numbers)
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
        _CLASSES,
        c.term_fast,
        c.term_emits,
        c.emits,
        c.term_end_mode,
        c.term_end_node,
    )
    options = (
        min(n, 8 * get_num_threads()),
        (max_depth + 3) * c.max_alt_len + 1,
        consume == "lazy",
        consume == "eager" and wraps == 0,
        _codon_limit(codons.shape[1], wraps, consume),
        max_depth,
    )
    _map_all(codons, grammar, options, arrays)
    return result


@njit(cache=True, parallel=True)
def _map_all(codons, grammar, options, out):  # pragma: no cover - compiled
    """Map the population in parallel slices, one preallocated stack per slice."""
    n, chunks, capacity = codons.shape[0], options[0], options[1]
    valid, used, n_elements = out[0], out[1], out[2]
    for chunk in prange(chunks):
        stack, depths = np.empty(capacity, np.int32), np.empty(capacity, np.int32)
        for i in range(chunk * n // chunks, (chunk + 1) * n // chunks):
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
    term_fast, term_emits, emits, term_end_mode, term_end_node = grammar[11:]
    lazy, pony, limit, max_depth = options[2], options[3], options[4], options[5]
    element_ids, numbers = out[3], out[4]
    n, slots = codons.shape[1], element_ids.shape[1]
    stack[0], depths[0] = start, 1
    sp, used, pos, deepest, pending = 1, 0, 0, 1, 1
    cur, cur_end, cur_depth, stuck = 0, 0, 0, False
    mode, node, sign, mant, scale, count, n_num = _IDLE, 0, 1.0, 0.0, 1.0, 0, 0
    while (cur < cur_end or sp > 0) and deepest <= max_depth:
        wrapped = pony and used > 0 and pos == 0 and pending > 0
        if cur < cur_end:
            symbol, depth = symbols[cur], cur_depth
            cur += 1
        else:
            sp -= 1
            symbol, depth = stack[sp], depths[sp]
        deepest = max(deepest, depth)
        if symbol < 0 and mode == _IDLE and term_fast[-1 - symbol]:
            for q in range(term_emits[-1 - symbol], term_emits[-symbol]):
                count, n_num = _emit(emits[q], out, i, count)
            mode, node = term_end_mode[-1 - symbol], term_end_node[-1 - symbol]
        elif symbol < 0:
            for p in range(term_chars[-1 - symbol], term_chars[-symbol]):
                code = chars[p]
                kind = classes[code]
                if mode == _NAME and _LETTER <= kind <= _DIGIT:
                    node = trie[node, code] if node >= 0 else -1
                    continue
                if kind == _DIGIT and mode >= _SIGN:
                    mant = mant * 10.0 + (code - 48)
                    scale = scale * 10.0 if mode >= _POINT else scale
                    mode = _FRACTION if mode >= _POINT else _INT
                    continue
                if kind == _DOT and mode == _INT:
                    mode = _POINT
                    continue
                count, n_num = _finish(mode, node, sign * mant / scale, trie_element, out, i, count, n_num)
                mode, node, sign, mant, scale = _IDLE, 0, 1.0, 0.0, 1.0
                if kind == _LETTER:
                    mode, node = _NAME, trie[0, code]
                elif kind == _DIGIT:
                    mode, mant = _INT, code - 48.0
                elif kind == _MINUS:
                    mode, sign = _SIGN, -1.0
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
                chosen = first + (choice[symbol, codon] if 0 <= codon < _CHOICE_CODONS else codon % k)
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
        count, n_num = _finish(mode, node, sign * mant / scale, trie_element, out, i, count, n_num)
    if not ok or count > slots:
        ok, count = False, 0
    for e in range(count, slots):
        element_ids[i, e] = -1
    for e in range(count, numbers.shape[1]):
        for j in range(NUMBERS_PER_ELEMENT):
            numbers[i, e, j] = np.nan
    return ok, used, count


@njit(cache=True, inline="always")
def _finish(mode, node, value, trie_element, out, i, count, n_num):  # pragma: no cover - compiled
    """Emit the token that just ended; a ``count`` beyond the slots means overflow."""
    numbers = out[4]
    if mode == _NAME and node >= 0 and trie_element[node] >= 0:
        return _emit(trie_element[node], out, i, count)
    if mode >= _INT and 0 < count <= numbers.shape[1] and n_num < NUMBERS_PER_ELEMENT:
        numbers[i, count - 1, n_num] = value
        return count, n_num + 1
    return count, n_num


@njit(cache=True, inline="always")
def _emit(element, out, i, count):  # pragma: no cover - compiled
    """Record element number ``count`` of genome ``i`` (slots past the end only count)."""
    element_ids, numbers = out[3], out[4]  # numbers has 0 slots when not kept
    if count < element_ids.shape[1]:
        element_ids[i, count] = element
    if count < numbers.shape[1]:
        for k in range(NUMBERS_PER_ELEMENT):
            numbers[i, count, k] = np.nan
    return count + 1, 0
