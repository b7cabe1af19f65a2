"""Fuzz every C entry point that takes outside data.

Each fuzz/fuzz_<target>.c is a libFuzzer harness.  It is built with clang
and AddressSanitizer + UndefinedBehaviorSanitizer (no recovery: the first
report aborts) against all of csrc/*.c in the firmware's float form, then
run for PYSIG_FUZZ_SECONDS (default 15 s when CI is set, the time each harness must survive,
kept so the whole CI run stays within its 20-minute budget;
10 s otherwise), starting from its seed corpus fuzz/corpus/<target>/.  Each
harness also runs for a sixth of that time (the small, fully covered targets
in FUZZ_SHARE a fraction of it) in a
MemorySanitizer build (reads of uninitialised memory).  A crash, a sanitizer
report, a timeout, an out-of-memory or a failed invariant (the harnesses
abort) fails the test and names the crashing input.  Executions run and the
coverage reached (libFuzzer's cov: edges and ft: features) are printed and
written to fuzz/build/fuzz-summary.json.
"""
import json
import os
import re
import shutil
import subprocess

import pytest

from conftest import CSRC_INCLUDE, ROOT, c_sources, require_tool

FUZZ_DIR = ROOT / "fuzz"
BUILD_DIR = FUZZ_DIR / "build"
SUMMARY = BUILD_DIR / "fuzz-summary.json"
HARNESSES = sorted(FUZZ_DIR.glob("fuzz_*.c"))
SANITIZE = ["-fsanitize=fuzzer,address,undefined", "-fno-sanitize-recover=all", "-g", "-O1"]
# MemorySanitizer sees reads of uninitialised values, which ASan does not
# (it found the chain using an unset Kalman estimate); it cannot be combined
# with ASan, so each harness also runs briefly in an MSan build.
SANITIZE_MSAN = ["-fsanitize=fuzzer,memory", "-fsanitize-memory-track-origins",
                 "-fno-sanitize-recover=all", "-g", "-O1"]
MSAN_SHARE = 1 / 6
FAILURE_MARKERS = ("ERROR: AddressSanitizer", "ERROR: UndefinedBehaviorSanitizer",
                   "runtime error:", "ERROR: libFuzzer", "deadly signal", "SUMMARY: ",
                   "WARNING: MemorySanitizer")
DONE_RE = re.compile(r"^#(\d+)\s+DONE\s+cov: (\d+) ft: (\d+) corp: (\d+)/", re.M)
# Targets whose coverage saturates within seconds: a fraction of the MSan time.
FUZZ_SHARE = {"types": 0.25, "scale": 0.25, "pwl": 0.5}
PROGRESS_RE = re.compile(r"^#(\d+)\s+\w+\s+cov: (\d+) ft: (\d+) corp: (\d+)/", re.M)


def fuzz_seconds():
    if os.environ.get("PYSIG_FUZZ_SECONDS"):
        return int(os.environ["PYSIG_FUZZ_SECONDS"])
    return 15 if os.environ.get("CI") else 10


def target_name(harness):
    return harness.stem[len("fuzz_"):]


@pytest.fixture(scope="module")
def clang():
    cc = require_tool("clang-14", "clang")
    BUILD_DIR.mkdir(parents=True, exist_ok=True)
    probe = BUILD_DIR / "probe.c"
    probe.write_text("#include <stdint.h>\n#include <stddef.h>\n"
                     "int LLVMFuzzerTestOneInput(const uint8_t *d, size_t n)"
                     "{ (void)d; (void)n; return 0; }\n")
    res = subprocess.run([cc, *SANITIZE, str(probe), "-o", str(BUILD_DIR / "probe")],
                         capture_output=True, text=True)
    if res.returncode != 0:
        msg = "clang cannot link the libFuzzer runtime (install libclang-rt-14-dev):\n" + res.stderr
        if os.environ.get("CI"):
            pytest.fail(msg)
        pytest.skip(msg)
    return cc


_CORE_OBJECTS = {}


def core_objects(cc, flags, suffix):
    """csrc/*.c compiled once per session and sanitizer build, instrumented
    for libFuzzer's coverage (fuzzer-no-link: no main); every harness of
    that build links them.  Compiling the core for each harness took most of
    the non-fuzzing time of a CI run."""
    if suffix not in _CORE_OBJECTS:
        objdir = BUILD_DIR / f"core{suffix}"
        shutil.rmtree(objdir, ignore_errors=True)
        objdir.mkdir(parents=True)
        sources = c_sources()
        compile_flags = [f.replace("-fsanitize=fuzzer,", "-fsanitize=fuzzer-no-link,") for f in flags]
        cmd = [cc, *compile_flags, "-std=c99", "-I", str(CSRC_INCLUDE), "-c", *map(str, sources)]
        res = subprocess.run(cmd, capture_output=True, text=True, cwd=objdir)
        assert res.returncode == 0, " ".join(cmd) + "\n" + res.stdout + res.stderr
        _CORE_OBJECTS[suffix] = [objdir / (src.stem + ".o") for src in sources]
    return _CORE_OBJECTS[suffix]


