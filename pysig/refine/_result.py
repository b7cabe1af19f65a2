"""What refine returns: the steps taken and the Result, with its
JSON-ready report and the refined model as data."""
from dataclasses import dataclass, field

import numpy as np

from . import _effect_models as fx
from . import _robust as robust
from ._diagnostics import ACF1_MATERIAL, TIME_R2_MATERIAL
from ._options import DEFAULT_REPORT_S


@dataclass
class Step:
    effect: str
    params: dict
    rms_before: float
    rms_after: float
    cv_rms_before: float
    cv_rms_after: float
    p_value: float
    candidates: list = field(default_factory=list)
    cv_systematic_before: float = float("nan")
    cv_systematic_after: float = float("nan")
    judged_with: list = field(default_factory=list)   # the effects added together with this one
    p_threshold: float = float("nan")   # the test's threshold when it was added
    random_walk: dict = None      # a slow-in-time effect's test under a random-walk zero

    def as_dict(self):
        return {"effect": self.effect, "params": self.params,
                "rms_before": self.rms_before, "rms_after": self.rms_after,
                "cv_rms_before": self.cv_rms_before, "cv_rms_after": self.cv_rms_after,
                "cv_systematic_before": self.cv_systematic_before,
                "cv_systematic_after": self.cv_systematic_after,
                "p_value": self.p_value, "p_threshold": self.p_threshold, "candidates": self.candidates,
                "judged_with": self.judged_with, "random_walk": self.random_walk,
                "nuisance": fx.FAMILIES[self.effect].nuisance if self.effect in fx.FAMILIES else False}


@dataclass
class Result:
    data: fx.FitData
    base: fx.FittedModel
    final: fx.FittedModel
    base_order_cv: dict
    steps: list
    rejected: list               # the best candidate of the last round, not added
    at_edge: list                # candidates of the last round left out: parameter at the search edge
    base_cv_rms: float
    final_cv_rms: float
    diagnostics_before: dict
    diagnostics_after: dict
    relations_before: dict
    unavailable: dict
    test: str
    used: np.ndarray = None      # samples usable before impulse screening
    impulses: np.ndarray = None  # samples treated as impulses
    not_claimed: list = field(default_factory=list)
    per_report: int = 1          # samples in one reported reading
    report_s: float = DEFAULT_REPORT_S
    shares: list = field(default_factory=list)      # each term's share of the systematic error removed
    dropped: list = field(default_factory=list)     # effects taken out again: a later one explains them
    base_cv_systematic: float = float("nan")
    final_cv_systematic: float = float("nan")

    @property
    def base_rms(self):
        return self.base.rms(self.data.mask)

    @property
    def final_rms(self):
        return self.final.rms(self.data.mask)

    def figures(self, model):
        """Robust (impulses left out) and plain (impulses in) per-sample RMS,
        the RMS of a reported reading (the residual averaged over report_s)
        and its systematic part."""
        robust_e = np.where(self.data.mask, model.residual, np.nan)
        out = robust.figures(robust_e, self.per_report)
        used = self.used if self.used is not None else self.data.mask
        out["plain_rms"] = float(np.sqrt(np.mean(model.residual[used] ** 2)))
        out["plain_averaged_rms"] = robust.averaged_rms(np.where(used, model.residual, np.nan),
                                                        self.per_report)
        return out

    def drift(self):
        """The nuisance drift in time: its knots and its size over the record
        in the reading's unit (zero at the start), or None."""
        curve = fx.drift_curve(self.data, self.final)
        if curve is None:
            return None
        knots = next(e.variant for e in self.final.spec.effects if e.name == "drift")
        used = curve[self.data.mask]
        return {"knots": int(knots), "session_steps": len(self.data.breaks),
                "over_record": float(np.ptp(used)),
                "start_to_end": float(used[-1] - used[0]),
                "unit": self.data.labels.get("unit") or (f"units of {self.data.labels['column']}"
                                                         if "column" in self.data.labels else "reading units"),
                "exported": False}

    def report(self):
        d = self.diagnostics_after
        unexplained = {"unexplained": bool(d["structured"])}
        unexplained.update({k: v for k, v in d.items() if k != "structured"})
        if d["structured"]:
            what = []
            if d["acf_lag1"] >= ACF1_MATERIAL:
                what.append(f"residual autocorrelated (lag-1 r = {d['acf_lag1']:.2f}, "
                            f"Ljung-Box p = {d['ljung_box_p']:.2g})")
            if d["time_blocks_r2"] >= TIME_R2_MATERIAL:
                what.append(f"residual varies with time ({100 * d['time_blocks_r2']:.0f} % of its "
                            f"variance between {d['time_blocks']} time blocks, "
                            f"ANOVA p = {d['time_blocks_anova_p']:.2g})")
            unexplained["seen"] = "; ".join(what)
        n_imp = int(self.impulses.sum()) if self.impulses is not None else 0
        return {
            "base_rms": self.base_rms,
            "final_rms": self.final_rms,
            "base_cv_rms": self.base_cv_rms,
            "final_cv_rms": self.final_cv_rms,
            "n_samples": int(self.data.mask.sum()),
            "impulses": {"count": n_imp,
                         "rule": (f"|r - running median of {2 * robust.HAMPEL_HALF_WINDOW + 1}| > "
                                  f"{robust.HAMPEL_K:g} robust sigma on the base residual; "
                                  "left out of fitting and scoring"),
                         "first_indices": [int(i) for i in np.flatnonzero(self.impulses)[:20]]
                         if n_imp else []},
            "report_s": self.report_s,
            "samples_per_report": self.per_report,
            "before": self.figures(self.base),
            "after": self.figures(self.final),
            "base_model": {"offset_order": self.base.spec.base_order,
                           "offset_family": self.base.spec.base_family,
                           "offset_order_cv_rms": {str(k): v for k, v in self.base_order_cv.items()},
                           "reference": self.data.labels.get("reference", "given")},
            "final_offset": self.final.spec.describe_base() if self.data.T is not None else None,
            "steps": [s.as_dict() for s in self.steps],
            "effects_found": [s.effect for s in self.steps if s.effect in fx.PHYSICAL],
            "drift": self.drift(),
            "cv_systematic": {"before": self.base_cv_systematic, "after": self.final_cv_systematic,
                              "removed": float(np.sqrt(max(0.0, self.base_cv_systematic ** 2
                                                            - self.final_cv_systematic ** 2)))},
            "shares": self.shares,
            "not_added": self.rejected,
            "not_claimed": self.not_claimed,
            "dropped": self.dropped,
            "at_search_edge": self.at_edge,
            "unexplained": unexplained,
            "residual_vs_candidates_before": self.relations_before,
            "unavailable": self.unavailable,
            "stopping_test": self.test,
            "model": model_dict(self.data, self.final),
        }


def model_dict(data, model):
    """The refined model as data: spec, coefficients and the scalings the
    columns were built with (what export needs)."""
    out = {"offset_order": model.spec.base_order,
           "offset_family": model.spec.base_family,
           "effects": [{"effect": e.name, "variant": e.variant, "param": e.param}
                       for e in model.spec.effects],
           "coefficients": model.coefficients(),
           "dt": data.dt}
    if data.T is not None:
        out["t_center"], out["t_scale"] = data.t_center, data.t_scale
    if data.r is not None:
        out["r_center"], out["r_scale"], out["r_abs"] = data.r_center, data.r_scale, data.r_abs
    return out
