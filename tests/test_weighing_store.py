"""A scale calibration stored as JSON and as a C header: the header compiled
with csrc/weigh/sig_scale.c gives the Python reference's Q16.16 masses bit for bit."""
import json
import subprocess

import numpy as np
import pytest

from conftest import CSRC_INCLUDE, c_source, require_tool
from pysig.cli import main
from pysig.errors import ModelFileError
from pysig.io import write_csv
from spec import scale as ref
from pysig.sim._loadcell import LoadCellParams, simulate
from pysig.weigh._calibration import calibrate, load_calibration

MASSES = np.arange(10.0, 50.1, 5.0)


def readings(n=5):
    """n raw readings at each standard mass, as a calibration session records them."""
    p = LoadCellParams(noise_uv_rms=1.0, nonlinearity_frac_fs=0.0002)
    kg, counts = [], []
    for i, m in enumerate(MASSES):
        run = simulate(p, seed=i, load_steps=((0.0, float(m)),), duration_s=n / p.rate_hz)
        kg += [m] * n
        counts += list(run["counts"])
    return np.array(kg), np.array(counts)


def test_json_round_trip(tmp_path):
    kg, counts = readings()
    cal = calibrate(counts, kg)
    cal.save(tmp_path / "cal.json")
    back = load_calibration(tmp_path / "cal.json")
    assert back == cal
    d = json.loads((tmp_path / "cal.json").read_text())
    assert (d["fixed"]["offset"], d["fixed"]["gain_mant"], d["fixed"]["gain_shift"]) == cal.fixed()


@pytest.mark.parametrize("text, match", [
    ("not json", "not a JSON"),
    ('{"kind": "other"}', "not a scale calibration"),
    ('{"kind": "pysig.scale_calibration", "version": 9}', "version 9"),
    ('{"kind": "pysig.scale_calibration", "version": 1, "unit": "kg"}', "missing"),
    ('{"kind": "pysig.scale_calibration", "version": 1, "unit": "kg", "offset_counts": 1, "gain": 0,'
     ' "linearity_err_pct_fs": 0, "residual_rms": 0, "full_scale": 50}', "gain non-zero"),
])
def test_bad_calibration_files(tmp_path, text, match):
    path = tmp_path / "cal.json"
    path.write_text(text)
    with pytest.raises(ModelFileError, match=match):
        load_calibration(path)
    with pytest.raises(ModelFileError, match="cannot read"):
        load_calibration(tmp_path / "missing.json")


def test_cli_header_compiles_and_matches_reference(tmp_path, capsys):
    gcc = require_tool("gcc")
    kg, counts = readings()
    write_csv(tmp_path / "readings.csv", {"kg": kg, "counts": counts})
    assert main(["calibrate-scale", str(tmp_path / "readings.csv"), "-o", str(tmp_path / "cal.json"),
                 "--header", str(tmp_path / "cal.h")]) in (0, None)
    out = capsys.readouterr().out
    assert "counts/kg" in out and "linearity error" in out
    cal = load_calibration(tmp_path / "cal.json")
    assert cal.counts_per_unit == pytest.approx(LoadCellParams().counts_per_kg, rel=1e-3)

    prog = tmp_path / "apply.c"
    prog.write_text("""#include <stdio.h>
#include <stdlib.h>
#include "cal.h"
int main(int argc, char **argv) {
    sig_scale_q16 q; sig_scale_f f; int i;
    if (sig_scale_init_q16(&q, SCALE_CAL_OFFSET, SCALE_CAL_GAIN_MANT, SCALE_CAL_GAIN_SHIFT)) return 2;
    if (sig_scale_init_f(&f, SCALE_CAL_OFFSET_F, SCALE_CAL_GAIN_F)) return 3;
    for (i = 1; i < argc; i++) {
        int32_t m; sig_real mf;
        sig_status st = sig_scale_apply_q16(&q, (int32_t)strtol(argv[i], NULL, 10), &m);
        sig_scale_apply_f(&f, (sig_real)strtol(argv[i], NULL, 10), &mf);
        printf("%ld %d %.17g\\n", (long)m, (int)st, (double)mf);
    }
    return 0;
}
""")
    exe = tmp_path / "apply"
    res = subprocess.run([gcc, "-std=c99", "-Wall", "-Wextra", "-Werror", "-DSIG_REAL_DOUBLE",
                          "-I", str(CSRC_INCLUDE), "-I", str(tmp_path), str(prog), str(c_source("sig_scale")),
                          "-o", str(exe)], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    codes = [int(c) for c in counts[::7]] + [-(1 << 23), (1 << 23) - 1, 0]
    res = subprocess.run([str(exe), *map(str, codes)], capture_output=True, text=True, check=True)
    rows = [line.split() for line in res.stdout.splitlines()]
    off, mant, shift = cal.fixed()
    want, sat = ref.apply_q16(codes, off, mant, shift)
    assert [int(r[0]) for r in rows] == want.tolist()
    assert [int(r[1]) for r in rows] == [2 if s else 0 for s in sat]
    np.testing.assert_allclose([float(r[2]) for r in rows], cal.to_mass(codes), rtol=1e-15, atol=1e-12)
    # the fixed mass agrees with the float mass within half a code plus a Q16 step
    np.testing.assert_allclose(want / 65536.0, cal.to_mass(codes), atol=0.5 * abs(cal.gain) + 2**-16)