def build_harness(cc, harness, flags=SANITIZE, suffix=""):
    exe = BUILD_DIR / (harness.stem + suffix)
    cmd = [cc, *flags, "-std=c99", "-I", str(CSRC_INCLUDE), "-I", str(FUZZ_DIR),
           str(harness), *map(str, core_objects(cc, flags, suffix)), "-o", str(exe)]
    res = subprocess.run(cmd, capture_output=True, text=True)
    assert res.returncode == 0, " ".join(cmd) + "\n" + res.stdout + res.stderr
    return exe


def parse_run(output):
    """Executions, coverage and corpus size from libFuzzer's stderr."""
    done = DONE_RE.findall(output) or PROGRESS_RE.findall(output)
    stats = dict(re.findall(r"^stat::(\w+):\s+(\d+)", output, re.M))
    if not done:
        return None
    runs, cov, ft, corp = map(int, done[-1])
    return {"executions": int(stats.get("number_of_executed_units", runs)),
            "exec_per_sec": int(stats.get("average_exec_per_sec", 0)),
            "cov": cov, "ft": ft, "corpus_units": corp,
            "new_units": int(stats.get("new_units_added", 0)),
            "peak_rss_mb": int(stats.get("peak_rss_mb", 0))}


def write_summary(target, record):
    try:
        summary = json.loads(SUMMARY.read_text())
    except (OSError, ValueError):
        summary = {}
    summary[target] = record
    SUMMARY.write_text(json.dumps(summary, indent=2, sort_keys=True) + "\n")


def describe_crash(workdir, target):
    """Name each crashing input and keep a copy in fuzz/build/crashes/<target>/."""
    keep = BUILD_DIR / "crashes" / target
    lines = []
    for art in sorted(workdir.glob("crash-*")) + sorted(workdir.glob("timeout-*")) \
            + sorted(workdir.glob("oom-*")) + sorted(workdir.glob("leak-*")):
        data = art.read_bytes()
        keep.mkdir(parents=True, exist_ok=True)
        shutil.copy(art, keep / art.name)
        lines.append(f"crashing input {keep / art.name} ({len(data)} bytes): {data[:256].hex()}")
    return "\n".join(lines)


def test_every_harness_has_a_seed_corpus():
    assert HARNESSES, "no fuzz/fuzz_*.c harness"
    for harness in HARNESSES:
        seeds = FUZZ_DIR / "corpus" / target_name(harness)
        assert seeds.is_dir() and any(seeds.iterdir()), f"{harness.name}: no seed corpus in {seeds}"


# Harness runs that fail because another owner's fix has not landed (their
# regression seeds crash at once): strict xfail naming the file and the fix,
# keyed by "<target>" (ASan+UBSan run) or "<target>-msan".
KNOWN_GAPS = {
}


def params(suffix=""):
    out = []
    for h in HARNESSES:
        reason = KNOWN_GAPS.get(target_name(h) + suffix)
        marks = [pytest.mark.xfail(strict=True, reason=reason)] if reason else []
        out.append(pytest.param(h, id=target_name(h), marks=marks))
    return out


def run_fuzzer(exe, target, seconds, tmp_path, key):
    """Run one harness from its seeds; record and print executions and
    coverage under `key` in the summary; fail on any report."""
    seeds = FUZZ_DIR / "corpus" / target
    work = tmp_path / "corpus"
    work.mkdir()
    cmd = [str(exe), f"-max_total_time={seconds}", "-print_final_stats=1", "-timeout=10",
           "-rss_limit_mb=2048", "-max_len=4096", f"-artifact_prefix={tmp_path}/",
           str(work), str(seeds)]
    env = dict(os.environ, ASAN_OPTIONS="abort_on_error=0:detect_leaks=1",
               UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1",
               MSAN_OPTIONS="print_stacktrace=1:halt_on_error=1")
    res = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=seconds + 120)
    output = res.stdout + res.stderr
    stats = parse_run(output)
    record = {"seconds": seconds, "seed_files": len(list(seeds.iterdir())),
              "returncode": res.returncode, "ok": False, **(stats or {})}
    failed = res.returncode != 0 or any(m in output for m in FAILURE_MARKERS)
    record["ok"] = not failed and stats is not None
    write_summary(key, record)
    print(f"\nfuzz {key}: {record.get('executions')} executions in {seconds} s, "
          f"cov {record.get('cov')} ft {record.get('ft')}, corpus {record.get('corpus_units')}")
    if failed:
        tail = "\n".join(output.splitlines()[-60:])
        pytest.fail(f"fuzz_{key} failed (exit {res.returncode})\n{describe_crash(tmp_path, key)}\n"
                    f"reproduce: {exe} <crash file>\n{tail}")
    assert stats is not None, "no libFuzzer statistics in the output:\n" + output[-3000:]
    assert stats["executions"] > 0
    shutil.rmtree(work, ignore_errors=True)


@pytest.mark.parametrize("harness", params())
def test_fuzz(harness, clang, tmp_path):
    target = target_name(harness)
    exe = build_harness(clang, harness)
    run_fuzzer(exe, target, fuzz_seconds(), tmp_path, target)


@pytest.mark.parametrize("harness", params("-msan"))
def test_fuzz_msan(harness, clang, tmp_path):
    target = target_name(harness)
    exe = build_harness(clang, harness, SANITIZE_MSAN, "_msan")
    seconds = max(1, round(fuzz_seconds() * FUZZ_SHARE.get(target, 1.0) * MSAN_SHARE))
    run_fuzzer(exe, target, seconds, tmp_path, target + "-msan")
