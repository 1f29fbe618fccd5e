#!/usr/bin/python3
"""Holds two fogpipe binaries to the same numbers: `simulate`, `run`, `sweep` and `compare` on
fixed simulated recordings (a paper-profile record, a nav-profile 3-axis record with temperature,
and a moving-rate record with its truth), every dataset and attribute of every output compared
bit for bit (NaN equal to NaN). Excluded, because they describe the run rather than the result:
/provenance, attributes and columns whose name ends in "seconds" (timings), and paths.
Used before and after a restructuring that must not change a result.

Usage: compare_outputs.py OLD_FOGPIPE NEW_FOGPIPE [WORK_DIR]
Exit 0 when every output is identical, 1 when any differs (the differences are printed).
"""
import csv
import json
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

OLD, NEW = sys.argv[1], sys.argv[2]
WORK = sys.argv[3] if len(sys.argv) > 3 else tempfile.mkdtemp(prefix="fogpipe-compare-outputs-")
differences = []


def fogpipe(binary, *args):
    r = subprocess.run([binary] + list(args), capture_output=True, text=True, timeout=1800)
    return r


def timing(name):
    return name.endswith("seconds") or name.endswith("seconds [s]")


def same_values(a, b):
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape or a.dtype != b.dtype:
        return False
    if a.dtype.kind == "f":
        return bool(np.array_equal(a, b, equal_nan=True))
    return bool(np.array_equal(a, b))


def compare_h5(label, path_a, path_b):
    with h5py.File(path_a, "r") as fa, h5py.File(path_b, "r") as fb:
        def walk(ga, gb, where):
            for name, value in ga.attrs.items():
                if timing(name):
                    continue
                if name not in gb.attrs or not same_values(value, gb.attrs[name]):
                    differences.append(f"{label}: attribute {where}@{name}")
            if set(ga.keys()) != set(gb.keys()):
                differences.append(f"{label}: members of {where} "
                                   f"{sorted(set(ga.keys()) ^ set(gb.keys()))}")
            for key in ga.keys():
                path = f"{where.rstrip('/')}/{key}"
                if path == "/provenance" or key not in gb:
                    continue
                a, b = ga[key], gb[key]
                if isinstance(a, h5py.Group):
                    walk(a, b, path)
                elif timing(key):
                    continue
                elif not same_values(a[()], b[()]):
                    differences.append(f"{label}: dataset {path}")
                else:
                    walk_attrs(a, b, path)

        def walk_attrs(a, b, path):
            for name, value in a.attrs.items():
                if not timing(name) and (name not in b.attrs or not same_values(value, b.attrs[name])):
                    differences.append(f"{label}: attribute {path}@{name}")

        walk(fa, fb, "/")


def compare_csv(label, path_a, path_b):
    with open(path_a) as fa, open(path_b) as fb:
        ra, rb = list(csv.reader(fa)), list(csv.reader(fb))
    if len(ra) != len(rb) or ra[0] != rb[0]:
        differences.append(f"{label}: rows or header")
        return
    keep = [i for i, h in enumerate(ra[0]) if not timing(h)]
    for n, (x, y) in enumerate(zip(ra, rb)):
        if [x[i] for i in keep] != [y[i] for i in keep]:
            differences.append(f"{label}: row {n}")


rec = os.path.join(WORK, "rec")
os.makedirs(rec, exist_ok=True)
inputs = {"paper": ["--profile", "paper", "--seed", "11"],
          "nav": ["--profile", "nav", "--axes", "3", "--duration-s", "1800", "--seed", "12"],
          "moving": ["--profile", "paper", "--rate-profile", "step:300:20,ramp:900:1200:0.05",
                     "--seed", "13"]}
for name, args in inputs.items():
    r = fogpipe(OLD, "simulate", *args, "-o", os.path.join(rec, name + ".h5"))
    if r.returncode != 0:
        sys.exit(f"could not simulate {name}.h5 with {OLD}: {r.stderr}")

# simulate: the same recordings and truths from the new binary.
for name, args in inputs.items():
    out = os.path.join(WORK, f"new_{name}.h5")
    fogpipe(NEW, "simulate", *args, "-o", out)
    compare_h5(f"simulate {name}.h5", os.path.join(rec, name + ".h5"), out)
    with open(os.path.join(rec, name + ".h5.truth.json")) as fa, open(out + ".truth.json") as fb:
        ta, tb = json.load(fa), json.load(fb)
    ta.pop("recording", None), tb.pop("recording", None)
    if ta != tb:
        differences.append(f"simulate {name}.h5.truth.json")

for tag, binary in (("old", OLD), ("new", NEW)):
    fogpipe(binary, "run", rec, "-o", os.path.join(WORK, "run_" + tag), "--threads", "2")
    fogpipe(binary, "sweep", os.path.join(rec, "moving.h5"), "-o", os.path.join(WORK, "sweep_" + tag),
            "--ar-order", "2:4", "--q-scale", "0.5,1,2", "--threads", "2")
    r = fogpipe(binary, "compare", os.path.join(rec, "paper.h5"), "--json")
    with open(os.path.join(WORK, f"compare_{tag}.json"), "w") as f:
        f.write(r.stdout)

for name in inputs:
    results = f"{name}.fogpipe.h5"
    a, b = (os.path.join(WORK, f"run_{t}", results) for t in ("old", "new"))
    if not (os.path.exists(a) and os.path.exists(b)):
        differences.append(f"run {results}: missing")
        continue
    compare_h5(f"run {results}", a, b)
compare_h5("sweep moving.sweep.h5", *(os.path.join(WORK, f"sweep_{t}", "moving.sweep.h5")
                                      for t in ("old", "new")))
compare_csv("sweep moving.sweep.csv", *(os.path.join(WORK, f"sweep_{t}", "moving.sweep.csv")
                                        for t in ("old", "new")))
with open(os.path.join(WORK, "compare_old.json")) as fa, open(os.path.join(WORK, "compare_new.json")) as fb:
    if json.load(fa) != json.load(fb):
        differences.append("compare --json")

for d in differences:
    print("DIFFERS:", d)
if not differences:
    print(f"identical: simulate (3 recordings), run (3 results files), sweep, compare ({WORK})")
sys.exit(1 if differences else 0)
