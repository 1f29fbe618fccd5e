#!/usr/bin/python3
"""The limit of filters built on the decomposition: oracles against the truth-free filters.

    /usr/bin/python3 scripts/filter_limit_study.py FOGPIPE WORKDIR [--jobs 2] [--seeds 1,2,3,4,5]

FOGPIPE is the fogpipe binary, WORKDIR a scratch folder (records, per-record result caches; the
results files of the runs are deleted as soon as they are read). Needs numpy, scipy, h5py
(Debian's /usr/bin/python3). Prints the tables of docs/filtering.md, "The limit of filters built
on the decomposition". A rerun reuses WORKDIR/results/<record>.json (delete them to recompute).

Records: the moving-truth grid of tests/algorithms/method/moving_truth.h, written by `fogpipe
simulate --profile none --rate-profile ...` (1 h at 10 Hz, white angle random walk N = 0.01 /
0.05 / 0.2 deg/sqrt(h), nothing else; record seed = 100 seed + 10 scenario + level, as
MovingTruthGrid), the true rate rate_rad_s rebuilt from the truth sidecar's `input_rate`.
Every RMS error is against that truth, over the analysed samples, in rad/s; the tables print
ratios (to raw, to the best truth-free reference filter of the same record).

Estimates per record:
  1. Truth-free: raw (the preprocessed signal), method 1 (`fogpipe run` defaults), method 1
     `--smooth`, and the four reference filters (`signals/reference/<name>/signal`); "best ref" is
     the best of the four on that record.
  2. Oracle A, method 1's own filter family tuned with the truth. Each component's output depends
     only on its own AR model and (q, R), so one `fogpipe run --store-filtered-imfs` per setting
     gives every component's output at that setting (`kalman/filtered`, the smoother's output
     with --smooth). Settings: --q-scale 10^(-4..4) at --r-scale 1; --q-scale = --r-scale = 0.01
     and 100 (the same ratio q/R, another R: the diffuse start's weight); an absolute --q 10^e
     shared by all components, R each one's R_k from the rule, e in steps of 1 so that every
     component sees ratios q/R_k from 1e-8 to 1e4 (R_k spans ~30 decades; this also frees the
     components the rule judges pure noise, q = 0 and P(0|0) = 0, which no scale moves); and an
     absolute --r 10^e shared by all components, q by the moment match, from 1e-6 to 100 times
     each component's variance (the rule's R_k is 1e-20 and less of a slow component's
     variance). Per component the setting is chosen by coordinate descent on the total RMS
     (starts: the default and the best global setting; the better end point is kept). "global"
     = the best single setting of that list with the truth. Filter and smoother separately.
  3. Oracle B, per-component linear oracle: each component (the band-limited IMFs and residue,
     `decomposition/imfs` + `residue` of the default run) through a zero-phase order-4
     Butterworth (scipy sosfiltfilt, odd extension over 8 cutoff periods, as fogpipe's) with its
     own cutoff (46 log-spaced 1e-4..4.5 Hz, or "pass") and its own least-squares gain, chosen
     with the truth by coordinate descent from the grid cutoff nearest C's Butterworth for all
     components. A common cutoff with gain 1 is the global Butterworth (the filter is linear), so
     B starts at (and ends below) a global Butterworth.
  4. Oracle C, the global bound on the raw signal: zero-phase Butterworth with the oracle cutoff
     (61 log-spaced 1 mHz..1 Hz, then golden section in log), centred moving average with the
     oracle window (log grid, then every window around the best), and the Wiener filter with the
     true spectra H = S_t / (S_t + S_n) (S_t the periodogram of the true rate, S_n the white
     level N^2 fs), applied by DFT to the record and its mirror image. "C" = the best of the
     three.
  Diagnostics: RMS(filter output) / RMS(component) per component at nine settings on one ramp
  record (can any q, R attenuate a component?); oracle B's output swapped into oracle A's, one
  component at a time (which components' filters hold A back); the share of the squared error
  in period bands (where the error goes) for method 1, oracle A and the best reference; smoother
  against filter at the oracle settings, and the change of the total when one component's filter
  output is swapped for its smoother output (same setting); the smoother/filter ratio at the
  defaults with --band-limit-ratio 0, and over the middle 80 % of the record (away from the
  diffuse start and the smoother's end).

Run time (measured, 45 records): 64-70 settings x (filter, smoother) + 4 more runs = ~135 fogpipe
runs of ~0.2 s per record, 28 min of CPU, 55 min wall with --jobs 2 on a shared 2-core machine
(load average 3-6 from other work); printing the tables again from the caches takes ~10 s.
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor

import h5py
import numpy as np
from scipy import signal as sps

DEG_H = math.pi / 180.0 / 3600.0  # rad/s per deg/h
FS_HZ = 10.0
DURATION_S = 3600.0
SCENARIOS = [("steps", "step:600:20,step:1500:-35,step:2400:25"),
             ("ramps", "ramp:300:1300:0.02,ramp:2000:3000:-0.03"),
             ("sines", "sine:0.002:20,sine:0.011:8")]
LEVELS_DEG_SQRT_H = [0.01, 0.05, 0.2]
REFERENCES = ["butterworth", "moving_average", "rw_kalman", "rw_rts"]
Q_SCALES = [10.0 ** e for e in range(-4, 5)]
PERIOD_BANDS_S = [0.0, 10.0, 100.0, 1000.0, math.inf]  # error shares by period band


def record_name(scenario, level, seed):
    return f"{scenario}_N{level}_s{seed}"


def simulate(fogpipe, workdir, seeds):
    os.makedirs(os.path.join(workdir, "records"), exist_ok=True)
    names = []
    for s, (scenario, profile) in enumerate(SCENARIOS):
        for l, level in enumerate(LEVELS_DEG_SQRT_H):
            for seed in seeds:
                name = record_name(scenario, level, seed)
                path = os.path.join(workdir, "records", name + ".h5")
                if not os.path.exists(path + ".truth.json"):
                    subprocess.run(
                        [fogpipe, "simulate", "--profile", "none", "--duration-s",
                         str(DURATION_S), "--sample-rate-hz", str(FS_HZ), "--n-deg-sqrt-h",
                         str(level), "--rate-profile", profile, "--seed",
                         str(seed * 100 + s * 10 + l), "--units", "rad/s", "--no-temperature",
                         "-o", path], check=True, capture_output=True)
                names.append((name, scenario, level, seed))
    return names


def true_rate_rad_s(truth_json, n):
    """The true rate at t_k = k / fs from the sidecar's input_rate (rate_profile.h)."""
    t = np.arange(n) / FS_HZ
    x = np.zeros(n)
    for c in truth_json["input_rate"]:
        if c["kind"] == "constant":
            x += c["value_deg_h"] * DEG_H
        elif c["kind"] == "step":
            x += np.where(t >= c["start_s"], c["value_deg_h"] * DEG_H, 0.0)
        elif c["kind"] == "ramp":
            x += c["slope_deg_h_per_s"] * DEG_H * (np.clip(t, c["start_s"], c["end_s"])
                                                     - c["start_s"])
        elif c["kind"] == "sine":
            x += c["amplitude_deg_h"] * DEG_H * np.sin(
                2 * math.pi * c["frequency_hz"] * t + c.get("phase_rad", 0.0))
        else:
            raise ValueError("unknown rate component " + c["kind"])
    return x + truth_json["earth_rate_rad_s"] + truth_json["axes"][0]["bias_rad_s"]


