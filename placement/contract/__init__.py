"""What a plug-in sees: the batch of evaluated placements, and the bases of objectives and limits.

A package that adds an objective or a limit imports from here alone (the names below are stable):

- :class:`EvaluatedBatch` (:mod:`placement.contract.batch`): what the exact chain computed for a batch of placements;
- :class:`Objective` and :data:`OBJECTIVES` (:mod:`placement.contract.objective`): a number per placement, and the
  better direction;
- :class:`Limit`, :class:`MarginField`, :class:`PathBound` and :data:`LIMITS` (:mod:`placement.contract.limit`): a
  limit's margins at every sample, and its bounds along a path for the optimal timing law.

Its members register under the entry-point groups ``placement.objectives`` and ``placement.limits``.
"""

from placement.contract.batch import EvaluatedBatch
from placement.contract.limit import LIMITS, Limit, Margin, MarginField, PathBound
from placement.contract.objective import OBJECTIVES, Objective, Wording, quantity, wording

__all__ = ["LIMITS", "OBJECTIVES", "EvaluatedBatch", "Limit", "Margin", "MarginField", "Objective", "PathBound", "Wording",
           "quantity", "wording"]
