"""The command line of a generated ``experiment.py``, at the path every build imports it from.

Generated code imports the top level of :mod:`mazegen.runtime` only: this module,
:mod:`~mazegen.runtime.metrics` and :mod:`~mazegen.runtime.population`. These paths stay
put, so a build folder made by an earlier version still runs.
"""

from mazegen.runtime.runs import main

__all__ = ["main"]
