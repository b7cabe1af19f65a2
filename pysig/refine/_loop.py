"""The refinement loop: fit the base model, look at the residual,
add the candidate effect that most lowers the out-of-sample error
(pysig.refine._cross_validation), repeat while the gain passes the stopping
rule (pysig.refine._stopping), and say when structure is left that no
candidate explains (pysig.refine._diagnostics).  When the best single
candidate fails, it is tried again with the offset order (and, with a
drift in the model, the drift's knots) chosen by CV with it in, then pairs
are fitted and judged together, the pair's order and a drift member's
knots chosen with both in (pysig.refine._joint); a drift in time is one of
the candidates, a nuisance reported on its own line and never exported to
the device.  A candidate whose fitted
time constant or width sits at the top of its search range is not tried
(_stopping.at_search_edge).  After each step the drift's knots are chosen
again, and an effect added earlier that no longer carries a material part
of the gain is taken out (and not tried again).  A hysteresis or a warm-up
(slow in time, what a wandering zero imitates) is claimed only if it also
stands with a random-walk zero estimated with it (_random_walk); one that
does not is not tried again."""
from dataclasses import replace

import numpy as np
from tqdm import tqdm

from . import _effect_models as fx
from . import _robust as robust
from ._base_model import base_spec, rechoose_drift, repolish, reselect, screen_impulses
from ._cross_validation import cv_residual, rms
from ._diagnostics import candidate_relations, residual_diagnostics
from ._joint import candidate_of, effect_shares, member_not_needed, order_trials, pair_trials, redrift_trials
from ._options import Options
from ._random_walk import SLOW_IN_TIME, random_walk_check
from ._result import Result, Step
from ._shape import shape_trials
from ._stopping import at_search_edge, judge, not_physical, stop_test
from ..errors import InsufficientDataError


def refine(data, opts=None):
    """Find what the base calibration model leaves out: fit the base model,
    then add, one at a time, the named effect that most lowers the blocked
    cross-validated error, while the gain is significant; say when structure
    is left that no candidate explains.

    Impulses are screened on the base model's residual; when the refined
    model's residual screens differently (structure the base model lacked
    looked like spikes to the running median), the loop runs once more
    with the screening of the refined residual.

    Parameters
    ----------
    data : pysig.refine._effect_models.FitData
        One measured column, its times, temperature and reference (true
        value), and the mask of samples to fit and score.
    opts : Options, optional
        Folds, guard band, significance level, smallest gain, the effect
        families to try (all by default).

    Returns
    -------
    Result
        The base and final models, the steps taken (effect, parameters,
        RMS and CV RMS before and after, p-value), the candidates rejected
        or left at their search edge, residual diagnostics before and after;
        `report()` gives all of it as a JSON-ready dict.

    Raises
    ------
    InsufficientDataError
        Fewer usable samples than 3 per fold.

    Examples
    --------
    >>> from lab.studies.refine_cases import chamber_run, fit_data
    >>> result = refine(fit_data(chamber_run("thermal_lag", seed=3)))   # a 90-s lag, not declared
    >>> [step.effect for step in result.steps], round(result.steps[0].params["tau_s"])
    (['thermal_lag'], 90)
    >>> result.base_rms / result.final_rms > 3, result.report()["unexplained"]["unexplained"]
    (True, False)
    """
    opts = opts or Options()
    if data.mask.sum() < 3 * opts.folds:
        raise InsufficientDataError(
            f"refine: {int(data.mask.sum())} usable samples; need at least {3 * opts.folds}")
    # a long record takes minutes: the bar counts the models fitted and
    # names the step and the candidate being tried
    with tqdm(desc=opts.label, unit=" fits", disable=(None if opts.progress is None else not opts.progress),
              leave=False, dynamic_ncols=True) as bar:
        screened, used, impulses = screen_impulses(data, opts)
        result = _confirmed_loop(screened, used, impulses, opts, bar)
        if opts.impulse_k is None or not result.steps:
            return result
        again = robust.impulse_mask(result.final.residual, used, opts.impulse_k)
        if np.array_equal(again, impulses):
            return result
        bar.set_postfix_str("again, impulses screened on the refined residual")
        return _confirmed_loop(replace(data, mask=used & ~again), used, again, opts, bar)


