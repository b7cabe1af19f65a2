"""Model selection: curve tidying and its errors, blocked
cross-validation over temperature, the magnetometer paper's four-point calibration, and
the real MPU-6000 curve."""
import warnings

import numpy as np
import pytest

from conftest import require_shared_data
from pysig.errors import InputFileError, InsufficientDataError, NonFiniteError, RangeError
from pysig.tcomp._cross_validation import (PAPER_TEMPS, blocked_folds, check_size, choose, cross_validate,
                                four_point_choice, four_point_study, load_curve, paper_points,
                                poly_fitter, pwl_fitter, score_sizes, tidy_curve)

MPU = "mpu6000_gyro_offset_vs_temp/mpu6000_sn102_gyro_offset.csv"


# ---- tidying -------------------------------------------------------------------

def test_repeated_temperatures_are_averaged_and_reported():
    temp = [1.0, 2.0, 2.0, 2.0, 3.0, 4.0, 4.0]
    vals = np.array([[1, 10], [2, 20], [4, 40], [6, 60], [7, 70], [8, 80], [10, 100]], float)
    with pytest.warns(UserWarning) as record:
        curve = tidy_curve(temp, vals, ["a", "b"], where="t.csv")
    assert [str(w.message) for w in record] == [
        "t.csv: averaged 3 rows at 2 °C (data rows 2-4)",
        "t.csv: averaged 2 rows at 4 °C (data rows 6-7)"]
    assert list(curve.temp) == [1, 2, 3, 4]
    assert list(curve.axis("a")) == [1, 4, 7, 9]
    assert list(curve.axis("b")) == [10, 40, 70, 90]
    assert len(curve.notes) == 2 and "t.csv" in curve.notes[0]


def test_unsorted_temperature_names_the_row():
    with pytest.raises(InputFileError, match=r"data row 3: temperature 1\.5 after 2\.0"):
        tidy_curve([1.0, 2.0, 1.5, 3.0], [0, 0, 0, 0], ["x"])


def test_nonfinite_cell_names_row_and_column():
    with pytest.raises(NonFiniteError, match=r"data row 2, column 'x'"):
        tidy_curve([1.0, 2.0, 3.0], [0, np.nan, 0], ["x"])
    with pytest.raises(NonFiniteError, match=r"column 'temperature'"):
        tidy_curve([1.0, np.inf, 3.0], [0, 0, 0], ["x"])


def test_load_curve_errors_name_the_file(tmp_path):
    p = tmp_path / "c.csv"
    p.write_text("temp_c,g\n1,5\n3,6\n2,7\n")
    with pytest.raises(InputFileError, match="c.csv: data row 3"):
        load_curve(p, "temp_c", ["g"])
    p.write_text("temp_c,g\n1,5\n")
    curve = load_curve(p, "temp_c", ["g"])
    assert curve.temp.size == 1


# ---- sizes the data cannot support ---------------------------------------------

def test_order_too_high_for_distinct_temperatures():
    temp = np.repeat([0.0, 10.0, 20.0], 4)
    with pytest.raises(InsufficientDataError, match="order 3 needs 4 distinct"):
        check_size("poly", 3, np.unique(temp).size)
    with pytest.raises(InsufficientDataError):
        score_sizes("poly", [1, 3], temp, temp * 2)


@pytest.mark.parametrize("size", [0, 1, -3])
def test_table_with_fewer_than_two_knots(size):
    with pytest.raises(RangeError, match="at least 2 knots"):
        check_size("pwl", size, 100)


def test_unknown_family_and_too_few_blocks():
    with pytest.raises(RangeError, match="unknown model family"):
        check_size("spline", 3, 100)
    with pytest.raises(RangeError, match="at least 3 blocks"):
        blocked_folds(np.arange(10.0), 2)
    with pytest.raises(InsufficientDataError):
        blocked_folds(np.ones(10), 5)


# ---- blocked cross-validation ---------------------------------------------------

def test_folds_are_contiguous_interior_blocks_covering_the_middle():
    temp = np.linspace(0.0, 80.0, 161)
    folds = blocked_folds(temp, 8)
    assert len(folds) == 6
    held = np.concatenate(folds)
    assert np.unique(held).size == held.size                    # each point held out once
    for f in folds:
        assert np.all(np.diff(f) == 1)                          # contiguous
        assert temp[f].max() - temp[f].min() <= 10.0
    assert temp[held].min() >= 10.0 and temp[held].max() < 70.0  # ends always trained
    assert 0 not in held and 160 not in held


def test_blocked_cv_refuses_to_reward_memorising_neighbours():
    """On a dense noisy quadratic, a table with a knot at every point fits
    in-sample perfectly, but across held-out blocks it can only bridge
    linearly: the quadratic must win the blocked CV."""
    rng = np.random.default_rng(7)
    temp = np.linspace(-20.0, 60.0, 161)
    y = 0.2 * (temp - 20.0) ** 2 + rng.normal(0.0, 1.0, temp.size)
    big = score_sizes("pwl", [161], temp, y)[0]
    quad = score_sizes("poly", [2], temp, y)[0]
    assert big.fit_rms < 1e-6                                   # memorised
    assert quad.cv_rms < 1.5 and big.cv_rms > 2 * quad.cv_rms   # but does not generalise
    scores = score_sizes("poly", range(1, 7), temp, y)
    assert choose(scores).size == 2


def test_blocked_cv_prefers_a_table_on_a_kinked_curve():
    temp = np.linspace(0.0, 40.0, 201)
    y = np.interp(temp, [0, 10, 20, 30, 40], [0, 100, -50, 20, 0])
    tab = score_sizes("pwl", [5], temp, y)[0]
    assert tab.cv_rms < 1e-9                                    # knots on the kinks
    polys = score_sizes("poly", range(1, 9), temp, y)
    assert min(s.cv_rms for s in polys) > 5.0


