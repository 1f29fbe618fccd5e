#!/usr/bin/python3
"""Method 1's RTS smoother against its filter on the moving-truth records (docs/filtering.md, "S5").

    /usr/bin/python3 scripts/smoother_fallback_study.py FOGPIPE WORKDIR SEEDS [--discrepancy]
                                                        [extra run options]

SEEDS like 1,2,3,4,5 (design) or 6,7,8 (check). Records: the moving-truth grid of
scripts/filter_limit_study.py (`fogpipe simulate --profile none --rate-profile ...`, record seed
100 seed + 10 scenario + level). Per record two `fogpipe run --store-filtered-imfs` (filter, and
`--smooth`); per-record caches in WORKDIR/cache (delete to recompute). The truth is used only to
score. Prints, over the records: smoother RMS / filter RMS, median (range), and the records where
the smoother is worse (at all, by more than 1e-4, by more than 1 %), method 1 / raw and / best
truth-free reference filter (medians), for
  "as run":     the smoother's output as FOGPIPE wrote it;
  "with check": each component's smoother output replaced by its filter's where the smoothed
                residuals' mean square is below the filtered ones' (the check of rts_smoother.h,
                applied here in Python), and how many components that replaces.
With --discrepancy also (11 more runs per record, `--smooth --q 1e-50 .. 1e-30`, where the check
is off): on each component the check flags, the smoother at the q whose smoothed residuals' mean
square is closest to the component's white-noise share (Morozov's discrepancy principle), per
scenario and overall. With a fogpipe built before the check (commit 8835fda) "as run" is the old behaviour and "with
check" the new one; with a fogpipe that has it both rows agree. About 1 min for 45 records with 2
processes. Needs numpy, scipy and h5py (Debian's /usr/bin/python3).
"""
import json, os, shutil, subprocess, sys, tempfile
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import h5py
import numpy as np
import filter_limit_study as fls
from concurrent.futures import ProcessPoolExecutor
FOG, WD, SEEDS = sys.argv[1], sys.argv[2], [int(s) for s in sys.argv[3].split(",")]
DISCREPANCY = "--discrepancy" in sys.argv[4:]
EXTRA = [a for a in sys.argv[4:] if a != "--discrepancy"]
Q_GRID = [10.0 ** e for e in range(-50, -28, 2)]


def read(record, name, smooth, more=()):
    od = tempfile.mkdtemp(dir=WD)
    try:
        cmd = [FOG, "run", record, "-o", od, "--threads", "1", "--store-filtered-imfs",
               "--imf-storage", "float64"] + (["--smooth"] if smooth else []) + EXTRA + list(more)
        subprocess.run(cmd, check=True, capture_output=True)
        with h5py.File(os.path.join(od, name + ".fogpipe.h5"), "r") as f:
            a = f["axes/axis0"]
            d = {k: a["kalman/" + k][:] for k in ("q", "r", "white_noise_variance")}
            d["out"] = a["kalman/filtered"][:].astype(np.float64).T
            d["replaced"] = (a["kalman/smoother_replaced"][:] if "smoother_replaced" in a["kalman"]
                             else np.zeros(d["out"].shape[0], dtype=np.int64))
            d["comps"] = np.vstack([a["decomposition/imfs"][:].T, a["decomposition/residue"][:][None, :]])
            d["m1"] = a["signals/method1"][:]
            d["mr"] = float(a["preprocessing/mean_removed"][()])
            d["dr"] = int(a["preprocessing/dropped_samples"][0])
            d["refs"] = {n: a[f"signals/reference/{n}/signal"][:] for n in fls.REFERENCES}
        return d
    finally:
        shutil.rmtree(od)


def one(arg):
    name = arg[0]
    cache = os.path.join(WD, "cache", name + ".npz")
    if os.path.exists(cache):
        return name
    record = os.path.join(WD, "records", name + ".h5")
    tj = json.load(open(record + ".truth.json"))
    f = read(record, name, False)
    s = read(record, name, True)
    n = f["m1"].size
    target = fls.true_rate_rad_s(tj, tj["num_samples"])[:][f["dr"]:][:n] - f["mr"]
    np.savez(cache, target=target, comps=f["comps"], filt=f["out"], smooth=s["out"],
             q=f["q"], r=f["r"], share=f["white_noise_variance"], replaced=s["replaced"],
             m1f=f["m1"], m1s=s["m1"],
             bestref=min(fls.rms(f["refs"][r] - target) for r in fls.REFERENCES))
    return name