def _confirmed_loop(data, used, impulses, opts, bar):
    """The loop, then each hysteresis or warm-up of its final model (slow in
    time, what a wandering zero imitates) tested with the model's smooth
    drift replaced by a random-walk zero estimated with it, at the
    threshold it was added with (_random_walk).  One that fails is not
    claimed: the loop runs again without its family (a lag it stood in
    front of is then found), and the report says why it was not added."""
    failed = []
    while True:
        result = _loop(data, used, impulses, opts, bar)
        if not opts.random_walk_check:
            return result
        failing = []
        for step in result.steps:
            if step.effect not in SLOW_IN_TIME:
                continue
            step.random_walk = random_walk_check(data, result.final, (step.effect,), result.per_report)
            step.random_walk["p_threshold"] = step.p_threshold
            if not step.random_walk["p_value"] < step.p_threshold:
                failing.append(step)
        if not failing:
            return replace(result, rejected=failed + result.rejected)
        failed += [_not_added(s.effect, s.params.get("start_branch", 0), s.cv_rms_after, s.cv_rms_before,
                              {"p_value": s.p_value, "p_threshold": s.p_threshold,
                               "systematic_gain": 1.0 - s.cv_systematic_after / s.cv_systematic_before
                               if s.cv_systematic_before > 0 else 0.0},
                              random_walk=s.random_walk) for s in failing]
        opts = replace(opts, families=tuple(f for f in opts.families if f not in {s.effect for s in failing}))
        bar.set_postfix_str(f"again without {', '.join(s.effect for s in failing)} (random-walk check)")


def _first_passing(data, trials, e_cv, opts, per_report, n_families, material_in_trial=False,
                   better_than=None):
    """The best trial by CV RMS (one effect or a pair) that passes the test
    and needs every member it names (_joint.member_not_needed), with its
    verdict; None if none does.  The Bonferroni count is `n_families` plus
    the distinct names the trials try.
    `material_in_trial`: against the current model only the significance
    and the relative gain are asked; how much the newcomer removes is
    judged in the trial's own model.
    `better_than`: only trials whose CV RMS is below it may pass (all are
    counted as tried)."""
    n_tried = n_families + len({t[1] for t in trials})
    for t in sorted(trials, key=lambda x: x[0]):
        if better_than is not None and not t[0] < better_than:
            break
        t_ok, t_verdict = judge(e_cv, t[3], opts, per_report, n_tried)
        if material_in_trial:
            t_ok = (t_verdict["p_value"] < t_verdict["p_threshold"]
                    and t_verdict["systematic_gain"] >= opts.min_gain)
        names, variants = (t[1], t[2]) if isinstance(t[1], tuple) else ((t[1],), (t[2],))
        if t_ok and member_not_needed(data, t[4], names, variants, opts, per_report, n_tried) is None:
            return t, t_verdict
    return None


