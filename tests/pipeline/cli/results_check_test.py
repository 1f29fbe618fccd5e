#!/usr/bin/python3
"""scripts/check_results_h5py.py on every storage option of `fogpipe run`, and the memory budget.

Usage: results_check_test.py FOGPIPE_BINARY SOURCE_DIR

1. Results files of each storage option (float64 default; float32 with filtered components;
   none; float64 with filtered components) of a 1-axis recording long enough for several chunks
   per IMF and a short 2-axis float32 recording pass the h5py check (which reads every dataset,
   checks it against schemas/results-v2.json and recomputes the numbers in numpy).
2. The check can fail: copies of a good file with one IMF sample changed, a wrong units
   attribute, a required dataset removed, or an undescribed dataset added each fail it with a
   message saying so.
3. The large datasets are chunked one IMF per chunk, with shuffle and deflate.
4. --memory-budget: a campaign several times larger than the budget runs one recording at a time
   and its peak RSS (os.wait4) stays within the budget; a recording that alone needs more than the
   budget is refused with a message naming the memory it needs, and the others still finish.
Recordings are written with h5py + numpy (seeded; run_campaign_test.write_recording).
"""
import os
import shutil
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np

# The same recordings, checks and helpers as the run tests (they share argv: FOGPIPE SOURCE).
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_campaign_test import (CHECKER, FOGPIPE, check, failures, run,  # noqa: E402
                               status_lines, write_recording)


def checker(paths):
    return subprocess.run(["/usr/bin/python3", CHECKER] + paths, capture_output=True, text=True)


def case_storage_options(tmp):
    rec = os.path.join(tmp, "rec")
    os.makedirs(rec)
    # 150000 samples: 3 chunks of 65536 rows per IMF, the last one short.
    write_recording(os.path.join(rec, "long.h5"), 1, n=150000, rate_hz=100.0)
    write_recording(os.path.join(rec, "two_axes.h5"), 2, n=5000, rate_hz=10.0, axes=2, dtype="f4",
                    units="deg/s")
    # Explicit q and R: the run does not depend on the default noise rule.
    common = ["--threads", "2", "--q", "1e-14", "--r", "2e-10"]
    options = {"float64": ["--imf-storage", "float64"],
               "float32_filtered": ["--store-filtered-imfs"],
               "none": ["--imf-storage", "none"],
               "float64_filtered": ["--imf-storage", "float64", "--store-filtered-imfs"]}
    outputs = {}
    for name, extra in options.items():
        out = os.path.join(tmp, "out_" + name)
        r = run(["run", rec, "-o", out] + common + extra)
        check(r.returncode == 0,
              f"run with {name} storage exits 0" + ("" if r.returncode == 0 else r.stderr[-500:]))
        outputs[name] = [os.path.join(out, n) for n in ("long.fogpipe.h5", "two_axes.fogpipe.h5")]
    c = checker([p for paths in outputs.values() for p in paths])
    print(c.stdout)
    check(c.returncode == 0, "every output of every storage option passes check_results_h5py.py")
    for name, words in (("float64", ["sum(IMFs)+residue (float64)", "Ljung-Box"]),
                        ("float32_filtered", ["sum(IMFs)+residue (float32)",
                                              "method1 = sum(filtered)"]),
                        ("float64_filtered", ["method1 = sum(filtered)"])):
        ok = all(f"{outputs[name][0]}: /axes/axis0: checked" in c.stdout and w in c.stdout
                 for w in words)
        check(ok, f"the {name} check recomputed {words}")
    with h5py.File(outputs["float64_filtered"][0], "r") as f:
        for name in ("axes/axis0/decomposition/imfs", "axes/axis0/kalman/filtered"):
            d = f[name]
            check(d.chunks == (65536, 1) and d.compression == "gzip" and d.shuffle,
                  f"{name} is chunked one column per chunk with shuffle + deflate "
                  f"({d.chunks}, {d.compression}, shuffle {d.shuffle})")
    return outputs["float64"][0]


def case_checker_fails(tmp, good):
    def mutated(name, edit):
        path = os.path.join(tmp, name + ".fogpipe.h5")
        shutil.copy(good, path)
        with h5py.File(path, "a") as f:
            edit(f)
        return checker([path])

    def bump_imf(f):
        d = f["axes/axis0/decomposition/imfs"]
        d[70000, 2] = d[70000, 2] * (1.0 + 1e-6)
    c = mutated("imf", bump_imf)
    check(c.returncode == 1 and "sum of IMFs + residue differs" in c.stdout,
          "one IMF sample changed by 1e-6 relative fails the check")

    def bad_units(f):
        f["axes/axis0/signals/method1"].attrs["units"] = "deg/h"
    c = mutated("units", bad_units)
    check(c.returncode == 1 and "units 'deg/h'" in c.stdout, "a wrong units attribute fails")

    def drop(f):
        del f["axes/axis0/models/bic"]
    c = mutated("drop", drop)
    check(c.returncode == 1 and "required dataset 'bic' is missing" in c.stdout,
          "a missing required dataset fails")

    def extra(f):
        f["axes/axis0/signals"].create_dataset("method3", data=np.zeros(10))
    c = mutated("extra", extra)
    check(c.returncode == 1 and "not described by the schema" in c.stdout,
          "an undescribed dataset fails")

    def bad_shape(f):
        del f["axes/axis0/decomposition/energy"]
        f["axes/axis0/decomposition"].create_dataset("energy", data=np.ones(3))
        f["axes/axis0/decomposition/energy"].attrs["units"] = "(rad/s)^2"
    c = mutated("shape", bad_shape)
    check(c.returncode == 1 and "energy: shape" in c.stdout, "a dataset of the wrong shape fails")


