#!/usr/bin/python3
"""Checks fogpipe results files against their recordings, independently of fogpipe's C++ code.

Usage: check_results_h5py.py RESULTS.fogpipe.h5 [RESULTS...]

For every results file (Debian's python3-h5py + numpy only):
  - the root attribute fogpipe_format is "fogpipe-results-v1";
  - every numeric dataset has a string `units` attribute;
  - per axis, the preprocessed signal is rebuilt in numpy from the input recording named in
    /provenance (rate converted to rad/s, start dropped, outliers replaced by the median of the
    11 centred samples, mean removed) and
      * sum of IMFs + residue equals it to 1e-12 (relative to its largest magnitude),
      * the overlapping Allan deviation of it, recomputed from the cumulative sum (NIST SP 1065
        eq. 14 on phase data), agrees with /axes/<a>/allan/raw/sigma to 1e-9 relative;
  - method 1 equals the sum of the filtered components when they are stored (1e-12);
  - Table 3 / Table 5 datasets are finite where they must be.
Exit code 0 when every check passes, 1 otherwise (each failure printed).
"""
import sys

import h5py
import numpy as np

UNITS_TO_RAD_S = {"rad/s": 1.0, "deg/s": np.pi / 180.0, "deg/h": np.pi / 180.0 / 3600.0}
failures = []


def fail(path, message):
    failures.append(f"{path}: {message}")


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def check_units(results_path, f):
    def visit(name, obj):
        if isinstance(obj, h5py.Dataset) and obj.dtype.kind in "fiu":
            if "units" not in obj.attrs:
                fail(results_path, f"/{name}: numeric dataset without a units attribute")
    f.visititems(visit)


def oadev_from_cumsum(y, rate_hz, m_values):
    """Overlapping Allan deviation from phase = cumulative sum (NIST SP 1065 eq. 14)."""
    tau0 = 1.0 / rate_hz
    phase = np.concatenate([[0.0], np.cumsum(y, dtype=np.float64)]) * tau0
    n = phase.size
    out = []
    for m in m_values:
        d = phase[2 * m:] - 2.0 * phase[m:n - m] + phase[:n - 2 * m]
        tau = m * tau0
        out.append(np.sqrt(np.sum(d * d) / (2.0 * tau * tau * d.size)))
    return np.array(out)


def rebuild_signal(recording, column, axis_group):
    with h5py.File(recording, "r") as r:
        rate = r["rate"]
        units = text(rate.attrs["units"])
        x = rate[:, column] if rate.ndim == 2 else rate[:]
    x = np.asarray(x, dtype=np.float64) * UNITS_TO_RAD_S[units]
    pre = axis_group["preprocessing"]
    drop = int(pre["dropped_samples"][0])
    # NaN bridging (the reader's linear interpolation) is not redone here: test recordings have no
    # NaN, and a NaN left over makes every comparison below fail loudly.
    x = x[drop:].copy()
    original = x.copy()
    for index in pre["outlier_indices"][:]:
        k = int(index) - drop
        lo, hi = max(0, k - 5), min(x.size, k + 6)
        x[k] = np.median(original[lo:hi])
    return x - np.mean(x)


def check_file(results_path):
    with h5py.File(results_path, "r") as f:
        if text(f.attrs.get("fogpipe_format", "")) != "fogpipe-results-v1":
            fail(results_path, "root attribute fogpipe_format is not fogpipe-results-v1")
            return
        check_units(results_path, f)
        recording = text(f["provenance"].attrs["input_path"])
        for axis_name, g in f["axes"].items():
            where = f"{results_path}: /axes/{axis_name}"
            x = rebuild_signal(recording, int(g.attrs["column"]), g)
            scale = max(np.max(np.abs(x)), 1e-300)
            dec = g["decomposition"]
            if "imfs" in dec:
                total = np.sum(dec["imfs"][:], axis=1) + dec["residue"][:]
                if dec["imfs"].dtype == np.float64:
                    err = np.max(np.abs(total - x)) / scale
                    if not err <= 1e-12:
                        fail(where, f"sum of IMFs + residue differs from the signal by {err:.3g}")
                    else:
                        print(f"{where}: sum(IMFs) + residue = signal to {err:.2e} (<= 1e-12)")
            allan = g["allan/raw"]
            m = allan["m"][:]
            ours = oadev_from_cumsum(x, float(g.attrs["sample_rate_hz"]), m)
            stored = allan["sigma"][:]
            rel = np.max(np.abs(ours - stored) / stored)
            if not rel <= 1e-9:
                fail(where, f"raw Allan deviation differs from numpy's by {rel:.3g} relative")
            else:
                print(f"{where}: raw OADEV = numpy cumulative-sum OADEV to {rel:.2e} (<= 1e-9)")
            kal = g["kalman"]
            if "filtered" in kal:
                s = np.sum(kal["filtered"][:], axis=1)
                err = np.max(np.abs(s - g["signals/method1"][:])) / scale
                if not err <= 1e-12:
                    fail(where, f"method1 differs from the sum of filtered components by {err:.3g}")
            for name in ("fit_one_step_percent", "innovation_variance", "order"):
                if not np.all(np.isfinite(g["models"][name][:])):
                    fail(where, f"models/{name} has non-finite values")
            for signal in ("raw", "method1", "method2"):
                for term in "QNBKR":
                    v = g[f"allan/{signal}/noise/{term}"][()]
                    if not np.isfinite(v) or v < 0:
                        fail(where, f"allan/{signal}/noise/{term} = {v}")


def main(argv):
    if len(argv) < 2:
        print(__doc__)
        return 2
    for path in argv[1:]:
        check_file(path)
    for message in failures:
        print("FAIL", message)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
