"""The involute function and its inverse over the whole useful range."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from gearbox.errors import InputError
from gearbox.geometry import inv, inv_inverse


def test_series_branch_keeps_relative_accuracy_for_small_angles():
    """Against the Taylor series to many terms, evaluated in exact rational steps."""
    a = np.array([1e-8, 1e-4, 1e-2, 0.049])
    ref = a**3 / 3 + 2 * a**5 / 15 + 17 * a**7 / 315 + 62 * a**9 / 2835 + 1382 * a**11 / 155925
    assert np.allclose(inv(a), ref, rtol=1e-15, atol=0)


def test_known_value_that_once_failed_to_converge():
    y = 0.017793399545623423  # inv(0.3695356...) : Newton oscillated on the last bit
    a = inv_inverse(y)
    assert abs(inv(a) - y) <= 4 * np.finfo(float).eps * np.tan(a)


@given(st.floats(1e-9, 1.5))
def test_inverse_round_trip(a):
    # accuracy limited by one ulp of tan(a) over d inv/da = tan^2(a)
    b = inv_inverse(inv(a))
    assert abs(b - a) <= 8 * np.finfo(float).eps * (np.tan(a) + a) / np.tan(a) ** 2 + 1e-15 * a


def test_vectorised_and_zero():
    a = np.linspace(0.0, 1.4, 200)
    assert np.allclose(inv_inverse(inv(a)), a, rtol=1e-12, atol=1e-13)
    assert inv_inverse(0.0) == 0.0


def test_negative_is_an_input_error():
    with pytest.raises(InputError, match="inv_inverse.y"):
        inv_inverse(-1e-3)
