"""Effects judged together.  Two effects that overlap can each look too weak
alone: a drift in time inflates every fold's error and hides a lag, and a
lag fitted without the drift bends to imitate it.  When the best single
candidate fails the stopping rule, pairs of the best candidates are fitted
jointly (both nonlinear
parameters re-polished together) and the pair is judged by the same rule,
its Bonferroni count including the pairs.  The pair has its own offset
order, and a drift member its own knots, chosen by CV with both members in
(those chosen without the partner bent to imitate it); a single candidate
that failed is tried once with its own order the same way.  A pair is
claimed only when
each member carries a material part of its gain: the pair, that member's
parameter chosen inside each fold, must lower the systematic error of a
reading by the rule's relative and material margins against the pair
without that member (the other held at the joint fit).  Otherwise a member
that helps nothing rides along on its partner's gain (a hysteresis next to
a warm-up).  Significance is the pair's, tested once against the current
model: two overlapping effects share their evidence, so each alone on top
of the other has less of it than the pair.

Once the loop stops, each effect's share of the systematic error removed:
the out-of-sample systematic error of the final model without that effect
(the others held), in quadrature over the final one, normalised over the
effects."""
from itertools import combinations

import numpy as np

from . import _effect_models as fx
from . import _robust as robust
from ._base_model import rechoose_drift, repolish, reselect
from ._cross_validation import cv_residual, rms
from ._stopping import judge, material

MAX_PAIR_MEMBERS = 3       # pairs among the three best helpful candidates


def candidate_of(data, spec, name, variant):
    """(family, variant, grid top, full-data fit) to let cross-validation
    choose `name`'s parameter per fold, given its full-data fit in `spec`."""
    fam = fx.FAMILIES[name]
    eff = next(e for e in spec.effects if e.name == name)
    return fam, variant, fx.grid_top(fam, data, eff.param), eff.param


def pair_trials(data, model, tried, opts, admissible):
    """Joint fits of pairs among the MAX_PAIR_MEMBERS families whose single
    candidates in `tried` (cv rms, name, variant, e, fitted model) score
    best out of sample, whether or not they beat the current model alone
    (the drift that hides a lag also spoils the lag's own score).  A family
    with several start variants (hysteresis) is tried in each, with the
    other member at its best variant.  `admissible` (family, spec) -> bool
    rejects a joint fit whose parameter moved out of what may be claimed.
    Returns [(cv rms, (a, b), (va, vb), e, model)]."""
    best = {}
    for c, name, v, _, trial in sorted(tried, key=lambda x: x[0]):
        if name in fx.FAMILIES and name not in best:
            best[name] = v
    out = []
    for a, b in combinations(list(best)[:MAX_PAIR_MEMBERS], 2):
        if fx.FAMILIES[a].param_name is not None and fx.FAMILIES[b].param_name is None:
            a, b = b, a          # the linear member first: the nonlinear one is searched on top of it
        for va in _variants(a, best[a]):
            joints = None
            for vb in _variants(b, best[b]):
                if joints is None or _nonlinear_count(joints[0]) > 1:
                    # with one nonlinear parameter the re-polish refits it in
                    # every start variant: the joint fit does not depend on vb
                    joint = fx.fit_param(data, model.spec, fx.FAMILIES[a], va)
                    joint = fx.fit_param(data, joint.spec, fx.FAMILIES[b], vb)
                    joint = repolish(data, joint.spec)
                    joints = [reselect(data, j, opts, polish=False)
                              for j in [joint] + _knots_with_partner(data, joint, a, opts)]
                for joint in joints:
                    if not all(admissible(fx.FAMILIES[n], joint.spec) for n in (a, b)):
                        continue
                    e = cv_residual(data, joint.spec.without(b), opts, candidate_of(data, joint.spec, b, vb))
                    knots = next(e.variant for e in joint.spec.effects if e.name == a) if a == "drift" else va
                    out.append((rms(e), (a, b), (knots, vb), e, joint))
    return out


def _nonlinear_count(model):
    """How many effects of `model` have a nonlinear parameter."""
    return sum(1 for e in model.spec.effects if fx.FAMILIES[e.name].param_name)


def _knots_with_partner(data, joint, member, opts):
    """When `member` of the pair in `joint` is the drift: [the pair with the
    drift's knots chosen again with its partner in] (_base_model.
    rechoose_drift) if they differ, else [].  The knots best alone were
    chosen while the drift imitated part of the partner (2 knots bending
    to a hysteresis's branches); the pair's CV chooses between the two."""
    if member != "drift":
        return []
    again = rechoose_drift(data, joint, opts)
    return [] if again is joint else [again]


