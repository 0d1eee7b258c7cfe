"""granmix studies: many co-simulations of a granmix scene and partner FMUs.

- :mod:`granmix.study` reads a study file (TOML): the scene, the partner FMUs, their
  connections, the parameters to vary, the design and the outputs to collect. Errors
  name the file, the key and the line.
- :mod:`granmix.design` turns a study's design (full grid, explicit list, seeded random
  or Latin hypercube) into cases, each keyed by a hash of its full specification.
- :mod:`granmix.master` runs one case (the co-simulation master loop) into a row.
- :mod:`granmix.sweep` runs a study's cases serially or on Dask, and
  :mod:`granmix.store` keeps each finished case on disk the moment it finishes, so
  that ``--resume`` runs only the missing ones.
- :mod:`granmix.cli` is ``granmix-sweep``.
- :mod:`granmix.vtu` reads the ``.vtu`` snapshots of ``granmix run`` into numpy arrays.
- :mod:`granmix.debris_variants` runs the saturated debris flow dry, saturated, dilatant
  and contractant and reports run-out, barrier loads and the pore pressure around its
  boulders (``python -m granmix.debris_variants``).
"""

from granmix.design import Case, cases
from granmix.study import Study, StudyError, load_study, parse_study

__all__ = ["Case", "Study", "StudyError", "cases", "load_study", "parse_study"]
