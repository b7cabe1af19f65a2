"""The default chain's numbers are written once, in C (sig_chain_params_auto_f /
sig_chain_params_auto_q, csrc/weigh/sig_chain_auto.c): the library's auto
preset (pysig.weigh._presets, what Chain() runs) must give the very same
sig_chain_params_* fields, float and fixed."""
from pysig.weigh._chain import auto_params
from pysig.weigh import chain_fixed_params, chain_params

# chain_params() names -> sig_chain_params_f fields
FLOAT_FIELDS = {"A0": "a0", "window": "window", "Q": "q", "R": "r", "P0": "p0", "x0": "x0",
                "seed_first": "seed_first", "stable_step": "stable_step",
                "stable_count": "stable_count", "lockout_n": "lockout_n",
                "motion_band": "motion_band", "motion_count": "motion_count",
                "zero_band": "zero_band", "zero_rate": "zero_rate", "noise_auto": "noise_auto"}


def test_float_auto_preset_is_the_c_constructor():
    p = chain_params("auto")
    assert {FLOAT_FIELDS[k]: p[k] for k in FLOAT_FIELDS} == auto_params(fixed=False)


def test_fixed_auto_preset_is_the_c_constructor():
    assert chain_fixed_params(chain_params("auto")) == auto_params(fixed=True)


def test_a_changed_preset_number_is_caught():
    # the comparison sees every field: one number off and the dicts differ
    c = auto_params(fixed=True)
    p = chain_fixed_params(chain_params("auto", stable_count=6))
    assert p != c and {k for k in c if p[k] != c[k]} == {"stable_count"}
