"""The C core as an Arduino / PlatformIO library: arduino/make_library.py
lays it out from csrc/ (one copy of the code), the manifests say what the
Library Manager and PlatformIO need, both examples build for the
ATmega328P warning-free with gcc-avr, avr-libc and Debian's Arduino core,
and run in simavr: the scale's stable flags and the compensated readings
(calibration image installed into EEPROM slot A on a blank chip, CRC
checked, loaded) equal the host C."""
import json
import os
import re
import subprocess
import tomllib
from pathlib import Path

import numpy as np
import pytest

from conftest import ROOT, require_target_tools, require_tool
from lab.mcu.build_arduino import CORE, build_sketch

ARDUINO = ROOT / "arduino"
EXAMPLES = ("HX711Scale", "CompensatedSensor")


def _make_library(tmp_path):
    import sys
    import pysig
    # the script sees the pysig this test imports (not another checkout's)
    env = dict(os.environ, PYTHONPATH=str(Path(pysig.__file__).resolve().parents[1]))
    subprocess.run([sys.executable, str(ARDUINO / "make_library.py"), str(tmp_path)], check=True,
                   capture_output=True, cwd=ROOT, env=env)
    return tmp_path / "SigCore"


@pytest.fixture(scope="module")
def library(tmp_path_factory):
    return _make_library(tmp_path_factory.mktemp("arduino"))


def test_manifests_name_the_same_library_and_version(library):
    version = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    props = dict(ln.split("=", 1) for ln in (library / "library.properties").read_text().splitlines() if ln)
    for key in ("name", "version", "author", "maintainer", "sentence", "paragraph", "category", "url",
                "architectures", "includes"):
        assert props.get(key), key
    pio = json.loads((library / "library.json").read_text())
    assert props["name"] == pio["name"] == "SigCore"
    assert props["version"] == pio["version"] == version
    assert props["includes"] == pio["headers"] == "SigCore.h"
    for ex in pio["examples"]:
        for f in ex["files"]:
            assert (library / ex["base"] / f).exists()


def test_src_is_csrc_flattened(library):
    src = library / "src"
    expected = {f.name for f in (ROOT / "csrc" / "include").glob("*.h")}
    for area in (ROOT / "csrc").iterdir():
        if area.is_dir() and area.name not in ("include", "port"):
            expected |= {f.name for f in [*area.glob("*.c"), *area.glob("*.h")]}
    generated = {"SigCore.h", "sig_chain_defaults.h"}
    assert {f.name for f in src.iterdir()} == expected | generated
    for name in expected:     # byte for byte: no fork
        origin = next(ROOT.glob(f"csrc/*/{name}"))
        assert (src / name).read_bytes() == origin.read_bytes(), name


def test_chain_defaults_are_the_package_default(library, tmp_path):
    from pysig.weigh import chain_fixed_params, chain_params
    gcc = require_tool("gcc")
    fields = chain_fixed_params(chain_params("auto"))
    prog = tmp_path / "dump.c"
    prog.write_text('#include <stdio.h>\n#include "sig_chain_defaults.h"\nint main(void) {\n'
                    "    sig_chain_params_q p;\n    sig_chain_defaults_q(&p);\n"
                    + "".join(f'    printf("{k} %ld\\n", (long)p.{k});\n' for k in fields)
                    + "    return 0;\n}\n")
    subprocess.run([gcc, "-std=c99", "-Wall", "-Wextra", "-Werror", f"-I{library / 'src'}", str(prog),
                    "-o", str(tmp_path / "dump")], check=True)
    out = subprocess.run([str(tmp_path / "dump")], capture_output=True, text=True, check=True).stdout
    assert {k: int(v) for k, v in (ln.split() for ln in out.splitlines())} == \
        {k: int(v) for k, v in fields.items()}


def _require_arduino():
    require_target_tools("avr")
    require_tool("avr-g++")
    if not (CORE / "Arduino.h").exists():
        msg = "the Arduino core is not installed (Debian package arduino-core-avr)"
        if os.environ.get("CI"):
            pytest.fail(msg + " (CI must install it: see .ci/run)")
        pytest.skip(msg)


def _uart_lines(elf, seconds):
    """What the sketch prints in simavr in `seconds` of wall time (it never ends)."""
    r = subprocess.run(["timeout", str(seconds), "simavr", "-m", "atmega328p", "-f", "16000000",
                        str(elf)], capture_output=True, text=True)
    text = re.sub(r"\x1b\[[0-9;]*m", "", r.stdout + r.stderr)
    return [ln[:-2] for ln in text.splitlines() if ln.endswith("..")]   # simavr shows "\r\n" as ".."


_BUILT = {}


def _sketch(library, example):
    """build_sketch once per example for this module (the run tests reuse it)."""
    _require_arduino()
    if example not in _BUILT:
        _BUILT[example] = build_sketch(library, example)
    return _BUILT[example]


@pytest.mark.parametrize("example", EXAMPLES)
def test_example_builds_for_the_atmega328p(library, example):
    r = _sketch(library, example)
    assert 0 < r["flash_bytes"] <= 32256 and 0 < r["ram_bytes"] <= 2048


def test_scale_example_runs_the_default_chain(library):
    """simavr's unconnected DOUT reads low: ready, all-zero codes; the
    printed stable flags follow the host chain on zeros, tare applied."""
    _require_arduino()
    from pysig.weigh import Chain
    lines = _uart_lines(_sketch(library, "HX711Scale")["elf"], 3)[:40]
    assert len(lines) >= 20
    _, stable, _ = Chain("auto", fixed=True).process(np.zeros(len(lines)), flags=True)
    assert [ln.split()[0] for ln in lines] == ["0.000"] * len(lines)
    assert [ln.split()[1] == "stable" for ln in lines] == list(stable)
    assert "(tare pending)" not in lines[-1]


def test_compensated_sensor_installs_and_loads_the_factory_image(library):
    _require_arduino()
    from pysig.tcomp._tmodel import TModel
    lines = _uart_lines(_sketch(library, "CompensatedSensor")["elf"], 3)
    assert lines[0] == "calibration slot A, status 0"
    header = (library / "examples" / "CompensatedSensor" / "factory_calibration.h").read_text()
    image = bytes(int(b, 16) for b in re.findall(r"0x([0-9a-f]{2})", header))
    t, *out, _, st = lines[1].split()
    h_out, h_st = TModel.from_image(image).apply(np.array([int(t) & 0xFFFF]), np.zeros((1, 3), np.int16))
    assert [int(v) for v in out] == list(h_out[0]) and int(st) == h_st[0]
