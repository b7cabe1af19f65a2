"""The load-cell simulator puts in exactly what its parameters say: each
disturbance alone is measured back from the codes."""
import numpy as np
import pytest
from scipy import stats

from pysig.errors import RangeError
from pysig.io import read_csv
from pysig.sim._loadcell import ADC_MAX, ADC_MIN, LoadCellParams, simulate, write_run

STEPS = ((0.0, 0.0), (10.0, 30.0), (40.0, 0.0))


def clean_codes(p):
    """What the run should be with every disturbance off."""
    run = simulate(p, seed=0)
    expect = np.rint(p.zero_counts + p.counts_per_kg * run["ref_kg"])
    return run, expect


def excess_uv(p, seed=1, **on):
    """Codes of the run with `on` switched on, minus the clean run, in uV."""
    base = simulate(p, seed=seed)["counts"].astype(float)
    run = simulate(p, seed=seed, **on)
    return run, (run["counts"] - base) * p.lsb_v * 1e6


def test_defaults_are_clean_and_match_the_datasheet_scale():
    p = LoadCellParams(load_steps=STEPS, duration_s=60.0)
    assert p.lsb_v == pytest.approx(2.5 / 128 / 2**23)
    assert p.counts_per_kg == pytest.approx(0.15e-3 / p.lsb_v)
    run, expect = clean_codes(p)
    np.testing.assert_array_equal(run["counts"], expect)
    assert run["t"][1] - run["t"][0] == pytest.approx(0.1)
    assert set(np.unique(run["ref_kg"])) == {0.0, 30.0}
    assert run["ref_kg"][99] == 0.0 and run["ref_kg"][100] == 30.0 and run["ref_kg"][400] == 0.0


def test_seeded_and_reproducible():
    p = LoadCellParams(noise_uv_rms=5.0, impulse_rate_hz=1.0, impulse_amp_uv=300.0, drift_rw_uv=0.5)
    a, b, c = simulate(p, seed=7), simulate(p, seed=7), simulate(p, seed=8)
    np.testing.assert_array_equal(a["counts"], b["counts"])
    assert not np.array_equal(a["counts"], c["counts"])


def test_white_noise_rms():
    p = LoadCellParams(duration_s=600.0)
    _, e = excess_uv(p, noise_uv_rms=3.0)
    # 6000 samples: chi-square interval of the standard deviation, 1e-6 two-sided
    n = e.size
    lo, hi = (np.sqrt(stats.chi2.ppf(q, n - 1) / (n - 1)) for q in (5e-7, 1 - 5e-7))
    assert 3.0 * lo - 0.01 <= np.std(e, ddof=1) <= 3.0 * hi + 0.01
    assert abs(stats.skew(e)) < 0.2


@pytest.mark.parametrize("polarity", ["+", "-", "both"])
def test_impulses_rate_amplitude_polarity(polarity):
    p = LoadCellParams(duration_s=600.0, rate_hz=10.0)
    _, e = excess_uv(p, impulse_rate_hz=0.5, impulse_amp_uv=400.0, impulse_polarity=polarity)
    hits = np.abs(e) > 1.0
    assert stats.binomtest(int(hits.sum()), e.size, 0.05).pvalue > 1e-6
    amps = np.abs(e[hits])
    assert amps.min() >= 200.0 - 0.01 and amps.max() <= 400.0 + 0.01
    signs = set(np.sign(e[hits]).astype(int))
    assert signs == {"+": {1}, "-": {-1}, "both": {-1, 1}}[polarity]


def test_periodic_pickup_aliases():
    p = LoadCellParams(duration_s=200.0, rate_hz=10.0)
    _, e = excess_uv(p, periodic_amp_uv=50.0, periodic_hz=50.2)
    spec = np.abs(np.fft.rfft(e))
    f = np.fft.rfftfreq(e.size, 1 / p.rate_hz)
    assert f[np.argmax(spec)] == pytest.approx(0.2, abs=0.01)
    assert np.max(np.abs(e)) == pytest.approx(50.0, abs=0.05)


def test_zero_drift_linear():
    p = LoadCellParams(duration_s=300.0)
    run, e = excess_uv(p, drift_uv_per_min=2.0)
    slope = np.polyfit(run["t"] / 60.0, e, 1)[0]
    assert slope == pytest.approx(2.0, abs=0.01)


def test_creep_follows_the_step_with_its_time_constant():
    p = LoadCellParams(load_steps=((0.0, 0.0), (10.0, 40.0)), duration_s=400.0)
    run, e = excess_uv(p, creep_frac=0.001, creep_tau_s=30.0)
    kg = e / p.uv_per_kg()
    t = run["t"]
    assert np.all(kg[t < 10.0] == 0)
    at_tau = kg[np.argmin(np.abs(t - 40.0))]
    assert at_tau == pytest.approx(0.04 * (1 - np.exp(-1)), abs=2e-4)   # 40 kg * 0.1 %
    assert kg[-1] == pytest.approx(0.04, abs=2e-4)


