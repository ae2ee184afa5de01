"""Genome hashing and the evaluation cache of an evolution run.

Rows are identified by a 64-bit hash of both chromosomes. The cache keeps the
fitness and codon usage of the previous generation's genomes, where nearly all repeats
come from (elites and parents copied without change), and a generation's duplicates are
evaluated once.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from mazegen.runtime.engine._used_operators import Usage
from mazegen.runtime.threads import in_blocks

_FNV_OFFSETS = (  # one FNV-1a chain per lane, each from its own start
    np.uint64(0xCBF29CE484222325),
    np.uint64(0x84222325CBF29CE4),
    np.uint64(0x9E3779B97F4A7C15),
    np.uint64(0xD6E8FEB86659FD93),
)
_FNV_PRIME = np.uint64(0x100000001B3)
_MIX_1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX_2 = np.uint64(0x94D049BB133111EB)


@njit(cache=True, inline="always")
def _mix(h):  # pragma: no cover - compiled
    """The splitmix64 finaliser: a bijection that spreads every input bit over the output."""
    h = (h ^ (h >> np.uint64(30))) * _MIX_1
    h = (h ^ (h >> np.uint64(27))) * _MIX_2
    return h ^ (h >> np.uint64(31))


@njit(cache=True, inline="always")
def _lanes(row, a, b, c, d):  # pragma: no cover - compiled
    """Feed ``row`` to four FNV-1a chains, value ``j`` to chain ``j % 4`` (the tail to the first).

    Four independent chains let the processor overlap the multiplications; rows of one
    call share their length, so the split is the same for every row.
    """
    n, j = row.shape[0], 0
    while j + 4 <= n:
        a = (a ^ np.uint64(row[j])) * _FNV_PRIME
        b = (b ^ np.uint64(row[j + 1])) * _FNV_PRIME
        c = (c ^ np.uint64(row[j + 2])) * _FNV_PRIME
        d = (d ^ np.uint64(row[j + 3])) * _FNV_PRIME
        j += 4
    while j < n:
        a = (a ^ np.uint64(row[j])) * _FNV_PRIME
        j += 1
    return a, b, c, d


@njit(cache=True, nogil=True)
def _hash_rows(first, last, codons, genes, out):  # pragma: no cover - compiled
    for i in range(first, last):
        a, b, c, d = _FNV_OFFSETS
        a, b, c, d = _lanes(codons[i], a, b, c, d)
        a, b, c, d = _lanes(genes[i], a, b, c, d)
        out[i] = _mix(_mix(_mix(_mix(a) ^ b) ^ c) ^ d)


def genome_hashes(codons: np.ndarray, genes: np.ndarray) -> np.ndarray:
    """``uint64[N]`` hash of each genome (codons and placement genes)."""
    n = codons.shape[0]
    flat_genes = np.ascontiguousarray(genes).reshape(n, int(np.prod(genes.shape[1:])))
    out = np.empty(n, dtype=np.uint64)
    in_blocks(_hash_rows, n, np.ascontiguousarray(codons), flat_genes, out)
    return out


@dataclass(frozen=True)
class Lookup:
    """How a generation splits between the cache, its own duplicates and new genomes.

    Attributes:
        todo: Rows to evaluate: the first occurrence of each genome the cache lacks, ascending.
        first: ``int64[N]``: the first row holding the same genome as each row.
        fitness: ``float64[N]``: the cached fitness of first occurrences, NaN where unknown.
        cached: Rows whose genome the cache holds (first occurrences), ascending.
        cached_from: The previous generation's row of each of ``cached``.
        distinct: Number of distinct genomes in the generation.
        table: Open-addressing table of the generation's hashes (0 = empty slot).
        table_rows: The first row of each table slot's genome.
    """

    todo: np.ndarray
    first: np.ndarray
    fitness: np.ndarray
    cached: np.ndarray
    cached_from: np.ndarray
    distinct: int
    table: np.ndarray
    table_rows: np.ndarray


class EvaluationCache:
    """Fitness and usage of the genomes of the last generation, in a hash table keyed by genome hash.

    Lookups and inserts run in a compiled loop over open-addressing tables (linear
    probing, at most half full): a generation of 50,000 is split in about a millisecond,
    where sorting its hashes cost several.
    """

    def __init__(self) -> None:
        self._table = np.zeros(1, dtype=np.uint64)
        self._rows = np.zeros(1, dtype=np.int64)
        self._fitness = np.zeros(1, dtype=np.float64)
        self._usage = Usage.empty(0, 0)

    def lookup(self, hashes: np.ndarray) -> Lookup:
        """Split a generation by its genome ``hashes`` (from :func:`genome_hashes`)."""
        capacity = 1 << max(1, int(2 * hashes.shape[0] - 1).bit_length())
        table = np.zeros(capacity, dtype=np.uint64)
        table_rows = np.empty(capacity, dtype=np.int64)
        first = np.empty(hashes.shape[0], dtype=np.int64)
        fitness = np.full(hashes.shape[0], np.nan)
        todo = np.empty(hashes.shape[0], dtype=np.int64)
        cached = np.empty(hashes.shape[0], dtype=np.int64)
        cached_from = np.empty(hashes.shape[0], dtype=np.int64)
        old = (self._table, self._rows, self._fitness)
        distinct, new, hits = _split(
            hashes, old, table, table_rows, first, fitness, todo, cached, cached_from
        )
        return Lookup(
            todo[:new], first, fitness, cached[:hits], cached_from[:hits], int(distinct), table, table_rows
        )

    def recall_usage(self, lookup: Lookup, usage: Usage) -> None:
        """Write the usage of ``lookup``'s cached rows into those rows of ``usage``."""
        usage.put(lookup.cached, self._usage, lookup.cached_from)

    def remember(self, lookup: Lookup, fitness: np.ndarray, usage: Usage) -> None:
        """Replace the cache with the generation of ``lookup``, whose rows scored ``fitness`` and
        read the codons ``usage`` says (every row, like ``fitness``)."""
        self._table, self._rows, self._fitness = lookup.table, lookup.table_rows, fitness
        self._usage = usage


@njit(cache=True, inline="always")
def _slot(table, key):  # pragma: no cover - compiled
    """The slot holding ``key``, or the empty slot where it would go."""
    mask = np.uint64(table.shape[0] - 1)
    slot = (key ^ (key >> np.uint64(29))) & mask
    while table[slot] != 0 and table[slot] != key:
        slot = (slot + np.uint64(1)) & mask
    return slot


@njit(cache=True)
def _split(
    hashes, old, table, table_rows, first, fitness, todo, cached, cached_from
):  # pragma: no cover - compiled
    old_table, old_rows, old_fitness = old
    distinct = 0
    new = 0
    hits = 0
    for i in range(hashes.shape[0]):
        key = hashes[i] if hashes[i] != 0 else np.uint64(1)  # 0 marks empty slots
        slot = _slot(table, key)
        if table[slot] == key:
            first[i] = table_rows[slot]
            continue
        table[slot] = key
        table_rows[slot] = i
        first[i] = i
        distinct += 1
        seen = _slot(old_table, key)
        if old_table[seen] == key:
            fitness[i] = old_fitness[old_rows[seen]]
            cached[hits] = i
            cached_from[hits] = old_rows[seen]
            hits += 1
        else:
            todo[new] = i
            new += 1
    return distinct, new, hits