def order_trials(data, tried, opts):
    """The best MAX_PAIR_MEMBERS physical candidates in `tried` (cv rms,
    name, variant, e, fitted model), each with the offset order chosen
    again by blocked CV with it in (_base_model.reselect; its parameter
    is still chosen inside each fold).  The current order was chosen
    without the candidate: an order too low for the curve leaves the
    candidate's columns to bend to it (a play operator's branches take
    part of a curved offset) and extrapolate that into held-out blocks, so
    a real effect scores worse than none.  Each side of the comparison
    then has the order CV chooses for it.  Returns [(cv rms, name,
    variant, e, model)] for the candidates whose order changes."""
    best = {}
    for _, name, v, _, trial in sorted(tried, key=lambda x: x[0]):
        fam = fx.FAMILIES.get(name)
        if fam is not None and not fam.nuisance and name not in best:
            best[name] = (v, trial)
    out = []
    for name, (v, trial) in list(best.items())[:MAX_PAIR_MEMBERS]:
        ordered = reselect(data, trial, opts, polish=False)
        if ordered is trial:
            continue
        e = cv_residual(data, ordered.spec.without(name), opts, candidate_of(data, ordered.spec, name, v))
        out.append((rms(e), name, v, e, ordered))
    return out


def redrift_trials(data, model, tried, opts, admissible):
    """When the model holds a drift: the best MAX_PAIR_MEMBERS physical
    candidates in `tried`, each with the drift's knots chosen again.  The
    drift's knots were chosen before the newcomer was in, when the drift
    bent to imitate part of it; with those knots the newcomer looks weak
    (a hysteresis whose branches follow the cold and warm spells in time).
    A function of time alone (a warm-up) is not among them: with fewer
    knots it is only another drift, and it would take the place of a knot
    (a drift alone got a warm-up of an eighth of the record that way).
    Returns [(cv rms, name, variant, e, model)] for the knots other than
    the current ones."""
    drift = next((e for e in model.spec.effects if e.name == "drift"), None)
    if drift is None:
        return []
    best = {}
    for c, name, v, _, _ in sorted(tried, key=lambda x: x[0]):
        fam = fx.FAMILIES.get(name)
        if fam is not None and not fam.nuisance and not fam.time_only and name not in best:
            best[name] = v
    out = []
    for name in list(best)[:MAX_PAIR_MEMBERS]:
        fam = fx.FAMILIES[name]
        for knots in fx.FAMILIES["drift"].variants:
            if knots == drift.variant:
                continue
            base = model.spec.without("drift").with_effect(fx.Effect("drift", knots))
            trial = fx.fit_param(data, base, fam, best[name])
            if sum(1 for e in trial.spec.effects if fx.FAMILIES[e.name].param_name) > 1:
                trial = repolish(data, trial.spec)
            trial = reselect(data, trial, opts, polish=False)
            if not admissible(fam, trial.spec):
                continue
            e = cv_residual(data, trial.spec.without(name), opts,
                            candidate_of(data, trial.spec, name, best[name]))
            out.append((rms(e), name, best[name], e, trial))
    return out


def member_not_needed(data, joint, names, variants, opts, per_report, n_tried):
    """None when every member of the pair in `joint` lowers the systematic
    error materially (_stopping.material) on top of the pair without it,
    else {effect, systematic_gain, ...} of the first member that does not
    (its parameter chosen inside each fold, the other member held at the
    joint fit)."""
    for name, variant in zip(names, variants):
        rest = joint.spec.without(name)
        e_without = cv_residual(data, rest, opts)
        e_with = cv_residual(data, rest, opts, candidate_of(data, joint.spec, name, variant))
        _, verdict = judge(e_without, e_with, opts, per_report, n_tried)
        if not material(verdict, opts):
            return {"effect": name, "not_needed_in": list(names), **verdict}
    return None


def _variants(name, best_variant):
    fam = fx.FAMILIES[name]
    return fam.variants if fam.param_name is not None else (best_variant,)


def effect_shares(data, model, e_final, opts, per_report):
    """Each term's share of the systematic error removed: the final model's
    out-of-sample residual without it (the others held) against `e_final`.
    Returns [{effect, systematic_without, removed, share}]."""
    sys_final = robust.systematic_rms(e_final, per_report)
    rows = []
    for eff in model.spec.effects:
        e = cv_residual(data, model.spec.without(eff.name), opts)
        sys_without = robust.systematic_rms(e, per_report)
        rows.append({"effect": eff.name, "systematic_without": sys_without,
                     "removed": float(np.sqrt(max(0.0, sys_without ** 2 - sys_final ** 2)))})
    total = sum(r["removed"] ** 2 for r in rows)
    for r in rows:
        r["share"] = r["removed"] ** 2 / total if total > 0 else 0.0
    return rows
