"""The motion as the page plays it: slowed down so that a short pass can be followed, and the time shown as a
cursor on the plot of each actuator's electric power."""

from __future__ import annotations

from fractions import Fraction

import numpy as np

SPEEDS = tuple(Fraction(1, 2 ** k) for k in range(6, -1, -1))  # 1/64 .. 1: of real time
PASS_SHOWN_S = 3.0  # the default speed shows a pass in at least this long


def speed_text(speed: Fraction) -> str:
    """'1/16 x' or '1 x (real time)'."""
    return "1 x (real time)" if speed == 1 else f"{speed} x"


def playback_speed(duration_s: float) -> Fraction:
    """The fastest speed of :data:`SPEEDS` at which a pass of ``duration_s`` (s) plays in :data:`PASS_SHOWN_S` or more
    (the slowest, 1/64, for a pass too short for any): a 0.27 s pass at 1/16, in 4.3 s."""
    fast_enough = [speed for speed in SPEEDS if duration_s / speed >= PASS_SHOWN_S]
    return max(fast_enough) if fast_enough else SPEEDS[0]


def power_with_cursor(t_s: np.ndarray, power_W: np.ndarray, now_s: float) -> tuple[np.ndarray, ...]:
    """The power plot's data with a cursor at ``now_s``: the sample nearest it repeated, and a last series that is
    a vertical line there, from the least to the greatest power (NaN elsewhere: not drawn).

    Args:
        t_s: The samples' times (n,), s, ascending.
        power_W: Each actuator's electric power at each sample (n, actuators), W.
        now_s: The time shown, s.

    Returns:
        (times (n + 1,), each actuator's power (n + 1,) ..., the cursor (n + 1,)): the times still ascending, each
        actuator's curve the same as drawn without the cursor.
    """
    index = int(np.clip(np.searchsorted(t_s, now_s), 0, len(t_s) - 1))
    repeat = np.insert(np.arange(len(t_s)), index, index)
    cursor = np.full(len(t_s) + 1, np.nan)
    finite = power_W[np.isfinite(power_W)]
    low, high = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 0.0)
    cursor[index], cursor[index + 1] = low, high
    return (np.asarray(t_s, dtype=float)[repeat], *(np.asarray(power_W[repeat, i], dtype=float)
                                                    for i in range(power_W.shape[1])), cursor)


def power_range(power_W: np.ndarray) -> tuple[float, float]:
    """The power axis's range (W): every finite power, with 5 % to spare."""
    finite = power_W[np.isfinite(power_W)]
    low, high = (float(finite.min()), float(finite.max())) if finite.size else (-1.0, 1.0)
    pad = 0.05 * max(high - low, 1e-9)
    return low - pad, high + pad
