#!/usr/bin/env python3
"""`fogpipe allan` on the real ADIS16405 recording against an independent numpy computation.

The overlapping Allan deviation is recomputed here from the HDF5 file (h5py) with numpy's
cumulative sum (NIST SP 1065 eq. 11 written on phase x = cumsum(y) / fs):
    sigma^2(m) = sum_i (x[i+2m] - 2 x[i+m] + x[i])^2 / (2 tau^2 (N - 2m + 1)),  tau = m / fs,
with the mean removed first (it cancels in the second difference, and removing it keeps the
cumulative sum small, so that its rounding error stays ~1e-13 relative for 1e6 samples) and
accumulated in float64. fogpipe must agree to 1e-9 relative at every tau of its log10 grid.

Exit code 77 (ctest SKIP_RETURN_CODE) when the shared data is absent; 0 on agreement; 1 otherwise.
Uses only numpy and h5py (what scripts/install-deps.sh installs).
"""
import argparse
import io
import os
import subprocess
import sys

import h5py
import numpy as np

SKIP = 77


def oadev_numpy(y, fs, m_values):
    y = np.asarray(y, dtype=np.float64)
    y = y - y.mean()
    x = np.concatenate(([0.0], np.cumsum(y))) / fs  # phase in (rate unit) x s
    n = y.size
    out = []
    for m in m_values:
        tau = m / fs
        d = x[2 * m:] - 2.0 * x[m:n + 1 - m] + x[:n + 1 - 2 * m]
        out.append(np.sqrt(np.dot(d, d) / (2.0 * tau * tau * (n - 2 * m + 1))))
    return np.array(out)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--fogpipe", required=True, help="path of the fogpipe binary")
    parser.add_argument("--data", action="append", default=[],
                        help="candidate folders holding adis16405_imu1.h5 (first found is used)")
    args = parser.parse_args()
    folder = next((d for d in args.data
                   if os.path.exists(os.path.join(d, "adis16405_imu1.h5"))), None)
    if folder is None:
        print("shared real-imu data not present; skipped")
        return SKIP
    path = os.path.join(folder, "adis16405_imu1.h5")
    run = subprocess.run([args.fogpipe, "allan", path, "--axis", "x", "--taus", "log10", "--csv"],
                         capture_output=True, text=True)
    if run.returncode != 0:
        print(run.stdout, run.stderr)
        return 1
    # genfromtxt(names=True) would take its names from a leading '#' line: drop those first.
    csv = "\n".join(line for line in run.stdout.splitlines() if not line.startswith("#"))
    table = np.genfromtxt(io.StringIO(csv), delimiter=",", names=True)
    with h5py.File(path, "r") as f:
        rate = f["rate"]
        assert rate.attrs["units"] in ("deg/s", b"deg/s")
        fs = float(f.attrs["sample_rate_hz"])
        axes = [a.decode() if isinstance(a, bytes) else a for a in rate.attrs["axes"]]
        y = rate[:, axes.index("x")]
    m = table["m"].astype(np.int64)
    expected = oadev_numpy(y, fs, m)
    got = table["sigma_deg_s"]
    rel = np.abs(got - expected) / expected
    worst = int(np.argmax(rel))
    print(f"{m.size} taus, worst relative difference {rel[worst]:.3e} at m = {m[worst]}")
    if not np.all(np.abs(table["tau_s"] - m / fs) <= 1e-15 * table["tau_s"]):
        print("tau_s is not m / fs")
        return 1
    if np.count_nonzero(table["count"] != y.size - 2 * m + 1):
        print("count is not N - 2m + 1")
        return 1
    return 0 if rel[worst] <= 1e-9 else 1


if __name__ == "__main__":
    sys.exit(main())
