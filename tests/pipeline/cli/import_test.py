#!/usr/bin/python3
"""End-to-end test of `fogpipe import` (driven through the binary).

Usage: import_test.py FOGPIPE_BINARY
Writes a CSV file with numpy and a MATLAB-v7.3-like file with h5py (512-byte user block holding
MATLAB's header, variables with a MATLAB_class attribute, an N x 3 matrix stored column-major as
HDF5 [3, N]), imports both, and checks with h5py that /rate holds exactly the source's numbers,
that `fogpipe validate` calls the recordings valid and that `fogpipe run` analyses them (status
ok). Then the refusals: a non-uniform time column, a transposed matrix, an older MAT-file, an
existing output.
"""
import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np

import recording_sources  # beside this script

FOGPIPE = sys.argv[1]
failures = []

N = 6000  # 10 min at 10 Hz: long enough for `run`, quick to analyse
RATE_HZ = 10.0


def check(condition, message):
    print(("ok   " if condition else "FAIL ") + message, flush=True)
    if not condition:
        failures.append(message)


def run(args):
    return subprocess.run([FOGPIPE] + args, capture_output=True, text=True)


def gyro_data(seed, axes=3):
    return recording_sources.gyro_deg_h(seed, N, axes)


def case_csv(tmp):
    data = gyro_data(1)
    temperature = 25.0 + 0.5 * np.sin(np.arange(N) / 600.0)
    source = os.path.join(tmp, "bench_run.csv")
    recording_sources.write_csv(source, data, temperature, RATE_HZ)
    out = os.path.join(tmp, "rec", "bench_run.h5")
    os.makedirs(os.path.dirname(out))
    r = run(["import", source, "-o", out, "--units", "deg/h", "--time-column", "t",
             "--rate-columns", "gx,gy,gz", "--aux", "temperature=temp:degC",
             "--instrument", "VG951", "--serial", "S-17",
             "--start-time-utc", "2026-03-01T08:00:00Z", "--latitude-deg", "48.5"])
    check(r.returncode == 0, f"import of a CSV exits 0 ({r.returncode}: {r.stderr.strip()})")
    check("rows/s" in r.stderr, "import reports its speed in rows/s")
    with h5py.File(out, "r") as f:
        rate = f["rate"]
        check(rate.dtype == np.float64 and rate.shape == (N, 3), f"/rate is float64 [N, 3] "
              f"({rate.dtype}, {rate.shape})")
        check(np.array_equal(rate[()], data), "/rate equals the CSV's numbers exactly")
        check(rate.attrs["units"] == "deg/h", "/rate units deg/h")
        check(list(rate.attrs["axes"]) == ["gx", "gy", "gz"], "axes named from the header")
        check(f.attrs["sample_rate_hz"] == RATE_HZ, "sample rate derived from the time column")
        check(np.array_equal(f["aux/temperature"][()], temperature) and
              f["aux/temperature"].attrs["units"] == "degC", "aux temperature imported with units")
        check(f.attrs["instrument"] == "VG951" and f.attrs["serial"] == "S-17" and
              f.attrs["start_time_utc"] == "2026-03-01T08:00:00Z" and
              f.attrs["latitude_deg"] == 48.5, "root attributes written")
        provenance = json.loads(f.attrs["import_provenance"])
    with open(source, "rb") as fh:
        sha = hashlib.sha256(fh.read()).hexdigest()
    check(provenance["source"]["sha256"] == sha, "provenance holds the source's SHA-256")
    check(provenance["source"]["path"] == os.path.abspath(source), "provenance holds the path")
    check(provenance["options"]["time_column"] == "t", "provenance holds the options")
    check(not [n for n in os.listdir(os.path.dirname(out)) if n != "bench_run.h5"],
          "no temporary file left next to the output")

    again = run(["import", source, "-o", out, "--units", "deg/h", "--time-column", "t",
                 "--rate-columns", "gx,gy,gz"])
    check(again.returncode == 1 and "give --force" in again.stderr,
          f"an existing output is refused without --force ({again.stderr.strip()})")
    return out