def tree_pids(pid):
    """A process and its descendants, from /proc's children lists."""
    pids, todo = [], [pid]
    while todo:
        p = todo.pop()
        pids.append(p)
        try:
            for task in os.listdir(f"/proc/{p}/task"):
                with open(f"/proc/{p}/task/{task}/children") as f:
                    todo += [int(c) for c in f.read().split()]
        except (FileNotFoundError, ProcessLookupError, PermissionError, ValueError):
            pass
    return sorted(pids)


def tree_pss_kib(pid):
    """Proportional set size of a process and its descendants [KiB]: shared pages counted once,
    or None when the tree changed while it was read. A parent read just before a fork and its
    child read just after it would count the shared pages one and a half times, so a sample
    counts only if the same processes exist before and after it."""
    before = tree_pids(pid)
    total = 0
    for p in before:
        try:
            with open(f"/proc/{p}/smaps_rollup") as f:
                total += sum(int(l.split()[1]) for l in f if l.startswith("Pss:"))
        except (FileNotFoundError, ProcessLookupError, PermissionError, ValueError):
            return None
    return total if tree_pids(pid) == before else None


def peak_rss_kib(args):
    """Peak memory of the run [KiB]. Inputs are read in forked child processes, and a forked
    child's RSS (and so wait4's ru_maxrss) counts every copy-on-write page it shares with its
    parent again; the memory actually in use is the sum of PSS over the process tree, sampled
    every 10 ms (a shorter peak can be missed; allocations here last for a whole recording)."""
    proc = subprocess.Popen([FOGPIPE] + args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    peak = 0
    while proc.poll() is None:
        peak = max(peak, tree_pss_kib(proc.pid) or 0)
        time.sleep(0.01)
    return proc.returncode, peak


def case_memory_budget(tmp):
    rec = os.path.join(tmp, "budget")
    os.makedirs(rec)
    for k in range(5):
        write_recording(os.path.join(rec, f"part{k}.h5"), 10 + k, n=180000, rate_hz=100.0)
    # Each needs about 20 x 180000 x 8 B = 27.5 MiB by the estimate (memory_budget.h), 5 of them
    # ~ 137 MiB; 100 MiB leaves 32 MiB for recordings after the 68 MiB of the process: one at a
    # time.
    budget_mib = 100
    out = os.path.join(tmp, "out_budget")
    code, rss = peak_rss_kib(["run", rec, "-o", out, "--threads", "2", "--q", "1e-14", "--r",
                              "2e-10", "--memory-budget", f"{budget_mib}M"])
    check(code == 0 and len([l for l in status_lines(out) if l["status"] == "ok"]) == 5,
          f"a 5-recording campaign runs under --memory-budget {budget_mib}M (exit {code})")
    check(rss <= budget_mib * 1024,
          f"its peak RSS {rss / 1024:.1f} MiB is within the {budget_mib} MiB budget")
    big = os.path.join(tmp, "budget_mixed")
    os.makedirs(big)
    shutil.copy(os.path.join(rec, "part0.h5"), os.path.join(big, "big.h5"))
    write_recording(os.path.join(big, "small.h5"), 3, n=4000, rate_hz=10.0)
    out = os.path.join(tmp, "out_mixed")
    r = run(["run", big, "-o", out, "--threads", "2", "--memory-budget", "80M"])
    lines = {os.path.basename(l["file"]): l for l in status_lines(out)}
    check(r.returncode == 1, f"a recording over the budget makes the run exit 1 ({r.returncode})")
    msg = lines.get("big.h5", {}).get("message", "")
    check(lines.get("big.h5", {}).get("status") == "failed" and "needs about" in msg and
          "--memory-budget" in msg and "big.h5" in msg,
          f"the recording over the budget is refused with what it needs: {msg}")
    check(lines.get("small.h5", {}).get("status") == "ok", "the recording within it finishes")


def main():
    tmp = tempfile.mkdtemp(prefix="fogpipe_results_check_")
    try:
        good = case_storage_options(tmp)
        case_checker_fails(tmp, good)
        case_memory_budget(tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
