"""PNG figures of one refine session (matplotlib, Agg backend): the residual
before (base model) and after (refined model) against temperature, time and
the regressor of each effect refine added."""
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from . import _effect_models as fx  # noqa: E402
from ..io import atomic_output  # noqa: E402
from ..errors import OutputFileError  # noqa: E402


def effect_regressor(data, model, effect):
    """(values, label) the effect's term is driven by, evaluated with the
    final model's parameters."""
    T_used = fx.temperature_used(data, model.spec) if data.T is not None else None
    if effect.name == "thermal_lag":
        return T_used - data.T, "lagged - measured temperature"
    cols, names = fx.FAMILIES[effect.name].columns(data, T_used, effect)
    return cols[:, 0], f"{effect.name} regressor {names[0]}"


def _pair(path, x, before, after, mask, xlabel, title, unit):
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8), sharey=True)
    for ax, e, name in ((axes[0], before, "before (base model)"), (axes[1], after, "after (refined)")):
        ax.plot(x[mask], e[mask], ".", ms=2, alpha=0.5)
        ax.axhline(0.0, color="k", lw=0.6)
        r = float(np.sqrt(np.mean(e[mask] ** 2)))
        ax.set_title(f"{name}: RMS {r:.3g} {unit}".strip(), fontsize=9)
        ax.set_xlabel(xlabel)
    axes[0].set_ylabel(f"residual {unit}".strip())
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    with atomic_output(path, "wb") as fh:
        fig.savefig(fh, format="png", dpi=90)
    plt.close(fig)
    return path


def write_plots(result, directory, prefix=""):
    """Write the figures of `result` into `directory`; returns the paths."""
    try:
        os.makedirs(directory, exist_ok=True)
    except OSError as exc:
        raise OutputFileError(f"{directory}: cannot create the plot directory: {exc.strerror}") from exc
    data, base, final = result.data, result.base, result.final
    unit = data.labels.get("unit", "")
    what = data.labels.get("column", "value")
    mask = data.mask
    paths = []
    if data.T is not None:
        paths.append(_pair(os.path.join(directory, f"{prefix}residual_vs_temperature.png"), data.T,
                           base.residual, final.residual, mask, "temperature",
                           f"{what}: residual against temperature", unit))
    paths.append(_pair(os.path.join(directory, f"{prefix}residual_vs_time.png"), data.t,
                       base.residual, final.residual, mask, "time (s)",
                       f"{what}: residual against time", unit))
    for e in final.spec.effects:
        x, label = effect_regressor(data, final, e)
        paths.append(_pair(os.path.join(directory, f"{prefix}residual_vs_{e.name}.png"), x,
                           base.residual, final.residual, mask, label,
                           f"{what}: residual against the {e.name} regressor", unit))
    return paths