def run_fogpipe(fogpipe, record, args, read_imfs=False):
    """One `fogpipe run` of one record; returns the arrays this study reads, then deletes it."""
    out = tempfile.mkdtemp(prefix="run-", dir=os.path.dirname(os.path.dirname(record)))
    try:
        storage = "float64" if read_imfs else "float32"
        cmd = [fogpipe, "run", record, "-o", out, "--threads", "1", "--store-filtered-imfs",
               "--imf-storage", storage] + list(args)
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            raise RuntimeError(" ".join(cmd) + ": " + r.stderr)
        stem = os.path.splitext(os.path.basename(record))[0]
        with h5py.File(os.path.join(out, stem + ".fogpipe.h5"), "r") as f:
            a = f["axes/axis0"]
            d = {"filtered": a["kalman/filtered"][:].astype(np.float64).T,
                 "q": a["kalman/q"][:], "r": a["kalman/r"][:],
                 "method1": a["signals/method1"][:],
                 "mean_removed": float(a["preprocessing/mean_removed"][()]),
                 "dropped": int(a["preprocessing/dropped_samples"][0])}
            if read_imfs:
                d["components"] = np.vstack([a["decomposition/imfs"][:].T,
                                             a["decomposition/residue"][:][None, :]])
                d["period_samples"] = a["decomposition/mean_period_samples"][:]
                d["refs"] = {n: a[f"signals/reference/{n}/signal"][:] for n in REFERENCES}
        return d
    finally:
        shutil.rmtree(out, ignore_errors=True)


