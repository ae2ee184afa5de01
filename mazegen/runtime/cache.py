"""Genome hashing and the evaluation cache of an evolution run.

Rows are identified by a 64-bit FNV-1a hash of both chromosomes. The cache keeps
the fitness of the previous generation's genomes, where nearly all repeats come
from (elites and parents copied without change), and a generation's duplicates
are evaluated once.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

_FNV_OFFSET = np.uint64(0xCBF29CE484222325)
_FNV_PRIME = np.uint64(0x100000001B3)


@njit(cache=True, parallel=True)
def _fnv_rows(codons: np.ndarray, genes: np.ndarray) -> np.ndarray:  # pragma: no cover - compiled
    n = codons.shape[0]
    out = np.empty(n, dtype=np.uint64)
    for i in prange(n):
        h = _FNV_OFFSET
        for value in codons[i]:
            h = (h ^ np.uint64(value)) * _FNV_PRIME
        for value in genes[i]:
            h = (h ^ np.uint64(value)) * _FNV_PRIME
        out[i] = h
    return out


def genome_hashes(codons: np.ndarray, genes: np.ndarray) -> np.ndarray:
    """``uint64[N]`` hash of each genome (codons and placement genes)."""
    return _fnv_rows(np.ascontiguousarray(codons), np.ascontiguousarray(genes.reshape(genes.shape[0], -1)))


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

    def remember(self, hashes: np.ndarray, fitness: np.ndarray) -> None:
        """Replace the cache with this generation's genomes."""
        unique, first = np.unique(hashes, return_index=True)
        self._hashes, self._fitness = unique, fitness[first]
