"""The one least-squares code: exact on exact data, honest about conditioning."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from pysig.errors import InsufficientDataError, NonFiniteError
from pysig.lsq import fit_linear_model, fit_normal_equations, fit_poly


@settings(max_examples=100, deadline=None)
@given(order=st.integers(0, 6),
       coef=st.lists(st.floats(-100, 100), min_size=7, max_size=7),
       lo=st.floats(-40, 40), span=st.floats(5, 100))
def test_recovers_exact_polynomial(order, coef, lo, span):
    x = np.linspace(lo, lo + span, 40)
    y = np.polynomial.polynomial.polyval(x, coef[:order + 1])
    fit = fit_poly(x, y, order)
    scale = max(1.0, np.max(np.abs(y)))
    assert np.max(np.abs(fit(x) - y)) <= 1e-8 * scale
    assert fit.rms <= 1e-8 * scale


def test_raw_coefficients_match_unscaled_form():
    x = np.linspace(0, 70, 30)
    y = 3.0 - 0.5 * x + 0.01 * x ** 2
    np.testing.assert_allclose(fit_poly(x, y, 2).raw_coefficients(), [3.0, -0.5, 0.01], rtol=1e-9, atol=1e-12)


def test_normal_equations_condition_much_worse_at_high_order():
    """The magnetometer paper's C^T C form on raw temperatures squares the condition number
    of an already ill-conditioned Vandermonde matrix; the scaled fit does not."""
    x = np.linspace(0, 70, 50)
    y = np.sin(x / 20)
    for order in (2, 4, 6):
        _, cond_normal = fit_normal_equations(x, y, order)
        cond_scaled = fit_poly(x, y, order).cond
        assert cond_normal > 1e6 * cond_scaled
    _, cond6 = fit_normal_equations(x, y, 6)
    assert cond6 > 1e18


def test_too_few_distinct_points():
    with pytest.raises(InsufficientDataError, match="order 2 needs at least 3 distinct x values, the data has 2"):
        fit_poly([0, 0, 50, 50], [1, 1, 2, 2], 2)


def test_nonfinite_named_by_index():
    with pytest.raises(NonFiniteError, match="non-finite y at index 1"):
        fit_poly([0, 1, 2], [0, np.nan, 2], 1)


def test_linear_model():
    rng = np.random.default_rng(1)
    design = rng.normal(size=(50, 3))
    beta, resid = fit_linear_model(design, design @ [1.0, -2.0, 0.5])
    np.testing.assert_allclose(beta, [1.0, -2.0, 0.5], atol=1e-12)
    assert np.max(np.abs(resid)) < 1e-12
    with pytest.raises(InsufficientDataError):
        fit_linear_model(design[:2], np.zeros(2))
