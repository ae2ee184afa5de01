"""What generated experiments import: mapping, geometry, metrics, evolution, results.

The runtime never imports textX: a Spec is plain data.
"""

import os

# With OpenMP's default active waiting every parallel numba call costs ~45 ms on a busy machine.
os.environ.setdefault("OMP_WAIT_POLICY", "passive")
