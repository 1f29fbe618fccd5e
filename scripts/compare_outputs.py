#!/usr/bin/python3
"""Holds two fogpipe binaries to the same numbers: `simulate`, `run`, `sweep` and `compare` on
fixed simulated recordings (a paper-profile record, a nav-profile 3-axis record with temperature,
and a moving-rate record with its truth), every dataset and attribute of every output compared
bit for bit (NaN equal to NaN). Excluded, because they describe the run rather than the result:
/provenance, attributes and columns whose name ends in "seconds" (timings), and paths.
Used before and after a restructuring that must not change a result.

Across the results layouts (an OLD binary writing fogpipe-results-v1, a NEW one v2) the files are
compared by content: each v2 noise table (allan/<signal>/noise/terms and the chi2, dof, p_value
attributes of noise) is read as the v1 scalars it replaced (noise/Q, noise/Q_std_error, ...,
noise/Q_z, noise/Q_significant, ..., noise@Q_reason, noise/chi2, noise/dof, noise/p_value), each
Allan table (allan/<signal>/table) as the v1 columns (allan/<signal>/tau_s, ..., count,
noise/model_alpha) with the units of its field_units, and
IMFs stored as float32 (v2's default) must equal the float64 ones rounded to float32 exactly
(the one documented difference); the format tag and decomposition@storage may differ so.

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
notes = []


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


# Datasets that --imf-storage decides the type of.
IMF_STORAGE_DATASETS = ("decomposition/imfs", "decomposition/residue", "kalman/filtered")


def flatten(f):
    """{"/path": value, "/path@attr": value} of every dataset and attribute outside /provenance,
    with results-v2 noise tables spelt as the results-v1 scalars they replaced."""
    out = {}

    def attrs(obj, path):
        for name, value in obj.attrs.items():
            if not timing(name):
                out[f"{path}@{name}"] = value

    def visit(path, obj):
        path = "/" + path
        if path == "/provenance" or path.startswith("/provenance/"):
            return
        attrs(obj, path)
        if isinstance(obj, h5py.Group):
            return
        if timing(path.rsplit("/", 1)[-1]):
            return
        if path.endswith("/noise/terms") and obj.dtype.names:
            noise = path[:-len("/terms")]
            for row in obj[()]:
                t, units = row["name"].decode(), row["units"].decode()
                for field, name, unit in (("value", t, units), ("std_error", t + "_std_error", units),
                                          ("z", t + "_z", "1"),
                                          ("upper_limit", t + "_upper_limit", units),
                                          ("readoff", t + "_readoff", units)):
                    out[f"{noise}/{name}"] = np.float64(row[field])
                    out[f"{noise}/{name}@units"] = unit
                for flag in ("significant", "reliable"):
                    out[f"{noise}/{t}_{flag}"] = np.array([row[flag]], dtype=np.int64)
                    out[f"{noise}/{t}_{flag}@units"] = "1"
                out[f"{noise}@{t}_reason"] = row["reason"].decode()
            return
        if path.endswith("/table") and "/allan/" in path and obj.dtype.names:
            group = path[:-len("/table")]
            table = obj[()]
            units = [u.decode() if isinstance(u, bytes) else str(u)
                     for u in obj.attrs["field_units"]]
            out.pop(f"{path}@field_units")
            for field, unit in zip(obj.dtype.names, units):
                name = f"{group}/noise/{field}" if field == "model_alpha" else f"{group}/{field}"
                out[name] = table[field]
                if unit:
                    out[f"{name}@units"] = unit
            return
        out[path] = obj[()]

    attrs(f, "")
    f.visititems(visit)
    # v2 keeps the fit's chi2, dof and p_value as attributes of noise; v1 had datasets.
    for key in [k for k in out if k.endswith(("/noise@chi2", "/noise@p_value", "/noise@dof"))]:
        noise, name = key.split("@")
        value = out.pop(key)
        out[f"{noise}/{name}"] = (np.array([value], dtype=np.int64) if name == "dof"
                                  else np.float64(value))
        out[f"{noise}/{name}@units"] = "1"
    return out


def compare_h5(label, path_a, path_b):
    with h5py.File(path_a, "r") as fa, h5py.File(path_b, "r") as fb:
        a, b = flatten(fa), flatten(fb)
    tags = (str(a.get("@fogpipe_format", "")), str(b.get("@fogpipe_format", "")))
    across_layouts = tags == ("fogpipe-results-v1", "fogpipe-results-v2")
    if sorted(set(a) ^ set(b)):
        differences.append(f"{label}: members {sorted(set(a) ^ set(b))[:20]}")
    rounded = 0
    for key in sorted(set(a) & set(b)):
        x, y = a[key], b[key]
        if across_layouts and key == "@fogpipe_format":
            continue
        if across_layouts and key.endswith("/decomposition@storage"):
            continue
        if (key.endswith(IMF_STORAGE_DATASETS) and np.asarray(x).dtype == np.float64
                and np.asarray(y).dtype == np.float32):
            # float32 storage: exactly the old doubles rounded to nearest.
            if np.array_equal(np.asarray(x).astype(np.float32), y, equal_nan=True):
                rounded += 1
            else:
                differences.append(f"{label}: {key} is not the float64 values rounded")
            continue
        if not same_values(x, y):
            differences.append(f"{label}: {key}")
    if rounded:
        notes.append(f"{label}: {rounded} IMF datasets float64 -> float32, equal to the rounded "
                     f"float64 values; every other of {len(a)} values identical")


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

for n in notes:
    print("note:", n)
for d in differences:
    print("DIFFERS:", d)
if not differences:
    print(f"identical: simulate (3 recordings), run (3 results files), sweep, compare ({WORK})")
sys.exit(1 if differences else 0)