def rms(e):
    return float(np.sqrt(np.mean(np.square(e))))


def coordinate_descent(outputs, target, start):
    """outputs[s, k, :]: component k at setting s; picks one s per k minimising the total RMS."""
    choice = list(start)
    num_k = outputs.shape[1]
    est = sum(outputs[choice[k], k] for k in range(num_k))
    for _ in range(30):
        changed = False
        for k in range(num_k):
            rest = target - (est - outputs[choice[k], k])
            cost = np.sum(np.square(rest[None, :] - outputs[:, k]), axis=1)
            best = int(np.argmin(cost))
            if cost[best] < cost[choice[k]] * (1 - 1e-12):
                est = target - rest + outputs[best, k]
                choice[k] = best
                changed = True
        if not changed:
            break
    return choice, est


def zero_phase_butterworth(x, cutoff_hz):
    sos = sps.butter(4, cutoff_hz / (FS_HZ / 2.0), output="sos")
    padlen = int(min(len(x) - 1, max(30, 8 * FS_HZ / cutoff_hz)))
    return sps.sosfiltfilt(sos, x, padtype="odd", padlen=padlen)


def oracle_butterworth(raw, target):
    grid = np.logspace(-3, 0, 61)
    costs = [rms(zero_phase_butterworth(raw, fc) - target) for fc in grid]
    i = int(np.argmin(costs))
    lo, hi = math.log(grid[max(i - 1, 0)]), math.log(grid[min(i + 1, len(grid) - 1)])
    g = (math.sqrt(5) - 1) / 2
    f = lambda u: rms(zero_phase_butterworth(raw, math.exp(u)) - target)
    a, b = hi - g * (hi - lo), lo + g * (hi - lo)
    fa, fb = f(a), f(b)
    for _ in range(25):
        if fa < fb:
            hi, b, fb = b, a, fa
            a = hi - g * (hi - lo)
            fa = f(a)
        else:
            lo, a, fa = a, b, fb
            b = lo + g * (hi - lo)
            fb = f(b)
    best = min((costs[i], grid[i]), (fa, math.exp(a)), (fb, math.exp(b)))
    return best[0], best[1]


def moving_average(x, h):
    c = np.concatenate([[0.0], np.cumsum(x)])
    i = np.arange(len(x))
    lo, hi = np.maximum(i - h, 0), np.minimum(i + h + 1, len(x))
    return (c[hi] - c[lo]) / (hi - lo)


def oracle_moving_average(raw, target):
    grid = sorted(set(int(round(v)) for v in np.logspace(0, math.log10(len(raw) / 2), 80)))
    costs = {h: rms(moving_average(raw, h) - target) for h in grid}
    h0 = min(costs, key=costs.get)
    j = grid.index(h0)
    for h in range(grid[max(j - 1, 0)], grid[min(j + 1, len(grid) - 1)] + 1):
        if h not in costs:
            costs[h] = rms(moving_average(raw, h) - target)
    h = min(costs, key=costs.get)
    return costs[h], 2 * h + 1


def oracle_wiener(raw, target, noise_variance):
    """Zero-phase Wiener filter with the true signal's periodogram and the white noise level,
    applied by DFT to the record extended by its mirror image (no jump at the wrap)."""
    n = len(raw)
    ext = lambda x: np.concatenate([x, x[::-1]])
    t = ext(target - target.mean())
    st = np.abs(np.fft.rfft(t)) ** 2 / (2 * n)
    h = st / (st + noise_variance)
    h[0] = 1.0
    y = np.fft.irfft(h * np.fft.rfft(ext(raw - raw.mean())), 2 * n)[:n] + raw.mean()
    return rms(y - target)


