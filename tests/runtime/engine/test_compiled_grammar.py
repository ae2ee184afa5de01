"""Tests of the grammar tables the mapping kernel reads."""

from __future__ import annotations

import numpy as np
import pytest

from mazegen.runtime.engine._bnf import parse_bnf
from mazegen.runtime.engine._compiled_grammar import CHOICE_CODONS, IDLE, NAME, compile_grammar

GRAMMAR = parse_bnf(
    "<s> ::= <e> | <e> <s> | wall(<n>)\n<e> ::= cobot | wa | ll box | router\n<n> ::= 1 | -2.5 | 3"
)
ELEMENTS = ("cobot", "wall", "router")


def test_rules_alternatives_and_symbols_spell_the_grammar() -> None:
    compiled = compile_grammar(GRAMMAR, ELEMENTS)
    rules = list(GRAMMAR.rules)
    terminals: list[str] = []
    for r, alternatives in enumerate(GRAMMAR.rules.values()):
        first, last = compiled.rule_alts[r], compiled.rule_alts[r + 1]
        assert last - first == len(alternatives)
        for a, alternative in zip(range(first, last), alternatives, strict=True):
            codes = compiled.symbols[compiled.alt_symbols[a] : compiled.alt_symbols[a + 1]]
            spelled = []
            for code in codes:
                if code >= 0:
                    spelled.append(rules[code])
                else:
                    t = -1 - code
                    chars = compiled.chars[compiled.term_chars[t] : compiled.term_chars[t + 1]]
                    spelled.append(bytes(chars).decode())
                    terminals.append(spelled[-1])
            assert spelled == [s.text for s in alternative]
            assert compiled.alt_nonterminals[a] == sum(s.nonterminal for s in alternative)
    assert rules[compiled.start] == GRAMMAR.start
    assert compiled.max_alt_len == max(len(a) for alts in GRAMMAR.rules.values() for a in alts)
    # The codon table is codon % alternatives of each rule.
    counts = np.diff(compiled.rule_alts)
    assert compiled.choice.shape == (len(rules), CHOICE_CODONS)
    np.testing.assert_array_equal(compiled.choice, np.arange(CHOICE_CODONS)[None, :] % counts[:, None])


def test_terminals_without_numbers_are_tokenised_once() -> None:
    compiled = compile_grammar(GRAMMAR, ELEMENTS)
    # Terminals in order of first appearance: each with the elements it completes by itself,
    # and the name it may leave unfinished for the next terminal ("wa" + "ll" is a wall).
    expected = {
        "wall(": ([1], IDLE),
        ")": ([], IDLE),
        "cobot": ([], NAME),  # a name is complete only when a non-letter follows
        "wa": ([], NAME),
        "ll box": ([], NAME),  # from the idle state "ll" starts no name: the kernel reads it after "wa"
        "router": ([], NAME),
    }
    by_text = {}
    for t in range(len(compiled.term_chars) - 1):
        text = bytes(compiled.chars[compiled.term_chars[t] : compiled.term_chars[t + 1]]).decode()
        by_text[text] = t
    for text, (emits, end_mode) in expected.items():
        t = by_text[text]
        assert compiled.term_fast[t], text
        assert list(compiled.emits[compiled.term_emits[t] : compiled.term_emits[t + 1]]) == emits, text
        assert compiled.term_end_mode[t] == end_mode, text
    for number in ("1", "-2.5", "3"):  # read character by character in the kernel
        assert not compiled.term_fast[by_text[number]]
    # The trie spells every element name and ends at its id.
    for element, name in enumerate(ELEMENTS):
        node = 0
        for c in name:
            node = compiled.trie[node, ord(c)]
            assert node > 0
        assert compiled.trie_element[node] == element


@pytest.mark.parametrize(
    ("names", "message"),
    [
        (("cobot", "cobot"), "repeat"),
        (("two words",), "not an identifier"),
        (("héllo",), "not an identifier"),
    ],
)
def test_element_names_must_be_distinct_identifiers(names: tuple[str, ...], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        compile_grammar(GRAMMAR, names)
