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
    # q16: mode 0, n, vf, derive (bit 0: recip from the range), t_lo, t_hi, recip u32, table, temperatures
    for k, (n, vf, lo, hi) in enumerate([(2, 8, 0, 1000), (5, 0, -2000, 2000),
                                         (255, 15, -32768, 32767), (17, 4, 100, 101)]):
        tab = [(-1) ** i * (i * 977 % 32768) for i in range(n)]
        data = bytes([0, n, vf, 1]) + s.pack("<hhI", lo, hi, 1) + s.pack(f"<{n}h", *tab)
        data += s.pack("<4h", lo - 1 if lo > -32768 else lo, hi, (lo + hi) // 2, 0)
        write("pwl", f"seed-q16-{k}", data)
    # float: mode 1, n, derive=1, t_lo, t_hi, inv_step (derived), table, temperatures
    for k, (n, lo, hi) in enumerate([(2, -40.0, 85.0), (9, 6.7, 41.1), (255, -1e30, 1e30)]):
        tab = [float(i) * 0.5 - 3 for i in range(n)]
        data = bytes([1, n, 1]) + f32(lo, hi, 0.0) + f32(*tab) + f32(*F_SPECIAL)
        write("pwl", f"seed-f-{k}", data)
    write("pwl", "regress-f-table-diff-overflow", bytes([1, 3, 1]) + f32(0.0, 2.0, 0.0)
          + f32(-3.4028235e38, 3.4028235e38, 0.0) + f32(0.5, 1.5))


def seeds_image():
    """Hand-framed images in each harness mode (raw, fixed-up, structured)."""
    write("image", "seed-raw-empty-image", b"\x00" + _sealed(b"", 7))
    write("image", "seed-raw-not-an-image", b"\x00" + b"PK\x03\x04" + bytes(40))
    write("image", "seed-fixup-body", b"\x01" + bytes(12) + struct.pack("<HH", 6, 4) + i32(-1) + bytes(2))
    # structured: n_axes, order, extra, [unknown type], u_shift, t_lo t_hi t_center t0 u_mul, q + coefs
    for k, (axes, order, extra) in enumerate([(0, 1, 0), (2, 1, 5), (1, 7, 1)]):
        body = bytes([axes, order, extra])
        if extra & 1:
            body += struct.pack("<H", 0x1234)
        body += bytes([14]) + struct.pack("<5h", -4000, 8500, 2250, 2500, 9000)
        for _ in range(axes % 3 + 1):
            body += bytes([20]) + b"".join(edgy(v) for v in [1 << 20, -(1 << 18), 12345, 0, 7, -7, 1, 2, 3][:order % 8 + 2])
        body += struct.pack("<hh", 2500, -5000) + i32(1)
        write("image", f"seed-structured-{k}", b"\x02" + body)


def _sealed(body, seq):
    import binascii
    data = b"psig" + bytes([1, 0]) + struct.pack("<HI", 12 + len(body) + 2, seq) + body
    return data + struct.pack("<H", binascii.crc_hqx(data, 0xFFFF))


def seeds_tcomp():
    # fixed: mode 0, n_axes, order, steer, u_shift, t_lo t_hi t_center t0 u_mul, coefs (edgy), q x3, then t + readings
    for k, (axes, order, steer, lo, hi) in enumerate([(3, 2, 1, -4000, 8500), (1, 8, 1, -32768, 32767),
                                                      (2, 1, 3, 2500, 2501), (1, 1, 0, 0, 100)]):
        n = (axes % 3 + 1) * (order % 8 + 1) if steer & 1 else axes * (order + 1)
        coefs = b"".join(edgy(v) for v in ([1 << 24, -(1 << 20), 77, -1, 2**31 - 1, -2**31, 5, 6, 7] * 3)[:n])
        body = bytes([0, axes, order, steer, 14]) + struct.pack("<5h", lo, hi, (lo + hi) // 2, 2500, 300)
        body += coefs + bytes([16, 30, 0]) + struct.pack("<8h", -32768, -32768, 32767, 32767, 2500, 100, -100, 0)
        write("tcomp", f"seed-q-{k}", body)
    # float: mode 1, n_axes, order, steer, then t_lo t_hi center inv_scale (raw) or steered ranges
    write("tcomp", "seed-f-steered", bytes([1, 2, 1, 1]) + f32(0, 0, 0, 0) + struct.pack("<hH", -4000, 12500)
          + i32(*[65536 * v for v in (3, -2, 1, 4, 5, 6, 7, 8, 9)]) + f32(*F_SPECIAL))
    write("tcomp", "seed-f-raw", bytes([1, 0, 1, 4]) + f32(-40.0, 85.0, 22.5, 0.016) + f32(1.0, 2.0)
          + f32(*F_SPECIAL))
    write("tcomp", "seed-f-overflow", bytes([1, 0, 2, 4]) + f32(-1.0, 1.0, 0.0, 1.0)
          + f32(3.4e38, 3.4e38, 3.4e38) + f32(1.0, 3.4e38, -3.4e38, 3.4e38))


def seeds_chain():
    # float, steered: mode 1, steer, scale u16, window, stable_count, lockout, motion, zero, seed_first, then ops
    ramp = b"".join(bytes([2]) + struct.pack("<h", v) for v in range(-3000, 3000, 250))
    write("chain", "seed-f-paper-ramp", bytes([1, 1]) + struct.pack("<H", 63) + bytes([9, 0, 0, 0, 0, 0]) + ramp)
    specials = b"".join(bytes([3]) + f32(v) for v in F_SPECIAL)
    write("chain", "seed-f-specials", bytes([1, 3]) + struct.pack("<H", 640) + bytes([9, 1, 3, 1, 1, 1])
          + specials + bytes([0xF0, 0xF1]) + f32(1.5) + bytes([0xF2, 0xF3]) + specials)
    write("chain", "seed-f-raw-params", bytes([1, 0]) + f32(2.0) + bytes([12]) + f32(1e-7, 0.05, 10.0, 1.0)
          + bytes([0]) + f32(0.01) + bytes([1, 0]) + f32(0.0) + bytes([1]) + f32(0.0, 0.0) + ramp)
    # fixed, steered: mode 0, steer, a0 u16, window, q, p0, x0 (edgy), seed_first, step, count, lockout,
    # motion band u16 + on/off, motion count, zero on/off (+ band u16), then ops
    rails = b"".join(bytes([1]) + edgy(v) for v in [I32_MIN, I32_MAX, 0, 16777215, -16777216, 5, -5, 1 << 30])
    steps = b"".join(bytes([0]) + struct.pack("<h", v) for v in [0, 100, 100, 100, 5000, 5000, 5000, -32768])
    write("chain", "seed-q-rails", bytes([0, 0x31]) + struct.pack("<H", 16) + bytes([9]) + i32(1 << 20, 10 << 16)
          + edgy(0) + bytes([1]) + struct.pack("<H", 64) + bytes([1, 2]) + struct.pack("<H", 100) + bytes([1, 2, 1])
          + struct.pack("<H", 50) + rails + steps + bytes([0xF0, 0xF1]) + edgy(I32_MIN) + bytes([0xF3]) + rails)
    write("chain", "seed-q-raw-params", bytes([0, 0]) + edgy(1000) + bytes([12]) + i32(107, 13107200) + edgy(128)
          + bytes([0]) + edgy(128) + bytes([1, 0]) + edgy(0) + bytes([1]) + edgy(0) + edgy(0) + steps)


def seeds_scale():
    # fixed: mode 0, offset, gain (edgy), shift, then counts (edgy)
    write("scale", "seed-q-hx711", bytes([0]) + edgy(-8000) + edgy(1 << 30) + bytes([0x80 | 46])
          + b"".join(edgy(v) for v in (0, 8388607, -8388608, 123456, I32_MIN, I32_MAX)))
    write("scale", "seed-q-rails", bytes([0]) + edgy(I32_MIN) + edgy(-1) + bytes([0])
          + b"".join(edgy(v) for v in (I32_MAX, I32_MIN, 0)))
    write("scale", "seed-f", bytes([1]) + f32(-8000.0, 0.0005) + f32(*F_SPECIAL))


def seeds_effects():
    # lag/creep q: mode 0, alpha, k (edgy), frac|0x80, then (selector, x)
    xs = b"".join(bytes([0]) + struct.pack("<h", v) for v in (2500, 2600, -3000, 32767, -32768, 0))
    write("effects", "seed-lag-q", bytes([0]) + edgy(6554) + edgy(-65536) + bytes([0x80 | 16]) + xs)
    write("effects", "seed-hyst-q", bytes([1]) + struct.pack("<h", 150) + edgy(1 << 20) + bytes([0x41])
          + struct.pack("<8h", 2500, 2700, 2600, 2400, -32768, 32767, 0, 10))
    write("effects", "seed-poly-q", bytes([2]) + edgy(0) + edgy(65536) + bytes([0x82, 3, 3])
          + b"".join(edgy(v) for v in (65536, 1000, -1000, 7, 0, 0, 0, 0, 0)) + b"".join(edgy(v) for v in (100, -100, 5))
          + edgy(1000) + struct.pack("<h", 16384) + edgy(1) + edgy(2) + edgy(3))
    write("effects", "seed-float", bytes([3]) + f32(0.1, 0.5, 2.0) + bytes([2, 0])
          + f32(1.0, 0.1, 0.01, 0, 0, 0, 0, 0, 0) + f32(0.01, 0.02, 0.03) + f32(*F_SPECIAL))


def seeds_tcomp_fast_path():
    # steer 5: valid counts and scaling, moderate coefficients (i16, shift byte)
    coefs = b"".join(struct.pack("<h", v) + bytes([s]) for v, s in
                     [(1200, 10), (-300, 4), (77, 0), (5, 2), (-5, 1), (100, 8), (-100, 8), (1, 0), (2, 0)])
    body = bytes([0, 2, 1, 5, 9]) + struct.pack("<5h", -4000, 8500, 2250, 2500, 300) + coefs
    body += bytes([12, 12, 0]) + struct.pack("<8h", -32768, -32768, 32767, 32767, 2500, 100, -100, 0)
    write("tcomp", "seed-q-fast-path", body)


def seeds_image_pwl():
    # structured image with an offset section and a table section (extra bit 3):
    # n_axes, order, extra, u_shift, 5 x i16, q + coefs, then table: axes, knots, lo, hi, recip, vf + entries
    body = bytes([0, 1, 8]) + bytes([14]) + struct.pack("<5h", -4000, 8500, 2250, 2500, 3670)
    body += bytes([16]) + b"".join(edgy(v) for v in (1000, -1000, 5))
    body += bytes([1, 7]) + struct.pack("<hhI", 670, 4110, 0) + bytes([4]) + struct.pack("<8h", *range(-400, 400, 100))
    body += struct.pack("<hh", 2500, -5000) + i32(3) + bytes([1, 0]) + struct.pack("<h", 1000)
    write("image", "seed-structured-pwl", b"\x02" + body)


def seeds_effects_refined():
    # mode 4: n_axes, order, u_shift, flags, axis, t_lo, t_hi, 27 coefs (i16 + shift), q x3,
    # lag alpha, hyst width, k (edgy), start, gain coefs (9 x i16), gain order, then (t, y) pairs
    coefs = b"".join(struct.pack("<h", v) + bytes([8]) for v in [1200, -300, 77] * 9)
    tail = struct.pack("<hh", 6554, 150) + edgy(1 << 18) + bytes([2]) + struct.pack("<9h", 0, 300, -50, 0, 0, 0, 0, 0, 0) + bytes([2])
    pairs = struct.pack("<12h", 2500, 100, 2600, -100, -4000, 32767, 8500, -32768, 3000, 0, 2000, 5)
    for k, flags in enumerate((0, 2, 6, 14)):
        write("effects", f"seed-refined-{k}", bytes([4, 0, 1, 9, flags, 0]) + struct.pack("<hh", -4000, 8500)
              + coefs + bytes([16, 20, 8]) + tail + pairs)


def seeds_device_id():
    # u8 serial length, serial, then a device-id payload: the device's own id
    # (short serial verbatim, long one hashed) and another device's
    def payload(serial):
        if len(serial) <= 16:
            return bytes([0, len(serial)]) + serial
        h = 2166136261
        for b in serial:
            h = ((h ^ b) * 16777619) & 0xFFFFFFFF
        return bytes([1, 16]) + struct.pack("<I", h) + serial[-12:]
    for name, serial, made_for in (("own-short", b"SN-0001", b"SN-0001"), ("own-one", b"A", b"A"),
                                   ("own-long", b"PLANT-01/LINE-4/LOT-2026-47/000123", None),
                                   ("other", b"abc", b"abd")):
        made_for = made_for or serial
        write("device_id", f"seed-{name}", bytes([len(serial)]) + serial + payload(made_for))


if __name__ == "__main__":
    seeds_types()
    seeds_pwl()
    seeds_image()
    seeds_image_pwl()
    seeds_tcomp()
    seeds_tcomp_fast_path()
    seeds_chain()
    seeds_scale()
    seeds_effects()
    seeds_effects_refined()
    seeds_device_id()
    for d in sorted(CORPUS.iterdir()):
        print(f"{d.name}: {len(list(d.iterdir()))} seeds")
