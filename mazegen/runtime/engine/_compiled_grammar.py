"""A grammar flattened into arrays for the mapping kernel of :mod:`mazegen.runtime.engine._mapping`.

Rules, alternatives and symbols become index tables; element and row names become a trie
over ASCII codes; terminals are tokenised once here, where they can be, so the
kernel emits their elements without reading their characters. The tokeniser's
character classes and states are shared with the kernel, which reads the
terminals that hold numbers character by character.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from mazegen.runtime.engine._bnf import Grammar

# Character classes of the kernel's tokeniser (ASCII codes; other text is 0).
OTHER, LETTER, DIGIT, MINUS, DOT = 0, 1, 2, 3, 4
CLASSES = np.zeros(128, np.int8)
CLASSES[[ord(c) for c in "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz_"]] = LETTER
CLASSES[[ord(c) for c in "0123456789"]] = DIGIT
CLASSES[ord("-")], CLASSES[ord(".")] = MINUS, DOT
# Tokeniser states.
IDLE, NAME, SIGN, INT, POINT, FRACTION = range(6)
CHOICE_CODONS = 256  # codons with a precomputed alternative per rule (the usual 0..255)


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

    Rows follow the elements in the trie: a name ending at a node with ``trie_element`` of
    ``len(element_names) + r`` is row ``r``, whose members are of element ``row_member[r]``, at least
    ``row_count[r, 0]`` and at most ``row_count[r, 1]`` of them.
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
    row_member: np.ndarray
    row_count: np.ndarray


RowToken = tuple[str, int, int, int]
"""A row as the mapping reads it: its name, its members' element id, its fewest and most members
(:attr:`mazegen.spec.Spec.row_tokens`)."""


def compile_grammar(
    grammar: Grammar, element_names: Sequence[str], rows: Sequence[RowToken] = ()
) -> CompiledGrammar:
    """Flatten a grammar into the arrays :func:`map_population` works on.

    Args:
        grammar: The grammar.
        element_names: Element names recognised in terminals; id = index.
        rows: The rows whose names the phenotype may hold, each followed by its member count.

    Returns:
        The compiled grammar.

    Raises:
        ValueError: If an element or row name is not an ASCII identifier or repeats.
    """
    names = [*element_names, *(row[0] for row in rows)]
    if len(set(names)) != len(names):
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
    for element, name in enumerate(names):
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
        elements, end_mode, end_node = scan or ([], IDLE, 0)
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
        choice=np.arange(CHOICE_CODONS)[None, :] % np.diff(rule_alts)[:, None].astype(i32),
        row_member=np.array([row[1] for row in rows], i32),
        row_count=np.array([row[2:] for row in rows], i32).reshape(len(rows), 2),
    )


def _scan_from_idle(
    text: str, trie: list[list[int]], trie_element: list[int]
) -> tuple[list[int], int, int] | None:
    """Tokenise a terminal from the idle state as the kernel would; ``None`` if it holds number characters.

    Returns:
        The elements completed inside the terminal, and the tokeniser's final mode and trie node.
    """
    codes = [ord(c) if ord(c) < 128 else 0 for c in text]
    if any(CLASSES[code] in (DIGIT, MINUS, DOT) for code in codes):
        return None
    mode, node, elements = IDLE, 0, []
    for code in codes:
        letter = CLASSES[code] == LETTER
        if mode == NAME and letter:
            node = trie[node][code] if node >= 0 else -1
            continue
        if mode == NAME and node >= 0 and trie_element[node] >= 0:
            elements.append(trie_element[node])
        mode, node = (NAME, trie[0][code]) if letter else (IDLE, 0)
    return elements, mode, node
