"""Write what a replay produced: DIR/replay.csv, DIR/model.bin (the last
committed image, readable by `pysig apply`), DIR/commits.json and
DIR/learn.png (coverage, models and flags over time)."""
import json
import os

import numpy as np

from ..io import atomic_output, write_csv


def write_outputs(result, out_dir, columns, raw, temp, temp_name="temp", still=None):
    """Write the replay's files into out_dir (created if missing); returns
    their paths.  columns: the reading column names; raw: (n, n_axes); temp:
    the log's temperature column as read."""
    os.makedirs(out_dir, exist_ok=True)
    raw = np.asarray(raw)
    cols = {temp_name: np.asarray(temp)}
    for a, name in enumerate(columns):
        cols[name] = raw[:, a]
    for a, name in enumerate(columns):
        cols[f"{name}_comp"] = result.comp[:, a].astype(np.int64)
    if still is not None:
        cols["still"] = np.asarray(still, dtype=np.int64)
    cols["stale"] = result.stale.astype(np.int64)
    cols["extrapolated"] = result.extrapolated.astype(np.int64)
    cols["model_sequence"] = result.sequence.astype(np.int64)
    paths = {"replay": os.path.join(out_dir, "replay.csv"), "commits": os.path.join(out_dir, "commits.json"),
             "plot": os.path.join(out_dir, "learn.png")}
    write_csv(paths["replay"], cols)
    if result.image is not None:
        paths["model"] = os.path.join(out_dir, "model.bin")
        with atomic_output(paths["model"], "wb") as fh:
            fh.write(result.image)
    with atomic_output(paths["commits"]) as fh:
        json.dump({"config": result.config.as_dict(), "commits": result.commits,
                   "solves": result.solves}, fh, indent=1)
    plot_replay(result, paths["plot"], columns)
    return paths


def plot_replay(result, path, columns):
    """Raw and corrected readings, the model sequence, stale and
    extrapolation flags and the temperature over the sample index."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    n = len(result.t)
    idx = np.arange(n)
    fig, ax = plt.subplots(3, 1, figsize=(9, 7), sharex=True)
    ax[0].plot(idx, result.t, lw=0.6, color="tab:red")
    ax[0].set_ylabel("t (image unit)")
    for a, name in enumerate(columns):
        ax[1].plot(idx, result.comp[:, a], lw=0.4, label=f"{name} corrected")
    ax[1].set_ylabel("corrected (LSB)")
    ax[1].legend(loc="upper right", fontsize=7)
    ax[2].step(idx, result.sequence, where="post", label="model sequence")
    ax[2].fill_between(idx, 0, result.stale * max(1, int(result.sequence.max())), step="post",
                       alpha=0.3, color="tab:red", label="stale")
    ax[2].fill_between(idx, 0, result.extrapolated * 0.5, step="post", alpha=0.3, color="tab:gray",
                       label="extrapolated")
    for c in result.commits:
        for x in ax:
            x.axvline(c["index"], color="tab:green", lw=0.6, alpha=0.6)
    ax[2].set_ylabel("model / flags")
    ax[2].set_xlabel("sample")
    ax[2].legend(loc="upper left", fontsize=7)
    fig.tight_layout()
    with atomic_output(path, "wb") as fh:
        fig.savefig(fh, format="png", dpi=90)
    plt.close(fig)
