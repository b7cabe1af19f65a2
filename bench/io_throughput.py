"""`pysig filter` end to end on a large CSV against the floor measured in the
same run, and peak memory.

The input is an HX711-like log (time in s, integer counts: steps, noise,
read glitches), 5 M rows by default (~90 MB of CSV).  Each figure is one
process, timed from its start to its exit, peak memory the process's own
VmHWM (peak resident set, read from /proc/self/status as it exits):

* floor: pyarrow.csv.read_csv of the file (counts as float64), the chain
  (pysig.weigh.Chain, the C core) over the counts column, pyarrow.csv.write_csv
  of the input columns plus `filtered` and `stable`, numpy and arrow
  exchanging buffers (pyarrow's pa.array/to_numpy would import pandas): what
  the job costs with nothing of pysig's checks or streaming;
* pysig: `pysig filter IN --column counts -o OUT` (streaming, the default)
  and with --in-memory, run as `python -m pysig` does (pysig.cli.main);
* each also in CPU seconds (user + system of the process): on a shared
  machine the wall clock carries other people's load, the CPU time less so;
* streaming at --big-rows (50 M by default; --big-rows 0 skips it).

ratio = pysig_s / floor_s.  output_column_mb is the output's column data in
memory (rows x 4 columns x 8 bytes): the in-memory goal is peak_rss_mb <= 3x
that, the streaming goal peak_rss_mb <= 300 MB at 50 M rows.  The machine
may be shared: the 1-minute load average is recorded beside each row.

    python bench/io_throughput.py --json bench/results/io_throughput.json
"""
import argparse
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np
import pyarrow as pa
import pyarrow.csv as pcsv

from pysig.io import write_json

FLOOR = """
import sys
import numpy as np, pyarrow as pa, pyarrow.csv as pcsv
from pysig.weigh import Chain
t = pcsv.read_csv(sys.argv[1], convert_options=pcsv.ConvertOptions(column_types={"counts": pa.float64()}))
c = t.column("counts").combine_chunks()
x = np.frombuffer(c.buffers()[1], dtype=np.float64, count=len(c), offset=c.offset * 8)
y, stable = Chain().process(x)
stable = stable.astype(np.int64)
arr = lambda a: pa.Array.from_buffers(pa.from_numpy_dtype(a.dtype), a.size, [None, pa.py_buffer(a)])
t = t.append_column("filtered", arr(y)).append_column("stable", arr(stable))
pcsv.write_csv(t, sys.argv[2])
""" + "\n"
# Peak memory is the child's own VmHWM (/proc/self/status), printed as it
# exits: the kernel's ru_maxrss of a child started by fork/vfork + exec
# carries the parent's peak from before the exec (this script's own arrays).
REPORT_PEAK = """
def _report_peak():
    for line in open("/proc/self/status"):
        if line.startswith("VmHWM:"):
            sys.stderr.write("PEAK_KB=" + line.split()[1] + "\\n")
"""
PYSIG = """
import sys
from pysig.cli import main
status = main(sys.argv[1:])
_report_peak()
sys.exit(status)
"""


def make_log(path, rows, seed=0, block=5_000_000):
    """Write the log in blocks (bounded memory even for 50 M rows)."""
    rng = np.random.default_rng(seed)
    with pcsv.CSVWriter(path, pa.schema([("t", pa.float64()), ("counts", pa.int64())])) as w:
        for start in range(0, rows, block):
            n = min(block, rows - start)
            i = np.arange(start, start + n)
            levels = 5800 + 10000 * rng.integers(0, 5, size=n // 150 + 2)
            counts = levels[(i - start) // 150] + np.round(rng.normal(0, 70, n)).astype(np.int64)
            counts[rng.integers(0, n, size=max(n // 300, 1))] = -8387000
            w.write_table(pa.table({"t": np.round(i * 0.1, 1), "counts": counts}))


def run(cmd):
    """(wall seconds, CPU seconds (user + system), peak RSS MB) of one child
    process that prints PEAK_KB=... on stderr as it exits."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in [ROOT, os.environ.get("PYTHONPATH")] if p))
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    secs = time.perf_counter() - t0
    err = proc.stderr.read().decode()
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed ({proc.returncode}): {err}")
    peak = [line for line in err.splitlines() if line.startswith("PEAK_KB=")]
    return secs, usage.ru_utime + usage.ru_stime, int(peak[-1][8:]) / 1024.0


ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def measure(src, tmp, rows, extra, floor=True):
    out = os.path.join(tmp, "out.csv")
    row = {"rows": rows, "mode": "in-memory" if "--in-memory" in extra else "streaming",
           "input_mb": os.path.getsize(src) / 1e6, "output_column_mb": rows * 4 * 8 / 1e6}
    row["pysig_s"], row["pysig_cpu_s"], row["peak_rss_mb"] = run(
        [sys.executable, "-c", "import sys\n" + REPORT_PEAK + PYSIG, "filter", src, "--column", "counts",
         "-o", out, *extra])
    if floor:
        row["floor_s"], row["floor_cpu_s"], row["floor_peak_rss_mb"] = run(
            [sys.executable, "-c", FLOOR + REPORT_PEAK + "_report_peak()\n", src, os.path.join(tmp, "floor.csv")])
        row["ratio"] = row["pysig_s"] / row["floor_s"]
        row["ratio_cpu"] = row["pysig_cpu_s"] / row["floor_cpu_s"]
    row["load_avg_1min"] = os.getloadavg()[0]
    row["peak_over_output_columns"] = row["peak_rss_mb"] / row["output_column_mb"]
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", type=int, default=5_000_000)
    ap.add_argument("--big-rows", type=int, default=50_000_000)
    ap.add_argument("--json")
    args = ap.parse_args()
    tmp = tempfile.mkdtemp(prefix="pysig-io-bench-")
    try:
        src = os.path.join(tmp, "in.csv")
        make_log(src, args.rows)
        stream = measure(src, tmp, args.rows, [])
        memory = measure(src, tmp, args.rows, ["--in-memory"])
        rows = [stream, memory]
        if args.big_rows:
            big = os.path.join(tmp, "big.csv")
            os.unlink(src)
            make_log(big, args.big_rows, seed=1)
            rows.append(measure(big, tmp, args.big_rows, [], floor=False))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print("| rows | mode | input MB | pysig s (CPU) | floor s (CPU) | ratio (CPU) | peak RSS MB | "
          "output columns MB | load |")
    print("|---:|---|---:|---:|---:|---:|---:|---:|---:|")
    nan = float("nan")
    for r in rows:
        print(f"| {r['rows']:,} | {r['mode']} | {r['input_mb']:.0f} | {r['pysig_s']:.2f} ({r['pysig_cpu_s']:.2f}) | "
              f"{r.get('floor_s', nan):.2f} ({r.get('floor_cpu_s', nan):.2f}) | "
              f"{r.get('ratio', nan):.2f} ({r.get('ratio_cpu', nan):.2f}) | "
              f"{r['peak_rss_mb']:.0f} | {r['output_column_mb']:.0f} | {r['load_avg_1min']:.1f} |")
    out = {**stream, "in_memory": memory, "streaming": rows[2:], "cpus": os.cpu_count(),
           "python": platform.python_version(), "pyarrow": pa.__version__}
    if args.json:
        os.makedirs(os.path.dirname(os.path.abspath(args.json)), exist_ok=True)
        write_json(args.json, out, allow_nan=True)


if __name__ == "__main__":
    main()