def case_matlab(tmp):
    data = gyro_data(2) / 3600.0 * np.pi / 180.0  # rad/s
    source = os.path.join(tmp, "bench_mat.mat")
    recording_sources.write_mat(source, "rate", data.T, RATE_HZ)  # N x 3 in MATLAB, HDF5 [3, N]
    out = os.path.join(tmp, "rec", "bench_mat.h5")
    r = run(["import", source, "-o", out, "--units", "rad/s", "--variable", "rate",
             "--sample-rate-variable", "fs", "--axes", "x,y,z"])
    check(r.returncode == 0, f"import of a MATLAB v7.3 file exits 0 ({r.returncode}: "
          f"{r.stderr.strip()})")
    with h5py.File(out, "r") as f:
        check(f["rate"].shape == (N, 3), f"the [3, N] MATLAB matrix became [N, 3] "
              f"({f['rate'].shape})")
        check(np.array_equal(f["rate"][()], data), "/rate equals the MATLAB matrix exactly")
        check(f["rate"].attrs["units"] == "rad/s", "/rate units rad/s")
        check(f.attrs["sample_rate_hz"] == RATE_HZ, "sample rate from the variable fs")
        provenance = json.loads(f.attrs["import_provenance"])
    check(provenance["source"]["format"] == "matlab-v7.3", "provenance names the format")
    return out


def case_refusals(tmp):
    # A time column with one irregular step at data row 100 (file line 102: header is line 1).
    t = np.arange(200) / RATE_HZ
    t[100:] += 0.04
    source = os.path.join(tmp, "jitter.csv")
    np.savetxt(source, np.column_stack([t, gyro_data(3)[:200, 0]]), fmt="%.17g",
               delimiter=",", header="t,x", comments="")
    r = run(["import", source, "-o", os.path.join(tmp, "jitter.h5"), "--units", "deg/h",
             "--time-column", "t"])
    check(r.returncode == 1 and "line 102" in r.stderr and "not uniform" in r.stderr,
          f"a non-uniform time column is refused naming line 102 ({r.stderr.strip()})")
    check(not os.path.exists(os.path.join(tmp, "jitter.h5")), "nothing written for it")

    source = os.path.join(tmp, "wide.mat")
    # HDF5 [N, 2]: MATLAB 2 x N, 2 samples
    recording_sources.write_mat(source, "rate", gyro_data(4)[:, :2], RATE_HZ)
    r = run(["import", source, "-o", os.path.join(tmp, "wide.h5"), "--units", "deg/h",
             "--variable", "rate", "--sample-rate-variable", "fs"])
    check(r.returncode == 1 and "a transposed matrix?" in r.stderr,
          f"more axes than samples is refused as a transposed matrix ({r.stderr.strip()})")

    source = os.path.join(tmp, "old.mat")
    with open(source, "wb") as fh:
        fh.write(b"MATLAB 5.0 MAT-file, Platform: GLNXA64".ljust(128) + bytes(512))
    r = run(["import", source, "-o", os.path.join(tmp, "old.h5"), "--units", "deg/h",
             "--variable", "rate", "--sample-rate-hz", "10"])
    check(r.returncode == 1 and "-v7.3" in r.stderr and "CSV" in r.stderr,
          f"an older MAT-file is refused with advice ({r.stderr.strip()})")

    r = run(["import", source, "-o", os.path.join(tmp, "x.h5")])
    check(r.returncode == 2, f"a missing --units is a usage error ({r.returncode})")


def main():
    tmp = tempfile.mkdtemp(prefix="fogpipe_import_test_")
    try:
        csv_out = case_csv(tmp)
        mat_out = case_matlab(tmp)
        for path in (csv_out, mat_out):
            r = run(["validate", path])
            check(r.returncode == 0 and "valid recording" in r.stdout,
                  f"validate: {os.path.basename(path)} is valid ({r.stdout.strip()})")
        results = os.path.join(tmp, "results")
        r = run(["run", csv_out, mat_out, "-o", results, "--threads", "2"])
        check(r.returncode == 0, f"run on the imported recordings exits 0 ({r.returncode}: "
              f"{r.stderr.strip()[-400:]})")
        with open(os.path.join(results, "status.jsonl")) as fh:
            statuses = [json.loads(line) for line in fh]
        check(len(statuses) == 2 and all(s["status"] == "ok" for s in statuses),
              f"run: both imported recordings analysed, status ok ({statuses})")
        case_refusals(tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
