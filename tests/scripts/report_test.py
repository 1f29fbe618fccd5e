#!/usr/bin/python3
"""scripts/report.py draws the pictures of any results file a user hands it, and refuses any other
file with exit 2, naming it:
- a results file of `fogpipe run`: index.html with Table 5 and the Allan, signal, PSD and IMF
  pictures of each axis;
- a results file with a `fogpipe compare -o` history: the six pictures of the last step, the
  model's fitted narrow bands marked on the PSD;
- a recording, or a results file of the previous layout (fogpipe-results-v1): exit 2.

Usage: report_test.py FOGPIPE SOURCE_DIR
"""
import os
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np

FAILURES = []


def check(condition, what):
    print(("ok   " if condition else "FAIL ") + what)
    if not condition:
        FAILURES.append(what)


def fogpipe(binary, *args):
    r = subprocess.run([binary, *args], capture_output=True, text=True, timeout=600)
    if r.returncode != 0:
        raise RuntimeError(f"fogpipe {' '.join(args)} exits {r.returncode}: {r.stderr[-2000:]}")


def report(script, path, out):
    return subprocess.run(["/usr/bin/python3", script, path, "-o", out], capture_output=True,
                          text=True, timeout=600)


def is_png(path):
    with open(path, "rb") as f:
        return f.read(8) == b"\x89PNG\r\n\x1a\n" and os.path.getsize(path) > 5000


def check_pictures(script, path, out, what, pictures):
    """report.py on PATH exits 0 and writes each of PICTURES into OUT as a PNG."""
    r = report(script, path, out)
    check(r.returncode == 0, f"{what} gives pictures (exit {r.returncode}: {r.stderr[-500:]})")
    for name in pictures:
        picture = os.path.join(out, name)
        check(os.path.isfile(picture) and is_png(picture), f"{what}: {name} is a picture")


def main():
    binary, source = sys.argv[1], sys.argv[2]
    script = os.path.join(source, "scripts", "report.py")
    tmp = tempfile.mkdtemp(prefix="fogpipe_report_test_")
    try:
        rec = os.path.join(tmp, "rec.h5")
        fogpipe(binary, "simulate", "--profile", "paper", "--seed", "3", "-o", rec)
        fogpipe(binary, "run", rec, "-o", os.path.join(tmp, "res"), "--threads", "2")
        results = os.path.join(tmp, "res", "rec.fogpipe.h5")

        out = os.path.join(tmp, "run_pictures")
        check_pictures(script, results, out, "a run results file",
                       ("allan_axis0.png", "signals_axis0.png", "psd_axis0.png", "imfs_axis0.png"))
        page = open(os.path.join(out, "index.html")).read() if os.path.isfile(
            os.path.join(out, "index.html")) else ""
        check("Table 5" in page and "allan_axis0.png" in page, "index.html holds Table 5 and the Allan picture")

        compared = os.path.join(tmp, "compared.h5")
        fogpipe(binary, "compare", rec, "-o", compared)
        check_pictures(script, compared, os.path.join(tmp, "compare_pictures"), "a compare history",
                       ("allan.png", "psd.png", "time.png", "history.png"))

        # A vibration band (white noise through a resonance at 1.5 Hz, damping 2 %, peak ~10x
        # the white floor) added to a navigation record: with --add narrow_band the fitted band
        # is marked on psd.png and named on stdout.
        banded = os.path.join(tmp, "banded.h5")
        fogpipe(binary, "simulate", "--profile", "nav", "--seed", "11", "-o", banded)
        with h5py.File(banded, "r+") as f:
            y, fs = f["rate"][()], f.attrs["sample_rate_hz"]
            w0 = 2 * np.pi * 1.5 / fs
            r = np.exp(-0.02 * w0)
            e = np.random.default_rng(5).standard_normal(len(y) + 4096)
            a1, a2, x = 2 * r * np.cos(w0), -r * r, np.zeros(len(e))
            for i in range(2, len(e)):  # the AR(2) resonator, burn-in 4096 samples
                x[i] = a1 * x[i - 1] + a2 * x[i - 2] + e[i]
            x = x[4096:]
            power = 10.0 * 2 * (np.var(np.diff(y)) / 2 / fs) * np.pi * 0.02 * 1.5
            f["rate"][...] = y + x * np.sqrt(power / np.var(x))
        banded_history = os.path.join(tmp, "banded_history.h5")
        fogpipe(binary, "compare", banded, "--add", "narrow_band", "-o", banded_history)
        out = os.path.join(tmp, "band_pictures")
        r = report(script, banded_history, out)
        check(r.returncode == 0 and is_png(os.path.join(out, "psd.png")),
              f"a compare history with a narrow band gives psd.png (exit {r.returncode})")
        marked = [line for line in r.stdout.splitlines() if "marks narrow_band" in line]
        f0 = [float(line.split("narrow_band ")[1].split(" Hz")[0]) for line in marked]
        # Within 3 of the fit's standard errors (stored in the history) of the truth, plus 0.1 %
        # of f0 for the resonator's peak against its pole angle, and the 4 digits printed.
        with h5py.File(banded_history, "r") as f:
            se = float(f["compare/step_000/narrow_bands/frequency_se_hz"][0])
        check(len(f0) == 1 and abs(f0[0] - 1.5) <= 3 * se + 1.5e-3 + 5e-4,
              f"psd.png marks the one fitted band at 1.5 Hz ({r.stdout.strip()})")

        r = report(script, rec, os.path.join(tmp, "none"))
        check(r.returncode == 2 and rec in r.stderr, f"a recording is refused, named (exit {r.returncode}: {r.stderr.strip()})")

        old = os.path.join(tmp, "old.fogpipe.h5")
        shutil.copy(results, old)
        with h5py.File(old, "r+") as f:
            f.attrs["fogpipe_format"] = "fogpipe-results-v1"
        r = report(script, old, os.path.join(tmp, "none"))
        check(r.returncode == 2 and "previous layout" in r.stderr and old in r.stderr,
              f"a results file of the previous layout is refused, named (exit {r.returncode}: {r.stderr.strip()})")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return 1 if FAILURES else 0


if __name__ == "__main__":
    sys.exit(main())
