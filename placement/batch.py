"""Deprecated module path: :class:`EvaluatedBatch` lives in :mod:`placement.evaluation.batch`.

Plug-ins written for placement 0.1 import it from here; this path keeps working, with a
``DeprecationWarning``, and will be removed in a later release.
"""

import warnings

from placement.evaluation.batch import EvaluatedBatch

warnings.warn("placement.batch is deprecated: import EvaluatedBatch from placement.evaluation.batch",
              DeprecationWarning, stacklevel=2)

__all__ = ["EvaluatedBatch"]
