"""The decoded population a generated ``fitness.py`` reads, at the path every build imports it from.

See :mod:`mazegen.runtime.experiment` for why generated code imports only the top level.
"""

from mazegen.runtime.engine import Population

__all__ = ["Population"]
