#!/usr/bin/python3
"""Pictures of a fogpipe sweep (fogpipe-sweep-v1, written by `fogpipe sweep`).

  scripts/plot_sweep.py OUT/<stem>.sweep.h5 [-o picture.png] [--metric rms_error|N|K|B|Q|R]

For every axis and EMD sift count: one heat map of the metric over (q_scale, r_scale) per AR
order (log colour scale, the best cell of each map marked), and the mean one-step fit % of the
components against the AR order. Needs only h5py, numpy and matplotlib (Debian packages).
"""
import argparse
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def groups(h5):
    for axis, g in h5["axes"].items():
        for name, t in g.items():
            yield axis, name, t


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("sweep")
    ap.add_argument("-o", "--output")
    ap.add_argument("--metric")
    a = ap.parse_args()
    out = a.output or a.sweep.rsplit(".h5", 1)[0] + ".png"
    with h5py.File(a.sweep, "r") as h5:
        tables = list(groups(h5))
        orders_all = [np.unique(t["ar_order"][()]) for _, _, t in tables]
        ncols = max(len(o) for o in orders_all) + 1
        fig, axes = plt.subplots(len(tables), ncols, figsize=(2.6 * ncols, 2.8 * len(tables)),
                                 squeeze=False)
        for row, (axis, name, t) in enumerate(tables):
            metric = a.metric or ("rms_error" if t.attrs["has_truth"] else "N")
            values = t[metric][()]
            units = t[metric].attrs["units"]
            order, q, r = t["ar_order"][()], t["q_scale"][()], t["r_scale"][()]
            qs, rs = np.unique(q), np.unique(r)
            finite = values[np.isfinite(values) & (values > 0)]
            lo, hi = (finite.min(), finite.max()) if finite.size else (1e-300, 1.0)
            norm = matplotlib.colors.LogNorm(vmin=lo, vmax=max(hi, lo * 1.0001))
            for col, p in enumerate(orders_all[row]):
                ax = axes[row][col]
                grid = np.full((len(rs), len(qs)), np.nan)
                for v, qq, rr, pp in zip(values, q, r, order):
                    if pp == p:
                        grid[np.searchsorted(rs, rr), np.searchsorted(qs, qq)] = v
                im = ax.imshow(grid, origin="lower", norm=norm, cmap="viridis", aspect="auto")
                if np.isfinite(grid).any():
                    i, j = np.unravel_index(np.nanargmin(grid), grid.shape)
                    ax.plot(j, i, "r*", ms=10)
                ax.set_xticks(range(len(qs)), [f"{v:g}" for v in qs], fontsize=7)
                ax.set_yticks(range(len(rs)), [f"{v:g}" for v in rs], fontsize=7)
                ax.set_xlabel("q scale", fontsize=8)
                if col == 0:
                    ax.set_ylabel(f"{axis} sifts {name.split('_')[-1]}\nR scale", fontsize=8)
                ax.set_title(f"AR({int(p)})", fontsize=9)
            for col in range(len(orders_all[row]), ncols - 1):
                axes[row][col].axis("off")
            fig.colorbar(im, ax=axes[row][: ncols - 1].tolist(), label=f"{metric} [{units}]",
                         shrink=0.8)
            ax = axes[row][ncols - 1]
            fit = t["fit_one_step_mean_percent"][()]
            ps = orders_all[row]
            ax.plot(ps, [np.nanmean(fit[order == p]) for p in ps], "o-")
            ax.set_xlabel("AR order", fontsize=8)
            ax.set_ylabel("mean one-step fit [%]", fontsize=8)
            ax.grid(True, alpha=0.3)
        fig.suptitle(f"fogpipe sweep: {h5.attrs['recording']}", fontsize=10)
        fig.savefig(out, dpi=110)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
