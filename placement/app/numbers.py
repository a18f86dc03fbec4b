"""How the workbench writes a number for people: five significant digits and its unit, the full value kept.

The page shows ``4.8011 J``; the element also carries the value to full precision (``data-value``, and as
its tooltip), which Export writes and the browser tests compare to the command line's to 1e-9.
"""

from __future__ import annotations

import html

import numpy as np

SIGNIFICANT_DIGITS = 5


def readable(value: float, digits: int = SIGNIFICANT_DIGITS) -> str:
    """``value`` to ``digits`` significant digits ("4.8011", "-0.0012346", "1.2346e+05"); "-" when not finite."""
    if not np.isfinite(value):
        return "-"
    return format(float(value), f".{digits}g")


def number_html(element_id: str, value: float, unit: str = "", digits: int = SIGNIFICANT_DIGITS) -> str:
    """A number's HTML: ``<span id=... data-value=...>4.8011</span> J`` (the unit outside the element)."""
    full = repr(float(value)) if np.isfinite(value) else ""
    text = (f'<span id="{html.escape(element_id)}" data-value="{full}" title="{full}">{readable(value, digits)}'
            "</span>")
    return f"{text} {html.escape(unit)}" if unit else text
