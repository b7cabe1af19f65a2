"""From a refined model to the firmware: fixed-point parameters of the
effects refine added, their coefficient-image sections, and the refined
correction evaluated two ways (float model, and the firmware's fixed-point
C through Cython); tests hold the C against the Python fixed-point spec
(spec.effects.RefinedQ), which the library never imports.

Image section payloads (little-endian; ids reserved in csrc/include/sig_image.h):
  2 GAIN_POLY     u8 order, 3 x u8 reserved (0), (order+1) x i32 coef Q16.16,
                  ascending powers of the offset section's u        (sig_gain_q)
  3 THERMAL_LAG   i32 alpha_q16 (1..65536), u8 frac (16), u8 reserved (0)
                                                                    (sig_lag_q)
  4 HYSTERESIS    i16 width (0.01 °C, >= 1), i8 start (-1, 0, 1), u8 reserved,
                  i32 k_q16 (Q16.16 reading LSB per 0.01 °C)         (sig_hyst_q)
  5 CREEP         i32 alpha_q16, u8 frac (0..16), u8 reserved, i32 k_q16
                                                                    (sig_creep_q)
The offset polynomial goes in section 1 in the format of sig_image.h
(read by sig_tcomp_load_image)."""
import struct

import numpy as np

from . import _effect_models as fx
from ..errors import ModelFileError, RangeError
from ..store._image import build_image, find_section
from ..tcomp._quant import choose_scaling, quantize_axis, to_centi

SECTION_OFFSET_POLY = 1
SECTION_GAIN_POLY = 2
SECTION_THERMAL_LAG = 3
SECTION_HYSTERESIS = 4
SECTION_CREEP = 5
EXPORTABLE = ("thermal_lag", "hysteresis")      # in the refined temperature chain (sig_refined_q)


def _alpha_q16(tau, dt):
    return int(min(65536, max(1, round(fx.lag_alpha(tau, dt) * 65536))))


def device_model(result, t0_c=25.0):
    """Fixed-point model of a refined temperature calibration (one axis):
    dict offset (sig_tcomp_q fields), lag, hyst, and float twins.  Effects
    outside the temperature chain are listed in 'not_exported'."""
    data, model = result.data, result.final
    if data.T is None or model.spec.base_order < 1:
        raise RangeError("device_model: the refined model has no temperature polynomial")
    if model.spec.base_family != "poly":
        raise RangeError(f"device_model: the refined offset is a {model.spec.describe_base()}; "
                         "the refined image carries a polynomial offset (export a table with "
                         "pysig.tcomp._table_fit's image)")
    coefs = model.coefficients()
    a = np.array([0.0] + [coefs[f"u^{k}"] for k in range(1, model.spec.base_order + 1)])
    sc = choose_scaling(int(to_centi(np.min(data.T))), int(to_centi(np.max(data.T))))
    # re-express f(u1), u1 = (T - c1)/s1, in the device abscissa u2 = (T - c2)/s2
    c1, s1, c2, s2 = data.t_center, data.t_scale, sc.center_c, sc.scale_c
    f_u2 = np.polynomial.Polynomial(a)(np.polynomial.Polynomial([(c2 - c1) / s1, s2 / s1]))
    delta = np.zeros(model.spec.base_order + 1)
    delta[:f_u2.coef.size] = f_u2.coef
    t0 = min(max(t0_c, sc.t_lo / 100.0), sc.t_hi / 100.0)
    delta[0] -= np.polynomial.polynomial.polyval((t0 - c2) / s2, delta)
    qa = quantize_axis(delta, what="refined offset")
    dev = {"offset": {"coef": list(qa.coef), "q": qa.q, "t_lo": sc.t_lo, "t_hi": sc.t_hi,
                      "t_center": sc.t_center, "t0": int(to_centi(t0)), "u_mul": sc.u_mul,
                      "u_shift": sc.u_shift},
           "offset_float": {"coef": delta.tolist(), "center": c2, "scale": s2},
           "lag": None, "hyst": None, "dt": data.dt, "not_exported": []}
    for e in model.spec.effects:
        if e.name == "thermal_lag":
            dev["lag"] = _alpha_q16(e.param, data.dt)
            dev["lag_float"] = {"tau_s": e.param}
        elif e.name == "hysteresis":
            width = max(1, int(round(e.param * 100)))
            h = coefs["hysteresis:branch"]
            dev["hyst"] = (width, int(round(h / width * 65536)), int(e.variant))
            dev["hyst_float"] = {"width": e.param, "h": h, "start": int(e.variant)}
        else:
            dev["not_exported"].append(e.name)
    return dev


