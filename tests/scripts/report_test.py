#!/usr/bin/python3
"""scripts/report.py draws the pictures of any results file a user hands it, and refuses any other
file with exit 2, naming it:
- a results file of `fogpipe run`: index.html with Table 5 and the Allan, signal, PSD and IMF
  pictures of each axis;
- a results file with a `fogpipe compare -o` history: the six pictures of the last step;
- a recording, or a results file of the previous layout (fogpipe-results-v1): exit 2.

Usage: report_test.py FOGPIPE SOURCE_DIR
"""
import os
import shutil
import subprocess
import sys
import tempfile

import h5py

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