def test_nonlinearity_bow():
    p = LoadCellParams(load_steps=((0.0, 25.0),), duration_s=1.0, capacity_kg=50.0)
    _, e = excess_uv(p, nonlinearity_frac_fs=0.0005)
    # at half capacity the bow peaks at 0.05 % of the 50 kg full-scale output
    assert np.median(e) / p.uv_per_kg() == pytest.approx(0.0005 * 50.0, abs=2e-4)
    p_full = LoadCellParams(load_steps=((0.0, 50.0),), duration_s=1.0)
    _, e_full = excess_uv(p_full, nonlinearity_frac_fs=0.0005)
    assert np.all(np.abs(e_full) < 0.01)                                # zero at capacity


def test_ringing_decays():
    p = LoadCellParams(load_steps=((0.0, 0.0), (5.0, 20.0)), duration_s=20.0)
    run, e = excess_uv(p, ringing_frac=0.2, ringing_hz=1.5, ringing_tau_s=0.5)
    kg = e / p.uv_per_kg()
    t = run["t"]
    assert np.max(np.abs(kg[(t >= 5.0) & (t < 6.0)])) > 1.0
    assert np.max(np.abs(kg[t > 10.0])) < 1e-3


def test_codes_clip_at_the_rails():
    p = LoadCellParams(load_steps=((0.0, 200.0),), duration_s=1.0)
    assert np.all(simulate(p)["counts"] == ADC_MAX)
    p = LoadCellParams(load_steps=((0.0, -200.0),), duration_s=1.0)
    assert np.all(simulate(p)["counts"] == ADC_MIN)


def test_rate_80():
    run = simulate(LoadCellParams(rate_hz=80.0, duration_s=2.0))
    assert run["t"].size == 160 and run["t"][1] == pytest.approx(1 / 80)


def test_csv_round_trip(tmp_path):
    p = LoadCellParams(load_steps=STEPS, duration_s=50.0, noise_uv_rms=2.0)
    run = simulate(p, seed=3)
    path = tmp_path / "run.csv"
    write_run(path, run)
    back = read_csv(path)
    assert list(back) == ["t", "counts", "ref_kg"]
    np.testing.assert_array_equal(back["counts"], run["counts"])
    np.testing.assert_array_equal(back["ref_kg"], run["ref_kg"])
    np.testing.assert_allclose(back["t"], run["t"], rtol=0, atol=1e-12)


@pytest.mark.parametrize("bad, match", [
    (dict(rate_hz=0.0), "rate_hz"),
    (dict(noise_uv_rms=-1.0), "noise_uv_rms"),
    (dict(impulse_polarity="up"), "impulse_polarity"),
    (dict(impulse_rate_hz=20.0), "impulse_rate_hz"),
    (dict(load_steps=((1.0, 0.0),)), "load_steps"),
    (dict(load_steps=((0.0, 0.0), (0.0, 5.0))), "load_steps"),
    (dict(creep_frac=float("nan")), "creep_frac"),
])
def test_bad_parameters(bad, match):
    with pytest.raises(RangeError, match=match):
        LoadCellParams(**bad)


def test_vibration_proportional_to_load():
    stds = []
    for kg in (10.0, 40.0):
        p = LoadCellParams(load_steps=((0.0, kg),), duration_s=600.0)
        _, e = excess_uv(p, vibration_g_rms=0.01)
        stds.append(np.std(e) / p.uv_per_kg())
    assert stds[0] == pytest.approx(0.1, rel=0.05)        # 10 kg * 0.01 g
    assert stds[1] == pytest.approx(0.4, rel=0.05)
    p0 = LoadCellParams(duration_s=10.0)
    _, e0 = excess_uv(p0, vibration_g_rms=0.01)
    assert np.all(e0 == 0)                               # nothing on an empty cell


def test_cli_simulate_writes_the_same_run(tmp_path, capsys):
    from pysig.cli import main
    out = tmp_path / "run.csv"
    argv = ["simulate", str(out), "--seed", "4", "--load-steps", "0:0,5:30,20:0",
            "--duration-s", "30", "--noise-uv-rms", "0.3", "--impulse-rate-hz", "0.2",
            "--impulse-amp-uv", "1500", "--impulse-polarity", "+"]
    assert main(argv) in (0, None)
    assert "300 samples" in capsys.readouterr().out
    back = read_csv(out)
    expect = simulate(LoadCellParams(load_steps=((0.0, 0.0), (5.0, 30.0), (20.0, 0.0)), duration_s=30.0,
                                     noise_uv_rms=0.3, impulse_rate_hz=0.2, impulse_amp_uv=1500.0,
                                     impulse_polarity="+"), seed=4)
    np.testing.assert_array_equal(back["counts"], expect["counts"])
    np.testing.assert_array_equal(back["ref_kg"], expect["ref_kg"])


def test_cli_simulate_bad_options(tmp_path, capsys):
    from pysig.cli import main
    out = tmp_path / "run.csv"
    assert main(["simulate", str(out), "--load-steps", "0:0,x"]) == RangeError.exit_status
    assert "t:kg pairs" in capsys.readouterr().err
    assert main(["simulate", str(out), "--rate-hz", "0"]) == RangeError.exit_status
    assert not out.exists()
