"""Taylor arithmetic: derivatives of compositions equal finite differences."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from placement.kinematics import taylor
from placement.kinematics.taylor import Taylor2


def curve(t, c):
    """A smooth test curve with known value, first and second derivative."""
    return c[0] + c[1] * np.sin(t) + c[2] * t**2, c[1] * np.cos(t) + 2 * c[2] * t, -c[1] * np.sin(t) + 2 * c[2]


def composite(x, y):
    """Uses every operation: + - * / sqrt arctan2, reversed operands and constants."""
    r = taylor.sqrt(1.5 + x * x + 0.5 * y * y)
    return taylor.arctan2(y - 0.3, r) * (2.0 - x) / (1.0 + r) + 1.0 / r - (3.0 - y) / 2.0


@settings(max_examples=50, deadline=None)
@given(st.floats(-2, 2), st.lists(st.floats(-1, 1), min_size=3, max_size=3),
       st.lists(st.floats(-1, 1), min_size=3, max_size=3))
def test_derivatives_equal_finite_differences(t, cx, cy):
    h = 1e-4
    x, y = Taylor2(*map(np.array, curve(t, cx))), Taylor2(*map(np.array, curve(t, cy)))
    result = composite(x, y)

    def value(s):
        return composite(Taylor2.constant(curve(s, cx)[0]), Taylor2.constant(curve(s, cy)[0])).v

    first = (value(t + h) - value(t - h)) / (2 * h)
    second = (value(t + h) - 2 * value(t) + value(t - h)) / h**2
    assert np.isclose(result.d1, first, atol=1e-7)
    assert np.isclose(result.d2, second, atol=1e-5)
