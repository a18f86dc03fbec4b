"""Limits as margins (a plug-in family, see :mod:`placement.limits.base`)."""

from placement.limits import collision, joints, motors, thermal, timing, workspace
from placement.limits.base import LIMITS, Limit, Margin, MarginField, margin_fields, tightest, worst_margins

__all__ = ["LIMITS", "Limit", "Margin", "MarginField", "collision", "joints", "margin_fields", "motors", "thermal",
           "tightest", "timing", "workspace", "worst_margins"]
