"""Bit rows: grid rows stored as ``uint64`` words, and the word operations the kernels share.

Bit ``j % 64`` of word ``j // 64`` is column ``j``. Counting and finding bits use the
processor's own instructions (LLVM's ``ctpop`` and ``cttz``) through numba intrinsics:
a table-free count is several times cheaper than a software one in the inner loops.
"""

from __future__ import annotations

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.extending import intrinsic

ONE = np.uint64(1)
ALL = np.uint64(0xFFFFFFFFFFFFFFFF)
HIGH = np.uint64(63)


@intrinsic
def _ctpop(typingctx, x):  # pragma: no cover - compiled
    if not isinstance(x, types.Integer):
        return None

    def codegen(context, builder, signature, args):
        return builder.ctpop(args[0])

    return x(x), codegen


@intrinsic
def _cttz(typingctx, x):  # pragma: no cover - compiled
    if not isinstance(x, types.Integer):
        return None

    def codegen(context, builder, signature, args):
        # "zero is poison": callers pass non-zero words only, so LLVM may use the bare instruction.
        return builder.cttz(args[0], ir.Constant(ir.IntType(1), 1))

    return x(x), codegen


@njit(cache=True, inline="always")
def lowest_bit(x):  # pragma: no cover - compiled
    """Index of the lowest set bit of a non-zero ``uint64``."""
    return int(_cttz(x))


@njit(cache=True, inline="always")
def popcount(x):  # pragma: no cover - compiled
    """Number of set bits of a ``uint64``."""
    return int(_ctpop(x))


@njit(cache=True, inline="always")
def span_mask(first, last, w):  # pragma: no cover - compiled
    """The bits of word ``w`` that lie in columns ``first..last`` (``w`` within their words)."""
    lo = first - 64 * w if w == first >> 6 else 0
    hi = last - 64 * w if w == last >> 6 else 63
    width = hi - lo + 1
    return ALL if width == 64 else ((ONE << np.uint64(width)) - ONE) << np.uint64(lo)


@njit(cache=True, inline="always")
def set_block(rows, first_row, last_row, first, last):  # pragma: no cover - compiled
    """Set columns ``first..last`` of bit rows ``first_row..last_row`` of ``rows``."""
    for w in range(first >> 6, (last >> 6) + 1):
        mask = span_mask(first, last, w)
        for r in range(first_row, last_row + 1):
            rows[r, w] |= mask


@njit(cache=True, inline="always")
def is_set(row, c):  # pragma: no cover - compiled
    """Whether column ``c`` of a bit row is set."""
    return bool((row[c >> 6] >> np.uint64(c & 63)) & ONE)