def _loop(data, used, impulses, opts, bar):
    per_report = robust.samples_per_report(data.dt, opts.report_s)
    t_sigma = robust.white_sigma(np.where(data.mask, data.T, np.nan)) if data.T is not None else 0.0
    spec, order_cv = base_spec(data, opts)
    model = fx.fit(data, spec)
    base = model
    e_cv = e_base = cv_residual(data, spec, opts)
    base_cv = rms(e_cv)
    unavailable = {f: fx.FAMILIES[f].unavailable(data) for f in opts.families
                   if fx.FAMILIES[f].unavailable(data)}
    diag_before = residual_diagnostics(data, model.residual, opts.test_blocks)
    relations = candidate_relations(data, model)
    steps, rejected, at_edge, not_claimed, dropped = [], [], [], [], []
    shaped = False

    def admissible(fam, spec):
        return at_search_edge(data, fam, spec) is None and not_physical(data, fam, spec, opts, t_sigma) is None

    for step_no in range(1, opts.max_steps + 1):
        tried, at_edge, not_claimed = [], [], []
        for name in opts.families:
            fam = fx.FAMILIES[name]
            if name in model.spec.names() or fam.unavailable(data) or name in {d["effect"] for d in dropped}:
                continue
            for v in fam.variants:
                bar.set_postfix_str(f"step {step_no}: {name}")
                bar.update()
                trial = fx.fit_param(data, model.spec, fam, v)
                edge = at_search_edge(data, fam, trial.spec)
                if edge is not None:
                    at_edge.append({"effect": name, "variant": v, **edge})
                    continue
                bad = not_physical(data, fam, trial.spec, opts, t_sigma)
                if bad is not None:
                    not_claimed.append({"effect": name, "variant": v, **bad})
                    continue
                if any(fx.FAMILIES[e.name].param_name for e in model.spec.effects):
                    # the earlier effects' parameters move with the newcomer
                    # (a lag fitted alone absorbs part of a hysteresis)
                    trial = repolish(data, trial.spec)
                e_new = cv_residual(data, trial.spec.without(name), opts,
                                    candidate_of(data, trial.spec, name, v))
                tried.append((rms(e_new), name, v, e_new, trial))
        if opts.shape and not shaped:
            # the best larger offset (one candidate: the size chosen by CV)
            shapes = [(rms(e), params, e, s) for params, s in shape_trials(data, model)
                      for e in [cv_residual(data, s, opts)]]
            if shapes:
                c, params, e_new, s = min(shapes, key=lambda x: x[0])
                tried.append((c, "offset_shape", params, e_new, fx.fit(data, s)))
        if not tried:
            break
        tried.sort(key=lambda x: x[0])
        summary = [{"effect": n, "variant": v, "cv_rms": c} for c, n, v, _, _ in tried]
        cv_new, name, variant, e_new, trial = tried[0]
        cv_old = rms(e_cv)
        # Bonferroni over the candidate families tried: a family's variant
        # (order, start branch, knots) is chosen by CV, as the offset shape's size is
        n_families = len({n for _, n, _, _, _ in tried})
        ok, verdict = judge(e_cv, e_new, opts, per_report, n_families)
        if not ok:
            bar.set_postfix_str(f"step {step_no}: {name} with its own offset order, drift knots, in pairs")
            # the offset order chosen again with the newcomer in: the order
            # chosen without it can be too low for it to predict held-out blocks
            found = _first_passing(data, order_trials(data, tried, opts), e_cv, opts, per_report, n_families)
            rechosen = "offset_order_rechosen" if found is not None else None
            if found is None:
                # the drift in the model chosen again with the newcomer in: the
                # newcomer must carry a material part of the gain on top of the
                # re-chosen drift alone (the knots' own gain is not its), and
                # that is where it is measured: the drift chosen without it took
                # over part of it, and what that drift leaves may be under the
                # material margin however large the newcomer is
                found = _first_passing(data, redrift_trials(data, model, tried, opts, admissible),
                                       e_cv, opts, per_report, n_families, material_in_trial=True)
                rechosen = "drift_knots_rechosen" if found is not None else None
            if found is None:
                # two overlapping effects can each fail alone and pass together;
                # a pair that predicts worse than the best single candidate
                # is not that (a drift and a hysteresis standing in for a
                # warm-up that predicts better alone)
                found = _first_passing(data, pair_trials(data, model, tried, opts, admissible),
                                       e_cv, opts, per_report, n_families, better_than=tried[0][0])
            if found is not None:
                (cv_new, name, variant, e_new, trial), verdict = found
                ok = True
                summary += [{"effect": name, "variant": variant, "cv_rms": cv_new, rechosen: True}
                            if rechosen else
                            {"effect": " + ".join(name), "variant": list(variant), "cv_rms": cv_new}]
        if not ok:
            rejected = [_not_added(name, variant, cv_new, cv_old, verdict)]
            break
        names = name if isinstance(name, tuple) else (name,)
        if name == "offset_shape":
            shaped = True
            new_model = trial
            params = [dict(variant)]
        else:
            new_model = reselect(data, rechoose_drift(data, trial, opts), opts)
            params = []
            for n in names:
                eff = next(e for e in new_model.spec.effects if e.name == n)
                p = fx.FAMILIES[n].describe(eff)
                p["coefficients"] = {k: v for k, v in new_model.coefficients().items()
                                     if k.startswith(n + ":")}
                params.append(p)
        e_cv_new = cv_residual(data, new_model.spec, opts)   # CV of the model actually kept
        if not rms(e_cv_new) < cv_old:
            # the per-fold parameter choice won, the model as kept does not
            rejected = [_not_added(name, variant, rms(e_cv_new), cv_old, verdict, kept_model_cv_worse=True)]
            break
        for n, p in zip(names, params):
            steps.append(Step(n, p, model.rms(data.mask), new_model.rms(data.mask),
                              cv_old, rms(e_cv_new), verdict["p_value"], summary,
                              verdict["cv_systematic_now"],
                              robust.systematic_rms(e_cv_new, per_report),
                              judged_with=[m for m in names if m != n],
                              p_threshold=verdict["p_threshold"]))
        model, e_cv = new_model, e_cv_new
        gone = _no_longer_needed(data, model, opts, per_report, n_families)
        if gone is not None:
            # an effect the rest of the kept model now explains (the
            # newcomer, the drift's knots chosen again with it): out, and
            # not tried again
            model = repolish(data, model.spec.without(gone["effect"]))
            e_cv = cv_residual(data, model.spec, opts)
            steps = [s for s in steps if s.effect != gone["effect"]]
            dropped.append({**gone, "with": model.spec.names()})
    _final_parameters(steps, model)
    return Result(data=data, base=base, final=model, base_order_cv=order_cv, steps=steps,
                  rejected=rejected, at_edge=at_edge, base_cv_rms=base_cv, final_cv_rms=rms(e_cv),
                  diagnostics_before=diag_before,
                  diagnostics_after=residual_diagnostics(data, model.residual, opts.test_blocks),
                  relations_before=relations, unavailable=unavailable, test=stop_test(opts),
                  used=used, impulses=impulses, not_claimed=not_claimed, dropped=dropped,
                  per_report=per_report, report_s=opts.report_s,
                  shares=effect_shares(data, model, e_cv, opts, per_report) if model.spec.effects else [],
                  base_cv_systematic=robust.systematic_rms(e_base, per_report),
                  final_cv_systematic=robust.systematic_rms(e_cv, per_report))