def one_q_grid(arg):
    """The smoother's component outputs at every q of Q_GRID (cached in WORKDIR/qgrid)."""
    name = arg[0]
    cache = os.path.join(WD, "qgrid", name + ".npz")
    if not os.path.exists(cache):
        record = os.path.join(WD, "records", name + ".h5")
        out = [read(record, name, True, ["--q", repr(q)])["out"] for q in Q_GRID]
        np.savez(cache, out=np.array(out))
    return name


def discrepancy(name):
    """Total RMS of the filter's sum with the flagged components' filter outputs replaced by the
    smoother at the q whose smoothed residual mean square is closest to the share; and the
    filter's own total RMS."""
    d = np.load(os.path.join(WD, "cache", name + ".npz"))
    grid = np.load(os.path.join(WD, "qgrid", name + ".npz"))["out"]
    t, c, f, s = d["target"], d["comps"], d["filt"], d["smooth"]
    replaced = d["replaced"] if "replaced" in d else np.zeros(c.shape[0])
    mix = s.copy()
    for k in range(c.shape[0]):
        if replaced[k] or np.mean((c[k] - s[k]) ** 2) < np.mean((c[k] - f[k]) ** 2):
            r = np.array([np.mean((c[k] - grid[j, k]) ** 2) for j in range(len(Q_GRID))])
            j = int(np.argmin(np.abs(np.log(np.maximum(r, 1e-300) / d["share"][k]))))
            mix[k] = grid[j, k]
    return fls.rms(mix.sum(0) - t) / fls.rms(f.sum(0) - t)


def score(name):
    d = np.load(os.path.join(WD, "cache", name + ".npz"))
    t, c, f, s = d["target"], d["comps"], d["filt"], d["smooth"]
    checked = s.copy()
    replaced = 0
    by_fogpipe = d["replaced"] if "replaced" in d else np.zeros(c.shape[0])
    for k in range(c.shape[0]):
        if by_fogpipe[k] or np.mean((c[k] - s[k]) ** 2) < np.mean((c[k] - f[k]) ** 2):
            checked[k] = f[k]
            replaced += 1
    raw, ref = fls.rms(c.sum(0) - t), float(d["bestref"])
    return (raw, ref, fls.rms(f.sum(0) - t), fls.rms(s.sum(0) - t),
            fls.rms(checked.sum(0) - t), replaced, c.shape[0])


def report(rows):
    v = np.array([r[:5] for r in rows])
    raw, ref, filt = v[:, 0], v[:, 1], v[:, 2]
    print("records", len(rows), "| filter / raw %.4f, filter / best ref %.3f (medians)"
          % (np.median(filt / raw), np.median(filt / ref)))
    for label, col in (("as run", 3), ("with check", 4)):
        q = v[:, col] / filt
        print("%-10s smoother / filter %.6f (%.6f-%.6f), worse: %d, > 1e-4: %d, > 1 %%: %d; "
              "smoother / raw %.4f, / best ref %.3f"
              % (label, np.median(q), q.min(), q.max(), (q > 1).sum(), (q > 1 + 1e-4).sum(),
                 (q > 1.01).sum(), np.median(v[:, col] / raw), np.median(v[:, col] / ref)))
    print("components replaced by the check (by fogpipe or here): %d of %d" % (sum(r[5] for r in rows),
                                                           sum(r[6] for r in rows)))


if __name__ == "__main__":
    os.makedirs(os.path.join(WD, "cache"), exist_ok=True)
    names = fls.simulate(FOG, WD, SEEDS)
    with ProcessPoolExecutor(2) as ex:
        done = list(ex.map(one, names))
    report([score(n) for n in done])
    if DISCREPANCY:
        os.makedirs(os.path.join(WD, "qgrid"), exist_ok=True)
        with ProcessPoolExecutor(2) as ex:
            list(ex.map(one_q_grid, names))
        q = {n: discrepancy(n) for n in done}
        for scenario, _ in fls.SCENARIOS:
            v = [x for n, x in q.items() if n.startswith(scenario)]
            print("discrepancy smoother / filter, %s: %.3f (%.3f-%.3f), > 1e-4 worse on %d of %d"
                  % (scenario, np.median(v), min(v), max(v), sum(x > 1 + 1e-4 for x in v),
                     len(v)))
        v = list(q.values())
        print("discrepancy smoother / filter, all: %.4f (%.4f-%.4f), > 1e-4 worse on %d of %d"
              % (np.median(v), min(v), max(v), sum(x > 1 + 1e-4 for x in v), len(v)))