def test_cv_equals_manual_fold_loop():
    rng = np.random.default_rng(1)
    temp = np.sort(rng.uniform(0, 50, 120))
    y = np.sin(temp / 8.0) * 30 + rng.normal(0, 0.5, temp.size)
    cv, per_fold = cross_validate(poly_fitter(3), temp, y, n_blocks=6)
    resid = []
    for f in blocked_folds(temp, 6):
        keep = np.setdiff1d(np.arange(temp.size), f)
        c = np.polyfit(temp[keep], y[keep], 3)
        resid.append(y[f] - np.polyval(c, temp[f]))
    assert cv == pytest.approx(np.sqrt(np.mean(np.concatenate(resid) ** 2)), rel=1e-9)
    assert len(per_fold) == 4


def test_pwl_cv_bridges_held_out_knots():
    temp = np.linspace(0.0, 40.0, 81)
    y = 3.0 * temp - 7.0                                        # a line: bridging is exact
    cv, _ = cross_validate(pwl_fitter(41), temp, y)
    assert cv < 1e-9


# ---- the magnetometer paper's four points -----------------------------------------------------

def test_paper_points_nearest_when_the_data_covers_them():
    temp = np.linspace(-10.0, 80.0, 91)
    pts = paper_points(temp)
    assert pts.mode == "nearest"
    assert list(temp[pts.index]) == list(PAPER_TEMPS)


def test_paper_points_spread_over_a_narrow_range_and_distinct():
    temp = np.linspace(6.0, 41.0, 36)
    pts = paper_points(temp)
    assert pts.mode == "spread"
    assert list(temp[pts.index]) == [6.0, 18.0, 31.0, 41.0]
    assert len(set(pts.index)) == 4
    with pytest.raises(InsufficientDataError, match="4 distinct"):
        paper_points([1.0, 2.0, 3.0])


def test_four_point_study_exact_on_a_cubic():
    temp = np.linspace(-10.0, 80.0, 91)
    y = 0.001 * temp ** 3 - 0.1 * temp ** 2 + temp
    pts, res = four_point_study(temp, y)
    by = {r.order: r for r in res}
    assert by[3].points_rms < 1e-9 and by[3].dense_rms < 1e-6   # a cubic through 4 points
    assert by[2].dense_rms > by[3].dense_rms
    assert np.isnan(by[3].loo_rms)                              # 3 points cannot test order 3
    assert np.isfinite(by[1].loo_rms) and np.isfinite(by[2].loo_rms)


def test_four_point_loo_choice_on_a_quadratic():
    temp = np.linspace(-10.0, 80.0, 91)
    y = 0.02 * (temp - 30.0) ** 2 + 0.5 * temp
    pts, res = four_point_study(temp, y)
    by = {r.order: r for r in res}
    assert by[2].loo_rms < 1e-9 and four_point_choice(res).order == 2
    # leave-one-out by hand for order 1
    tp, yp = temp[pts.index], y[pts.index]
    e = [yp[i] - np.polyval(np.polyfit(np.delete(tp, i), np.delete(yp, i), 1), tp[i])
         for i in range(4)]
    assert by[1].loo_rms == pytest.approx(np.sqrt(np.mean(np.square(e))))


# ---- the real curve -----------------------------------------------------------------

def test_real_mpu6000_curve():
    path = require_shared_data(MPU)
    with warnings.catch_warnings():
        warnings.simplefilter("error")                          # no repeats in this file
        curve = load_curve(path, "temp_c", ["gyro_x", "gyro_y", "gyro_z"])
    assert curve.temp.size == 184 and not curve.notes
    x = curve.axis("gyro_x")
    polys = score_sizes("poly", range(1, 9), curve.temp, x)
    # the x offset rises then falls: order 2 cannot follow it, blocked CV
    # picks a higher order (PROVENANCE.md)
    assert choose(polys).size > 2
    assert polys[1].cv_rms > 2 * choose(polys).cv_rms
    pts, res = four_point_study(curve.temp, x)
    assert pts.mode == "spread"                                  # 6.7-41.1 °C only
    assert {r.order for r in res} == {1, 2, 3}
    # four points cannot see the hump: their own leave-one-out picks a line,
    # which misses the dense curve by far more than the blocked-CV choice
    assert four_point_choice(res).order == 1
    assert res[0].dense_rms > 5 * choose(polys).cv_rms


from hypothesis import given, settings, strategies as st  # noqa: E402


@settings(max_examples=150, deadline=None)
@given(st.lists(st.floats(-40, 120), min_size=5, max_size=200, unique=True), st.integers(3, 12))
def test_folds_partition_the_interior(temps, n_blocks):
    temp = np.sort(np.array(temps))
    if temp[-1] - temp[0] < 1e-6:
        return
    try:
        folds = blocked_folds(temp, n_blocks)
    except InsufficientDataError:
        return                                            # no point inside the interior blocks
    width = (temp[-1] - temp[0]) / n_blocks
    held = np.concatenate(folds)
    assert np.unique(held).size == held.size
    assert temp[held].min() >= temp[0] + width * (1 - 1e-9)
    assert temp[held].max() < temp[-1] - width * (1 - 1e-9)
    for f in folds:                                      # one block each, contiguous
        assert np.all(np.diff(f) == 1)
        assert temp[f].max() - temp[f].min() <= width * (1 + 1e-9)
    # every interior point is held out exactly once
    interior = np.flatnonzero((temp >= temp[0] + width * (1 + 1e-9))
                              & (temp < temp[-1] - width * (1 + 1e-9)))
    assert set(interior) <= set(held)
