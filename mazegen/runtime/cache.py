"""Genome hashing and the evaluation cache of an evolution run.

Rows are identified by a 64-bit hash of both chromosomes. The cache keeps the
fitness of the previous generation's genomes, where nearly all repeats come from
(elites and parents copied without change), and a generation's duplicates are
evaluated once.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

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


@njit(cache=True, parallel=True)
def _hash_rows(codons, genes):  # pragma: no cover - compiled
    n = codons.shape[0]
    out = np.empty(n, dtype=np.uint64)
    for i in prange(n):
        a, b, c, d = _FNV_OFFSETS
        a, b, c, d = _lanes(codons[i], a, b, c, d)
        a, b, c, d = _lanes(genes[i], a, b, c, d)
        out[i] = _mix(_mix(_mix(_mix(a) ^ b) ^ c) ^ d)
    return out


def genome_hashes(codons: np.ndarray, genes: np.ndarray) -> np.ndarray:
    """``uint64[N]`` hash of each genome (codons and placement genes)."""
    flat_genes = np.ascontiguousarray(genes).reshape(codons.shape[0], int(np.prod(genes.shape[1:])))
    return _hash_rows(np.ascontiguousarray(codons), flat_genes)


class EvaluationCache:
    """Fitness of the genomes of the last generation, looked up by hash."""

    def __init__(self) -> None:
        self._hashes = np.empty(0, dtype=np.uint64)
        self._fitness = np.empty(0, dtype=np.float64)

    def lookup(self, hashes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Return (found mask, fitness where found) for ``hashes``."""
        if self._hashes.size == 0:
            return np.zeros(hashes.shape[0], dtype=bool), np.zeros(hashes.shape[0])
        where = np.searchsorted(self._hashes, hashes)
        where = np.minimum(where, self._hashes.size - 1)
        found = self._hashes[where] == hashes
        return found, self._fitness[where]

    def remember(self, unique_hashes: np.ndarray, fitness: np.ndarray) -> None:
        """Replace the cache with this generation's genomes.

        Args:
            unique_hashes: Sorted distinct hashes, as from ``np.unique``.
            fitness: Their fitness.
        """
        self._hashes, self._fitness = unique_hashes, fitness