def correct_float(dev, temp_c, y):
    """The refined model's correction in float64: y - (f(T') - f(T0)) - h*branch/w."""
    T = np.asarray(temp_c, dtype=float)
    if dev.get("lag_float"):
        T = fx.first_order_lag(T, fx.lag_alpha(dev["lag_float"]["tau_s"], dev["dt"]))
    off = dev["offset_float"]
    lo, hi = dev["offset"]["t_lo"] / 100.0, dev["offset"]["t_hi"] / 100.0
    u = (np.clip(T, lo, hi) - off["center"]) / off["scale"]
    out = np.asarray(y, dtype=float) - np.polynomial.polynomial.polyval(u, off["coef"])
    if dev.get("hyst_float"):
        h = dev["hyst_float"]
        out -= h["h"] * (T - fx.play_operator(T, h["width"], h["start"])) / h["width"]
    return out


def correct_c(dev, t_centi, y):
    """The firmware's sig_refined_step_q through Cython."""
    from . import _effects
    return _effects.refined_q(t_centi, y, dev["offset"], dev["lag"], dev["hyst"])


# ---- image sections --------------------------------------------------------------

def offset_payload(offset):
    """Section 1 payload for one axis (format in csrc/include/sig_image.h)."""
    coef = list(offset["coef"])
    head = struct.pack("<BBBBhhhhh", 1, len(coef) - 1, offset["u_shift"], 0, offset["t_lo"],
                       offset["t_hi"], offset["t_center"], offset["t0"], offset["u_mul"])
    return head + struct.pack("<B", offset["q"]) + struct.pack(f"<{len(coef)}i", *coef)


def lag_payload(alpha_q16, frac=16):
    return struct.pack("<iBB", alpha_q16, frac, 0)


def hyst_payload(width, k_q16, start):
    return struct.pack("<hbBi", width, start, 0, k_q16)


def creep_payload(alpha_q16, frac, k_q16):
    return struct.pack("<iBBi", alpha_q16, frac, 0, k_q16)


def gain_payload(coef):
    return struct.pack("<BBBB", len(coef) - 1, 0, 0, 0) + struct.pack(f"<{len(coef)}i", *coef)


def parse_lag(p, where="image"):
    if len(p) != 6:
        raise ModelFileError(f"{where}: thermal-lag section is {len(p)} bytes, expected 6")
    alpha, frac, res = struct.unpack("<iBB", p)
    if not (1 <= alpha <= 65536 and frac <= 16 and res == 0):
        raise ModelFileError(f"{where}: thermal-lag section: alpha_q16 {alpha}, frac {frac} out of range")
    return alpha, frac


def parse_hyst(p, where="image"):
    if len(p) != 8:
        raise ModelFileError(f"{where}: hysteresis section is {len(p)} bytes, expected 8")
    width, start, res, k = struct.unpack("<hbBi", p)
    if width < 1 or start not in (-1, 0, 1) or res:
        raise ModelFileError(f"{where}: hysteresis section: width {width}, start {start} out of range")
    return width, k, start


def parse_creep(p, where="image"):
    if len(p) != 10:
        raise ModelFileError(f"{where}: creep section is {len(p)} bytes, expected 10")
    alpha, frac, res, k = struct.unpack("<iBBi", p)
    if not (1 <= alpha <= 65536 and frac <= 16 and res == 0):
        raise ModelFileError(f"{where}: creep section: alpha_q16 {alpha}, frac {frac} out of range")
    return alpha, frac, k


def parse_gain(p, where="image"):
    if len(p) < 8:
        raise ModelFileError(f"{where}: gain section of {len(p)} bytes is too short")
    order = p[0]
    if order > 8 or any(p[1:4]) or len(p) != 4 + 4 * (order + 1):
        raise ModelFileError(f"{where}: gain section: order {order}, {len(p)} bytes")
    return list(struct.unpack(f"<{order + 1}i", p[4:]))


def refined_image(dev, sequence=1):
    """The coefficient image of a refined temperature model."""
    sections = [(SECTION_OFFSET_POLY, offset_payload(dev["offset"]))]
    if dev["lag"] is not None:
        sections.append((SECTION_THERMAL_LAG, lag_payload(dev["lag"])))
    if dev["hyst"] is not None:
        sections.append((SECTION_HYSTERESIS, hyst_payload(*dev["hyst"])))
    return build_image(sections, sequence)


def read_refined_image(data, where="image"):
    """(lag alpha_q16 or None, hyst tuple or None) from an image."""
    out = {}
    for key, typ, parse in (("lag", SECTION_THERMAL_LAG, parse_lag),
                            ("hyst", SECTION_HYSTERESIS, parse_hyst)):
        try:
            payload = find_section(data, typ, where)
        except ModelFileError as exc:
            if "no section" in str(exc):
                out[key] = None
                continue
            raise
        out[key] = parse(payload, where)
    if out["lag"] is not None:
        out["lag"] = out["lag"][0]
    return out
