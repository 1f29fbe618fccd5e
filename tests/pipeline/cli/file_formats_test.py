#!/usr/bin/python3
"""Every HDF5 file kind fogpipe writes passes `fogpipe validate` and opens in `fogpipe info`.

  file_formats_test.py FOGPIPE

The kinds: recordings (simulate, import), a results file (run), a campaign table (merge, with a
missing recording), a sweep table (sweep), a model history of its own (compare -o NEW) and one
appended to a results file (compare -o RESULTS). Each must be valid (exit 0) and summarised by
info (exit 0, its key lines). A copy with one required object removed with h5py must be invalid
(exit 1) with a message naming that object. Integer counts with a scale_factor (contract v1.1)
run to the numbers of the float file they stand for.
"""
import os
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np

FOGPIPE = sys.argv[1]
failures = []


def check(condition, message):
    print(("ok   " if condition else "FAIL ") + message, flush=True)
    if not condition:
        failures.append(message)


def run(*args, ok=(0,)):
    p = subprocess.run([FOGPIPE] + [str(a) for a in args], capture_output=True, text=True)
    if p.returncode not in ok:
        sys.exit(f"FAIL: fogpipe {' '.join(map(str, args))} -> {p.returncode}\n{p.stdout}\n"
                 f"{p.stderr}")
    return p


def write_csv(path):
    rng = np.random.default_rng(5)
    n, rate_hz = 6000, 10.0
    t = np.arange(n) / rate_hz
    gyro = 0.3 * rng.standard_normal((n, 2)) + np.cumsum(0.001 * rng.standard_normal((n, 2)), 0)
    temperature = 20.0 + 0.001 * np.arange(n)
    np.savetxt(path, np.column_stack([t, gyro, temperature]), fmt="%.17g", delimiter=",",
               header="t,gx,gy,temp", comments="")


def make_files(tmp):
    """Writes one file of every kind; returns {kind: path}."""
    data = os.path.join(tmp, "data")
    run("simulate", "-o", data, "--files", "3", "--profile", "paper", "--duration-s", "600",
        "--sample-rate-hz", "10", "--seed", "8", "--serial", "FOG-7")
    manifest = os.path.join(tmp, "manifest.txt")
    run("plan", data, "-o", manifest)
    listed = [l.split()[0] for l in open(manifest) if not l.startswith("#")]
    csv = os.path.join(tmp, "table.csv")
    write_csv(csv)
    imported = os.path.join(tmp, "imported.h5")
    run("import", csv, "-o", imported, "--units", "deg/h", "--time-column", "t",
        "--rate-columns", "gx,gy", "--aux", "temperature=temp:degC")
    outdir = os.path.join(tmp, "out")
    run("run", listed[0], listed[1], "-o", outdir, "--threads", "2")
    results = os.path.join(outdir, os.path.basename(listed[0])[:-3] + ".fogpipe.h5")
    campaign = os.path.join(outdir, "campaign.h5")
    run("merge", outdir, "--manifest", manifest, ok=(1,))  # the third recording is missing
    sweep_dir = os.path.join(tmp, "sweep")
    run("sweep", listed[0], "-o", sweep_dir, "--ar-order", "2,3", "--q-scale", "1",
        "--r-scale", "1,10", "--threads", "2")
    sweep = os.path.join(sweep_dir, os.path.basename(listed[0])[:-3] + ".sweep.h5")
    history = os.path.join(tmp, "history.h5")
    run("compare", listed[0], "-o", history)
    run("compare", listed[0], "-o", history, "--add", "gauss_markov")
    appended = os.path.join(tmp, "appended.fogpipe.h5")
    shutil.copy(results, appended)
    run("compare", listed[0], "-o", appended)
    return {"simulated recording": listed[0], "imported recording": imported, "results": results,
            "campaign": campaign, "sweep": sweep, "compare": history,
            "results with compare": appended}


# The lines `info` must print for each kind.
INFO_LINES = {
    "simulated recording": ["recording  6000 samples at 10 Hz (600 s)", "serial     FOG-7"],
    "imported recording": ["2 axes (gx, gy) in deg/h", "aux        temperature in degC"],
    "results": ["Table 3:", "Table 5:", "  input "],
    "campaign": ["3 rows, 3 recordings (2 ok, 0 failed, 1 missing)", "raw N [deg/sqrt(h)]",
                 "raw K [deg/h/sqrt(h)]", " +- ", "missing"],
    "sweep": ["(6 settings, ", "ranked by rms_error", "  1  ", "  dflt ", "  ref   "],
    "compare": ["model history", "step  axis     error      consistent", "gauss_markov   (error x"],
    "results with compare": ["Table 5:", "model history", "step  axis     error"],
}

# One required object per kind to remove, and the text the problem must contain.
DAMAGE = {
    "simulated recording": ("rate", "/: missing required dataset 'rate'"),
    "results": ("provenance/config_toml", "/provenance: missing required dataset 'config_toml'"),
    "campaign": ("campaign/raw_N", "/campaign: missing required dataset 'raw_N'"),
    "sweep": ("axes/axis0/emd_sifts_10/ranking",
              "/axes/axis0/emd_sifts_10: missing required dataset 'ranking'"),
    "compare": ("compare/step_001/imf/z", "/compare/step_001/imf: missing required dataset 'z'"),
}