def _not_added(name, variant, cv_new, cv_old, verdict, **why):
    """The report's entry for a candidate not added: its CV RMS against the
    current model's, the test's verdict, and why (when not the test)."""
    return {"effect": name, "variant": variant, "cv_rms": cv_new, "cv_rms_now": cv_old,
            "cv_gain": 1.0 - cv_new / cv_old if cv_old > 0 else 0.0, **verdict, **why}


def _final_parameters(steps, model):
    """Each step reports the parameters its effect has in the final model
    (what the device correction uses): a later effect re-polishes an earlier
    one's time constant or width (a lag fitted before the drift bends to
    imitate it) and the drift's knots are chosen again.  A value it was
    added with that differs stays as `<name>_when_added`."""
    for step in steps:
        eff = next((e for e in model.spec.effects if e.name == step.effect), None)
        if eff is None:
            continue
        for key, value in fx.FAMILIES[step.effect].describe(eff).items():
            added = step.params.get(key)
            if added is not None and added != value:
                step.params[f"{key}_when_added"] = added
                step.params[key] = value


def _no_longer_needed(data, model, opts, per_report, n_tried):
    """The first physical effect of `model` that does not carry a material
    part of the gain on top of the rest of it (the test a pair's members
    pass, _joint.member_not_needed), or None.  Effects are judged together,
    in the model as kept: a warm-up taken for part of a drift's settling
    adds nothing once the drift's knots are chosen again, and would ride
    along with a share of 0."""
    for eff in model.spec.effects:
        if fx.FAMILIES[eff.name].nuisance:
            continue
        why = member_not_needed(data, model, (eff.name,), (eff.variant,), opts, per_report, n_tried)
        if why is not None:
            return why
    return None
