#!/usr/bin/python3
"""Per-component scalar shrinkage of method 1, truth-free, against the best reference filter.

    /usr/bin/python3 scripts/component_gain_study.py FOGPIPE WORKDIR [extra fogpipe run options]

Uses the records and helpers of scripts/filter_limit_study.py (the 45 moving-truth records, seeds
1-5). For every component k of `fogpipe run --store-filtered-imfs` it forms
  v1: the filter output x_k shrunk about its mean by g_k = 1 - max(0, S_k - var(c_k - x_k)) / var(x_k)
      (S_k the component's white-noise share, kalman/white_noise_variance: the share the filter
      did not remove, as a Wiener gain on what it passed), and
  v2: the component itself shrunk by 1 - S_k / var(c_k),
clipped to [0, 1], and prints the RMS error against the truth / that of the best truth-free
reference filter, per cell (median over the seeds) and over all 45 records (docs/filtering.md,
"Per-component gains"). Needs numpy, scipy and h5py (Debian's /usr/bin/python3).
"""
import collections
import json
import os
import shutil
import subprocess
import sys
import tempfile
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import h5py
import numpy as np
import filter_limit_study as fls
from concurrent.futures import ProcessPoolExecutor
FOG = sys.argv[1]; WD = sys.argv[2]
extra = sys.argv[3:]

def one(arg):
    name, scenario, level, seed = arg
    record = os.path.join(WD, "records", name + ".h5")
    tj = json.load(open(record + ".truth.json"))
    out = {}
    for smooth in (False, True):
        od = tempfile.mkdtemp(dir=WD)
        cmd = [FOG, "run", record, "-o", od, "--threads", "1", "--store-filtered-imfs", "--imf-storage", "float64"] + (["--smooth"] if smooth else []) + extra
        subprocess.run(cmd, check=True, capture_output=True)
        with h5py.File(os.path.join(od, name + ".fogpipe.h5"), "r") as f:
            a = f["axes/axis0"]
            filt = a["kalman/filtered"][:].astype(np.float64).T
            comps = np.vstack([a["decomposition/imfs"][:].T, a["decomposition/residue"][:][None, :]])
            share = a["kalman/white_noise_variance"][:]
            m1 = a["signals/method1"][:]
            mr = float(a["preprocessing/mean_removed"][()]); dr = int(a["preprocessing/dropped_samples"][0])
            refs = {n: a[f"signals/reference/{n}/signal"][:] for n in fls.REFERENCES}
        shutil.rmtree(od)
        n = m1.size
        target = fls.true_rate_rad_s(tj, tj["num_samples"])[dr:][:n] - mr
        key = "s" if smooth else "f"
        out["raw"] = fls.rms(comps.sum(0) - target)
        out["m1" + key] = fls.rms(m1 - target)
        out["bestref"] = min(fls.rms(refs[r] - target) for r in fls.REFERENCES)
        # V1: residual-noise gain on the filter outputs
        tot = np.zeros(n); tot2 = np.zeros(n)
        gs = []
        for k in range(comps.shape[0]):
            c = comps[k]; x = filt[k]
            mu = x.mean()
            vx = np.var(x); rem = np.var(c - x); S = share[k]
            left = max(0.0, S - rem)
            g = 0.0 if vx <= 0 else min(1.0, max(0.0, 1.0 - left / vx))
            gs.append(g)
            tot += mu + g * (x - mu)
            vc = np.var(c); g2 = 0.0 if vc <= 0 else min(1.0, max(0.0, 1 - S / vc))
            tot2 += c.mean() + g2 * (c - c.mean())
        out["v1" + key] = fls.rms(tot - target)
        out["v2"] = fls.rms(tot2 - target)
        out["g" + key] = gs
    out["name"] = name
    return out

names = fls.simulate(FOG, WD, [1, 2, 3, 4, 5])
with ProcessPoolExecutor(2) as ex:
    res = list(ex.map(one, names))
json.dump(res, open(os.path.join(WD, "gain%s.json" % ("_".join(extra))), "w"))
cells = collections.defaultdict(list)
for r in res:
    cells[r["name"].rsplit("_s", 1)[0]].append(r)
print("cell m1f/ref m1s/ref v1f/ref v1s/ref v2/ref | v1f/raw")
allv = collections.defaultdict(list)
for c, rs in cells.items():
    row = []
    for k in ("m1f", "m1s", "v1f", "v1s", "v2"):
        vals = [r[k] / r["bestref"] for r in rs]; allv[k] += vals
        row.append("%.2f" % np.median(vals))
    print(c, *row, "%.3f" % np.median([r["v1f"] / r["raw"] for r in rs]))
for k, v in allv.items():
    print(k, "median %.2f max %.2f within1.25: %d/45" % (np.median(v), max(v), sum(x <= 1.25 for x in v)))