def band_shares(error, raw_mse):
    """Squared error per period band (PERIOD_BANDS_S), as fractions of raw's mean square error."""
    n = len(error)
    p = np.abs(np.fft.rfft(error)) ** 2
    p[1:(n + 1) // 2] *= 2.0
    p /= n * n
    freq = np.fft.rfftfreq(n, 1.0 / FS_HZ)
    period = np.where(freq > 0, 1.0 / np.maximum(freq, 1e-300), math.inf)
    out = []
    for lo, hi in zip(PERIOD_BANDS_S[:-1], PERIOD_BANDS_S[1:]):
        out.append(float(p[(period >= lo) & (period < hi)].sum() / raw_mse))
    return out


def study_record(args):
    fogpipe, workdir, name, level = args
    cache = os.path.join(workdir, "results", name + ".json")
    if os.path.exists(cache):
        with open(cache) as f:
            return json.load(f)
    t0 = time.time()
    record = os.path.join(workdir, "records", name + ".h5")
    with open(record + ".truth.json") as f:
        truth_json = json.load(f)
    d0 = run_fogpipe(fogpipe, record, [], read_imfs=True)
    ds = run_fogpipe(fogpipe, record, ["--smooth"])
    n = d0["method1"].size
    truth = true_rate_rad_s(truth_json, truth_json["num_samples"])[d0["dropped"]:][:n]
    target = truth - d0["mean_removed"]  # the truth as the mean-removed outputs see it
    comps = d0["components"]
    raw = comps.sum(axis=0)
    res = {"name": name, "raw": rms(raw - target)}
    res["method1"] = rms(d0["method1"] - target)
    res["method1_smooth"] = rms(ds["method1"] - target)
    for ref in REFERENCES:
        res[ref] = rms(d0["refs"][ref] - target)
    best_ref_name = min(REFERENCES, key=lambda r: res[r])
    res["best_ref"] = res[best_ref_name]
    res["best_ref_name"] = best_ref_name
    num_k = comps.shape[0]
    res["num_components"] = num_k
    res["period_s"] = [float(t) / FS_HZ for t in d0["period_samples"]] + [DURATION_S]

    # Oracle A: the settings.
    settings = [("q_scale", s, []) if abs(s - 1.0) < 1e-12 else
                ("q_scale", s, ["--q-scale", repr(s)]) for s in Q_SCALES]
    settings += [("qr_scale", 0.01, ["--q-scale", "0.01", "--r-scale", "0.01"]),
                 ("qr_scale", 100.0, ["--q-scale", "100", "--r-scale", "100"])]
    # An absolute q shared by all components (R stays each one's R_k): ratios q/R_k of
    # 1e-8..1e4 on every component, including those the rule judged pure noise (q = 0).
    lo = math.floor(math.log10(d0["r"].min())) - 8
    hi = math.ceil(math.log10(d0["r"].max())) + 4
    settings += [("q_abs", 10.0 ** e, ["--q", f"1e{e}"]) for e in range(lo, hi + 1)]
    # An absolute R shared by all components, q by the moment match from it: R from 1e-6 to 100
    # times each component's variance. The rule's R_k is the white fraction of the AR innovation
    # variance, 1e-20 and less of the variance on slow components, so no scale above reaches an
    # R that attenuates them; these settings can (R >> variance: the output tends to the mean).
    variances = comps.var(axis=1)
    lo = math.floor(math.log10(variances.min())) - 6
    hi = math.ceil(math.log10(variances.max())) + 2
    settings += [("r_abs", 10.0 ** e, ["--r", f"1e{e}"]) for e in range(lo, hi + 1)]
    pure = d0["q"] == 0.0
    default_index = Q_SCALES.index(1.0)
    res["settings"] = [[kind, value] for kind, value, _ in settings]
    res["pure_noise_components"] = int(pure.sum())
    for mode, base, extra in (("filter", d0, []), ("smooth", ds, ["--smooth"])):
        outs = np.empty((len(settings), num_k, n))
        for i, (_, _, a) in enumerate(settings):
            outs[i] = base["filtered"] if not a else run_fogpipe(fogpipe, record, a + extra)[
                "filtered"]
        global_costs = [rms(outs[i].sum(axis=0) - target) for i in range(len(settings))]
        g = int(np.argmin(global_costs))
        best = None
        for start in ([default_index] * num_k, [g] * num_k):
            choice, est = coordinate_descent(outs, target, start)
            if best is None or rms(est - target) < rms(best[1] - target):
                best = (choice, est)
        choice, est = best
        res[f"oracleA_{mode}"] = rms(est - target)
        res[f"oracleA_{mode}_choice"] = choice
        res[f"oracleA_global_{mode}"] = global_costs[g]
        res[f"oracleA_global_{mode}_setting"] = list(settings[g][:2])
        res[f"oracleA_{mode}_bands"] = band_shares(est - target, res["raw"] ** 2)
        if mode == "filter":
            filter_outs, filter_choice, filter_est = outs, choice, est
        else:
            # The smoother at the filter's oracle settings, and per component: does swapping
            # component k's filter output for its smoother output (same setting) raise the RMS?
            swapped = sum(outs[filter_choice[k], k] for k in range(num_k))
            res["smooth_at_filter_oracle"] = rms(swapped - target)
            base_rms = res["oracleA_filter"]
            deltas = []
            for k in range(num_k):
                e = filter_est - filter_outs[filter_choice[k], k] + outs[filter_choice[k], k]
                deltas.append(rms(e - target) / base_rms - 1.0)
            res["swap_delta"] = deltas
            # ... and at the default settings.
            deltas = []
            for k in range(num_k):
                e = d0["method1"] - d0["filtered"][k] + ds["filtered"][k]
                deltas.append(rms(e - target) / res["method1"] - 1.0)
            res["swap_delta_default"] = deltas
        del outs
    res["method1_bands"] = band_shares(d0["method1"] - target, res["raw"] ** 2)
    res["best_ref_bands"] = band_shares(d0["refs"][best_ref_name] - target, res["raw"] ** 2)

    # Oracle C: global bound on the raw signal.
    res["oracleC_butterworth"], res["oracleC_butterworth_cutoff_hz"] = oracle_butterworth(
        raw, target)
    res["oracleC_moving_average"], res["oracleC_moving_average_window"] = \
        oracle_moving_average(raw, target)
    noise_variance = (level * math.pi / 180.0 / 60.0) ** 2 * FS_HZ  # N [rad/sqrt(s)]^2 fs
    res["oracleC_wiener"] = oracle_wiener(raw, target, noise_variance)
    res["oracleC"] = min(res["oracleC_butterworth"], res["oracleC_moving_average"],
                         res["oracleC_wiener"])

    # Oracle B: per-component cutoff + gain.
    cutoffs = list(np.logspace(-4, math.log10(4.5), 46))
    cand = np.empty((len(cutoffs) + 1, num_k, n))
    for j, fc in enumerate(cutoffs):
        for k in range(num_k):
            cand[j, k] = zero_phase_butterworth(comps[k], fc)
    cand[len(cutoffs)] = comps  # "pass"
    fc0 = res["oracleC_butterworth_cutoff_hz"]
    start = int(np.argmin(np.abs(np.log(np.array(cutoffs) / fc0))))
    choice = [start] * num_k
    gains = np.ones(num_k)
    est = sum(cand[start, k] for k in range(num_k))
    for _ in range(30):
        before = rms(est - target)
        for k in range(num_k):
            rest = target - (est - gains[k] * cand[choice[k], k])
            y = cand[:, k]
            yy = np.maximum(np.sum(y * y, axis=1), 1e-300)
            gk = np.sum(y * rest[None, :], axis=1) / yy
            cost = np.sum(np.square(rest), axis=0) - gk * gk * yy
            j = int(np.argmin(cost))
            choice[k], gains[k] = j, gk[j]
            est = target - rest + gains[k] * cand[j, k]
        if rms(est - target) > before * (1 - 1e-9):
            break
    res["oracleB"] = rms(est - target)
    # Which components' filters hold oracle A back: swap one component's oracle A filter output
    # for its oracle B output (relative change of the total RMS; negative: B's is better).
    res["swap_B_into_A"] = [
        rms(filter_est - filter_outs[filter_choice[k], k] + gains[k] * cand[choice[k], k]
            - target) / res["oracleA_filter"] - 1.0 for k in range(num_k)]
    res["oracleB_start"] = rms(zero_phase_butterworth(raw, cutoffs[start]) - target)
    del cand

    # S5 diagnostics at the defaults: without band limiting; and away from both ends (the
    # filter's diffuse start and the smoother's end), over the middle 80 % of the record.
    f = run_fogpipe(fogpipe, record, ["--band-limit-ratio", "0"])["method1"]
    s = run_fogpipe(fogpipe, record, ["--band-limit-ratio", "0", "--smooth"])["method1"]
    res["bl0_filter"], res["bl0_smooth"] = rms(f - target), rms(s - target)
    mid = slice(n // 10, n - n // 10)
    res["mid_filter"] = rms(d0["method1"][mid] - target[mid])
    res["mid_smooth"] = rms(ds["method1"][mid] - target[mid])
    res["mid_oracle_filter"] = rms(filter_est[mid] - target[mid])
    res["mid_smooth_at_filter_oracle"] = rms(swapped[mid] - target[mid])
    res["seconds"] = time.time() - t0
    os.makedirs(os.path.dirname(cache), exist_ok=True)
    with open(cache + ".tmp", "w") as f:
        json.dump(res, f)
    os.replace(cache + ".tmp", cache)
    return res


def fmt_cell(values):
    v = np.asarray(values)
    return f"{np.median(v):.3f} ({v.min():.2f}-{v.max():.2f})"


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    p.add_argument("fogpipe")
    p.add_argument("workdir")
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--seeds", default="1,2,3,4,5")
    a = p.parse_args()
    fogpipe = os.path.abspath(a.fogpipe)
    workdir = os.path.abspath(a.workdir)
    seeds = [int(s) for s in a.seeds.split(",")]
    t0 = time.time()
    records = simulate(fogpipe, workdir, seeds)
    jobs = [(fogpipe, workdir, name, level) for name, _, level, _ in records]
    with ProcessPoolExecutor(max_workers=a.jobs) as pool:
        results = list(pool.map(study_record, jobs))
    by_cell = {}
    for (name, scenario, level, seed), r in zip(records, results):
        by_cell.setdefault((scenario, level), []).append(r)
    print(f"{len(results)} records, seeds {a.seeds}; wall {time.time() - t0:.0f} s this call, "
          f"{sum(r['seconds'] for r in results):.0f} s of per-record work (cached or not)")

    cols = [("method1", "method 1"), ("method1_smooth", "m1 --smooth"),
            ("best_ref", "best ref"), ("oracleA_global_filter", "A global filt"),
            ("oracleA_global_smooth", "A global smooth"), ("oracleA_filter", "A per-comp filt"),
            ("oracleA_smooth", "A per-comp smooth"), ("oracleB", "B per-comp LP"),
            ("oracleC_butterworth", "C butterworth"), ("oracleC_moving_average", "C mov. avg"),
            ("oracleC_wiener", "C wiener"), ("oracleC", "C best")]
    for denom, title in (("raw", "RMS / raw"), ("best_ref", "RMS / best truth-free reference")):
        print(f"\n{title}: median over seeds (min-max)")
        print("| cell | " + " | ".join(c[1] for c in cols) + " |")
        print("|---" * (len(cols) + 1) + "|")
        for (scenario, level), rs in by_cell.items():
            row = [fmt_cell([r[c] / r[denom] for r in rs]) for c, _ in cols]
            print(f"| {scenario} N={level} | " + " | ".join(row) + " |")
        allr = [r for rs in by_cell.values() for r in rs]
        row = [fmt_cell([r[c] / r[denom] for r in allr]) for c, _ in cols]
        print("| all 45 | " + " | ".join(row) + " |")

    allr = [r for rs in by_cell.values() for r in rs]
    def count(pred):
        return sum(1 for r in allr if pred(r))
    print("\nS3 (<= 1.25 x best truth-free ref), records meeting it of", len(allr))
    for c, label in cols[:8]:
        print(f"  {label}: {count(lambda r: r[c] <= 1.25 * r['best_ref'])}")
    print("Best truth-free reference per record:",
          {n: count(lambda r, n=n: r['best_ref_name'] == n) for n in REFERENCES})

    print("\nS5, smoother / filter (median (min-max) over records; records where smoother >"
          " filter):")
    for label, s, f in (("defaults", "method1_smooth", "method1"),
                        ("oracle A per component (each its own)", "oracleA_smooth",
                         "oracleA_filter"),
                        ("smoother at the filter's oracle settings", "smooth_at_filter_oracle",
                         "oracleA_filter"),
                        ("oracle A global (each its own)", "oracleA_global_smooth",
                         "oracleA_global_filter"),
                        ("defaults, --band-limit-ratio 0", "bl0_smooth", "bl0_filter"),
                        ("defaults, middle 80 % of the record", "mid_smooth", "mid_filter"),
                        ("filter's oracle settings, middle 80 %", "mid_smooth_at_filter_oracle",
                         "mid_oracle_filter")):
        v = [r[s] / r[f] for r in allr]
        print(f"  {label}: {fmt_cell(v)}; {sum(1 for x in v if x > 1)} of {len(v)}")
    print("  swapping one component's filter output for its smoother output (same setting),"
          " change of the total RMS by component (imf1 fastest; median (min-max) over records):")
    for key, label in (("swap_delta_default", "defaults"), ("swap_delta", "oracle A filter")):
        kmax = max(r["num_components"] for r in allr)
        parts = []
        for k in range(kmax):
            v = [100 * r[key][k] for r in allr if k < r["num_components"] - 1]
            if v:
                parts.append(f"imf{k + 1} {np.median(v):+.2f}% ({min(v):+.1f}..{max(v):+.1f})")
        v = [100 * r[key][-1] for r in allr]
        parts.append(f"residue {np.median(v):+.2f}% ({min(v):+.1f}..{max(v):+.1f})")
        print(f"   {label}: " + "; ".join(parts))

    print("  oracle B's output swapped for oracle A's filter output, one component at a time:")
    kmax = max(r["num_components"] for r in allr)
    parts = []
    for k in range(kmax - 1):
        v = [100 * r["swap_B_into_A"][k] for r in allr if k < r["num_components"] - 1]
        parts.append(f"imf{k + 1} {np.median(v):+.1f}% ({min(v):+.0f}..{max(v):+.0f})")
    v = [100 * r["swap_B_into_A"][-1] for r in allr]
    parts.append(f"residue {np.median(v):+.1f}% ({min(v):+.0f}..{max(v):+.0f})")
    print("   " + "; ".join(parts))

    print("\nWhere the squared error goes: share of raw's MSE in period bands "
          + ", ".join(f"{lo:g}-{hi:g} s" for lo, hi in zip(PERIOD_BANDS_S[:-1], PERIOD_BANDS_S[1:]))
          + " (median over the 15 records of each scenario)")
    for scenario, _ in SCENARIOS:
        rs = [r for (s, _), v in by_cell.items() if s == scenario for r in v]
        for key, label in (("method1_bands", "method 1"),
                           ("oracleA_filter_bands", "oracle A filter"),
                           ("best_ref_bands", "best ref")):
            shares = np.median(np.array([r[key] for r in rs]), axis=0)
            print(f"  {scenario:6s} {label:16s} " + " ".join(f"{x:.4f}" for x in shares))

    print("\nOracle A per-component choices: how often each kind of setting was chosen")
    kinds = {}
    for r in allr:
        for i in r["oracleA_filter_choice"]:
            kind, value = r["settings"][i]
            kinds[kind] = kinds.get(kind, 0) + 1
    print("  filter:", kinds)
    print("\nOracle B start (global oracle cutoff) / oracle C butterworth (check ~1):",
          fmt_cell([r["oracleB_start"] / r["oracleC_butterworth"] for r in allr]))
    # Can any setting attenuate a component? RMS of each component's filter output over the
    # component's own RMS, on one record (the slow components stay at 1.00 whatever q and R).
    name = record_name("ramps", 0.05, seeds[0])
    record = os.path.join(workdir, "records", name + ".h5")
    print(f"\nRMS(filtered component) / RMS(component) on {name} (imf1 first, residue last):")
    for a in ([], ["--q-scale", "1e-4"], ["--q-scale", "1e4"], ["--q", "1e-48"], ["--q", "1e-40"],
              ["--q", "1e-30"], ["--r", "1e-12"], ["--r", "1e-9"], ["--r", "1e-6"]):
        d = run_fogpipe(fogpipe, record, a, read_imfs=True)
        ratios = d["filtered"].std(axis=1) / d["components"].std(axis=1)
        print(f"  {' '.join(a) or 'defaults':16s} " + " ".join(f"{x:.2f}" for x in ratios))
    print(f"Total wall time of this call: {time.time() - t0:.0f} s")


if __name__ == "__main__":
    main()
