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


if __name__ == "__main__":
    seeds_types()
    for d in sorted(CORPUS.iterdir()):
        print(f"{d.name}: {len(list(d.iterdir()))} seeds")