def numeric_datasets(path):
    """Every numeric dataset of a results file outside /provenance, by name."""
    found = {}
    with h5py.File(path, "r") as f:
        def visit(name, obj):
            if (isinstance(obj, h5py.Dataset) and obj.dtype.kind in "fiu"
                    and not name.startswith("provenance")):
                found[name] = obj[()]
        f.visititems(visit)
    return found


def check_integer_counts(tmp):
    """Contract v1.1: an int16 / int32 /rate with scale_factor is read as counts x scale_factor,
    so `run` gives the numbers of a float64 file holding those products; without scale_factor, or
    with a zero one, validate refuses it naming the problem."""
    rng = np.random.default_rng(11)
    counts = np.round(rng.normal(0, 3000, (6000, 2))).astype(np.int16)
    scale = 0.0025  # deg/h per count
    files = {}
    for kind, data in (("float64", counts * scale), ("int16", counts),
                       ("int32", counts.astype(np.int32))):
        files[kind] = os.path.join(tmp, f"counts_{kind}.h5")
        with h5py.File(files[kind], "w") as f:
            f.attrs["sample_rate_hz"] = 10.0
            d = f.create_dataset("rate", data=data)
            d.attrs["units"] = "deg/h"
            if kind != "float64":
                d.attrs["scale_factor"] = scale
    outdir = os.path.join(tmp, "counts_out")
    run("run", *files.values(), "-o", outdir, "--threads", "2")
    reference = numeric_datasets(os.path.join(outdir, "counts_float64.fogpipe.h5"))
    for kind in ("int16", "int32"):
        v = run("validate", files[kind], ok=(0, 1, 2))
        check(v.returncode == 0, f"{kind} counts with scale_factor: validate exit 0 ({v.stdout})")
        got = numeric_datasets(os.path.join(outdir, f"counts_{kind}.fogpipe.h5"))
        same = got.keys() == reference.keys() and all(
            np.array_equal(got[k], reference[k], equal_nan=got[k].dtype.kind == "f")
            for k in reference)
        check(same and len(reference) > 10, f"run on {kind} counts x scale_factor gives every "
              f"dataset of the float64 file ({len(reference)} datasets)")
    for name, value, problem in (("no_scale", None, "has no 'scale_factor' attribute"),
                                 ("zero_scale", 0.0, "'scale_factor' is 0")):
        path = os.path.join(tmp, f"counts_{name}.h5")
        shutil.copy(files["int16"], path)
        with h5py.File(path, "r+") as f:
            del f["rate"].attrs["scale_factor"]
            if value is not None:
                f["rate"].attrs["scale_factor"] = value
        v = run("validate", path, ok=(0, 1, 2))
        check(v.returncode == 1 and problem in v.stdout and path in v.stdout,
              f"int16 counts, {name}: validate exit 1 naming the file and the problem "
              f"({v.returncode}: {v.stdout.strip()})")


def main():
    tmp = tempfile.mkdtemp(prefix="fogpipe_file_formats_")
    files = make_files(tmp)
    for kind, path in files.items():
        v = run("validate", path, ok=(0, 1, 2))
        check(v.returncode == 0, f"{kind}: validate exit 0 ({v.returncode}: {v.stdout.strip()}"
                                 f" {v.stderr.strip()})")
        i = run("info", path, ok=(0, 1))
        check(i.returncode == 0, f"{kind}: info exit 0 ({i.stderr.strip()})")
        for line in INFO_LINES[kind]:
            check(line in i.stdout, f"{kind}: info shows {line!r}")
        if i.returncode != 0 or not all(line in i.stdout for line in INFO_LINES[kind]):
            print(i.stdout)
    for kind, (name, problem) in DAMAGE.items():
        damaged = os.path.join(tmp, "damaged_" + os.path.basename(files[kind]))
        shutil.copy(files[kind], damaged)
        with h5py.File(damaged, "r+") as f:
            del f[name]
        v = run("validate", "--no-data", damaged, ok=(0, 1, 2))
        check(v.returncode == 1, f"{kind} without /{name}: validate exit 1 ({v.returncode})")
        check(problem in v.stdout, f"{kind} without /{name}: the problem names it ({v.stdout})")
    # The campaign's links to the results files are described, not followed: one that points
    # elsewhere inside its file is a problem.
    campaign = os.path.join(tmp, "out", "relinked_campaign.h5")
    shutil.copy(files["campaign"], campaign)
    with h5py.File(campaign, "r+") as f:
        name = next(iter(f["results"]))
        target = f["results"].get(name, getlink=True).filename
        del f["results"][name]
        f["results"][name] = h5py.ExternalLink(target, "/provenance")
    v = run("validate", campaign, ok=(0, 1, 2))
    check(v.returncode == 1 and f"/results/{name}: external link to '/provenance'" in v.stdout,
          f"a campaign link to another object is a problem ({v.stdout.strip()})")
    check_integer_counts(tmp)
    if failures:
        sys.exit(f"{len(failures)} failure(s): " + "; ".join(failures))
    shutil.rmtree(tmp)
    print("file_formats_test: ok")


if __name__ == "__main__":
    main()
