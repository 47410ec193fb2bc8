#!/usr/bin/env python3
"""Six snapshots of a rings run, each particle coloured by the piece it is
in (linked within 1.5 spacings), as rings_shipped.png:

    /usr/bin/python3 docs/results/stability_session40/rings_snapshots.py RUN OUT.png"""
import glob
import os
import sys

import h5py
import matplotlib
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..",
                                "taylor_session39"))
from rings_pieces import components, spacing  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    run, out = sys.argv[1], sys.argv[2]
    dx = spacing(run)
    snaps = sorted(glob.glob(os.path.join(run, "snap_*.h5")))
    fig, axes = plt.subplots(2, 3, figsize=(15, 8))
    for ax, path in zip(axes.flat, [snaps[i] for i in (6, 10, 14, 18, 22, len(snaps) - 1)]):
        with h5py.File(path, "r") as f:
            x, time = np.array(f["position"])[:, :2], float(f.attrs["time_s"][0])
        count, label = components(x, 1.5 * dx)
        ax.scatter(x[:, 0] * 1e3, x[:, 1] * 1e3, c=label % 10, cmap="tab10", s=1)
        ax.set_aspect("equal")
        ax.set_xlabel("x (mm)")
        ax.set_title("t = %.2f ms, %d connected piece%s" % (time * 1e3, count,
                                                            "" if count == 1 else "s"))
    fig.suptitle(os.path.basename(run.rstrip("/")))
    fig.tight_layout()
    fig.savefig(out, dpi=70)


if __name__ == "__main__":
    main()
