"""The static analysers over csrc/ with zero findings as the bar: cppcheck
(warning, performance and portability checks; style is the project's own
choice, e.g. declarations at the top of a block) and gcc -fanalyzer, in
every sig_real form (float, double, fixed-only).  Both run in well under a
minute.  Each also gets a planted defect, so a tool that silently checks
nothing fails the test instead of passing it."""
import subprocess

import pytest

from conftest import CSRC, CSRC_INCLUDE, c_sources, require_tool

AREAS = sorted(d for d in CSRC.iterdir() if d.is_dir() and d.name not in ("include", "port"))
PORTS = [CSRC / "port" / "mcs51"]
PRIVATE_INCLUDES = sorted({p.parent for p in CSRC.rglob("*.h")} - {CSRC_INCLUDE})
REAL_FORMS = {"float": [], "double": ["-DSIG_REAL_DOUBLE"], "fixed-only": ["-DSIG_NO_FLOAT"]}

PLANTED = """#include <stddef.h>
#include <stdint.h>
int32_t planted(const int32_t *p, int n)
{
    int32_t buf[4];
    int32_t acc;
    if (p == NULL) return *p;
    if (n > 2) acc = 1;
    buf[4] = acc;
    return buf[0];
}
"""


def cppcheck_cmd(cppcheck, paths):
    # SIG_PORT_HEADER names a target's header: never set for the portable core
    return [cppcheck, "--enable=warning,performance,portability", "--std=c99", "--quiet",
            "--error-exitcode=1", "--inline-suppr", "-USIG_PORT_HEADER",
            f"-I{CSRC_INCLUDE}", *[f"-I{d}" for d in PRIVATE_INCLUDES], *map(str, paths)]


def test_cppcheck_finds_nothing():
    cppcheck = require_tool("cppcheck")
    res = subprocess.run(cppcheck_cmd(cppcheck, AREAS + PORTS), capture_output=True, text=True,
                         timeout=300)
    findings = (res.stdout + res.stderr).strip()
    assert res.returncode == 0 and not findings, findings


def test_cppcheck_finds_a_planted_defect(tmp_path):
    cppcheck = require_tool("cppcheck")
    (tmp_path / "planted.c").write_text(PLANTED)
    res = subprocess.run(cppcheck_cmd(cppcheck, [tmp_path]), capture_output=True, text=True,
                         timeout=300)
    assert res.returncode != 0 and "planted.c" in res.stdout + res.stderr


def fanalyzer(gcc, src, flags, out):
    res = subprocess.run([gcc, "-std=c99", "-O1", "-fanalyzer", *flags, f"-I{CSRC_INCLUDE}",
                          f"-I{src.parent}", "-c", str(src), "-o", str(out)],
                         capture_output=True, text=True, timeout=300)
    return res.returncode, res.stderr


@pytest.mark.parametrize("form", sorted(REAL_FORMS))
def test_gcc_fanalyzer_finds_nothing(form, tmp_path):
    gcc = require_tool("gcc")
    found = []
    for src in c_sources() + sorted((CSRC / "port" / "mcs51").glob("*.c")):
        rc, err = fanalyzer(gcc, src, REAL_FORMS[form], tmp_path / "x.o")
        if rc != 0 or "warning" in err or "error" in err:
            found.append(err.strip() or f"{src.name}: exit {rc}")
    assert not found, "\n".join(found)


def test_gcc_fanalyzer_finds_a_planted_defect(tmp_path):
    gcc = require_tool("gcc")
    src = tmp_path / "planted.c"
    src.write_text(PLANTED)
    _, err = fanalyzer(gcc, src, [], tmp_path / "x.o")
    assert "-Wanalyzer-" in err, err
