"""Write the seed corpora fuzz/corpus/<target>/ (run from the repo root:
`python3 fuzz/make_corpus.py`).  Seeds are the hand-picked starting points
the fuzzer mutates from: rails, zeros, special floats and, for parsers, valid
inputs.  Inputs that once crashed a harness are kept beside them as
regress-* files (written by hand, never by this script)."""
import struct
from pathlib import Path

CORPUS = Path(__file__).resolve().parent / "corpus"

I32_MIN, I32_MAX = -2**31, 2**31 - 1
F_SPECIAL = [0.0, -0.0, 1.0, -1.0, float("nan"), float("inf"), float("-inf"),
             1e-45, -1e-45, 1.1754942e-38, 3.4028235e38, -3.4028235e38, 1e-7, 0.05, 10.0]


def i32(*values):
    return b"".join(struct.pack("<i", v) for v in values)


def f32(*values):
    return b"".join(struct.pack("<f", v) for v in values)


def write(target, name, data):
    d = CORPUS / target
    d.mkdir(parents=True, exist_ok=True)
    (d / name).write_bytes(data)


def edgy(v):
    """fuzz_i32_edgy encoding: selector 5 then raw bits."""
    return b"\x05" + i32(v)


def seeds_types():
    pairs = [(I32_MIN, I32_MIN), (I32_MAX, I32_MAX), (I32_MIN, -1), (65536, 65536),
             (-1, 1), (46341 << 8, 46341 << 8), (-65537, 65535), (0, I32_MIN)]
    for k, (a, b) in enumerate(pairs):
        write("types", f"seed-{k:02d}", edgy(a) + edgy(b) + bytes([k * 4 % 32]))
    write("types", "seed-rails", bytes(range(8)) * 3)


def seeds_pwl():
    import struct as s
    # q16: mode 0, n, shift, vf, derive=1, t_lo, t_hi, recip, table, temperatures
    for k, (n, shift, vf, lo, hi) in enumerate([(2, 0, 8, 0, 1000), (5, 4, 0, -2000, 2000),
                                                (255, 31, 15, -32768, 32767), (17, 10, 4, 100, 101)]):
        tab = [(-1) ** i * (i * 977 % 32768) for i in range(n)]
        data = bytes([0, n, shift, vf, 1]) + s.pack("<hhH", lo, hi, 1) + s.pack(f"<{n}h", *tab)
        data += s.pack("<4h", lo - 1 if lo > -32768 else lo, hi, (lo + hi) // 2, 0)
        write("pwl", f"seed-q16-{k}", data)
    # float: mode 1, n, derive=1, t_lo, t_hi, inv_step (derived), table, temperatures
    for k, (n, lo, hi) in enumerate([(2, -40.0, 85.0), (9, 6.7, 41.1), (255, -1e30, 1e30)]):
        tab = [float(i) * 0.5 - 3 for i in range(n)]
        data = bytes([1, n, 1]) + f32(lo, hi, 0.0) + f32(*tab) + f32(*F_SPECIAL)
        write("pwl", f"seed-f-{k}", data)
    write("pwl", "regress-f-table-diff-overflow", bytes([1, 3, 1]) + f32(0.0, 2.0, 0.0)
          + f32(-3.4028235e38, 3.4028235e38, 0.0) + f32(0.5, 1.5))


if __name__ == "__main__":
    seeds_types()
    seeds_pwl()
    for d in sorted(CORPUS.iterdir()):
        print(f"{d.name}: {len(list(d.iterdir()))} seeds")
