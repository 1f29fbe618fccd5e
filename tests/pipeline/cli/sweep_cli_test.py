#!/usr/bin/python3
"""End-to-end test of `fogpipe sweep`, `plan` and `merge` through the binary (h5py, numpy only).

  sweep_cli_test.py FOGPIPE SOURCE_DIR

- sweep: a simulated recording with a moving true rate and a grid held in a TOML config file;
  the HDF5 table has one column per metric with units, one row per setting (the default rule of
  every order included), the CSV has the same rows, the ranking is sorted by the RMS error, and
  scripts/plot_sweep.py draws the picture; an unknown config key is a usage error (exit 2);
- progress: with stderr on a terminal, sweep's progress lines appear there (one per table and
  stage, redrawn in place) and never on stdout; with stderr in a file there are none unless
  --progress asks for them;
- plan + run + merge: a campaign merged twice (idempotent), one recording processed twice
  (--force) still gives one row, and a recording listed in the manifest but never run is
  "missing".
"""
import csv
import os
import pty
import select
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np


def run(*args, ok=(0,)):
    p = subprocess.run([str(a) for a in args], capture_output=True, text=True)
    if p.returncode not in ok:
        sys.exit(f"FAIL: {' '.join(map(str, args))} -> {p.returncode}\n{p.stdout}\n{p.stderr}")
    return p


def run_with_terminal_stderr(*args):
    """(exit code, stdout, stderr) of a run whose stderr is a pseudo-terminal."""
    master, slave = pty.openpty()
    p = subprocess.Popen([str(a) for a in args], stdout=subprocess.PIPE, stderr=slave)
    os.close(slave)
    err = b""
    while True:  # drain the terminal while the program runs, or it blocks on a full one
        if select.select([master], [], [], 0.5)[0]:
            try:
                chunk = os.read(master, 65536)
            except OSError:  # EIO: the program closed its end
                break
            if not chunk:
                break
            err += chunk
        elif p.poll() is not None:
            break
    out = p.stdout.read()
    p.wait()
    os.close(master)
    return p.returncode, out.decode(), err.decode()


def check_progress(fogpipe, rec, out):
    """Progress on a terminal's stderr, none on stdout, none in a log by default."""
    grid = ["--ar-order", "2,4", "--q-scale", "1", "--r-scale", "1"]
    code, stdout, stderr = run_with_terminal_stderr(fogpipe, "sweep", rec, "-o", out, *grid)
    assert code == 0, (code, stdout, stderr)
    for line in ["sweep " + rec + ": table 1/1 (axis axis0, 10 sifts)", ", stage ", "ETA",
                 "writing "]:
        assert line in stderr, (line, stderr)
    assert "\r\x1b[K" in stderr, "a terminal's progress line is redrawn in place"
    assert "sweep " + rec + ":" not in stdout and "stage" not in stdout, stdout
    assert "rank" in stdout, stdout
    logged = run(fogpipe, "sweep", rec, "-o", out, *grid)
    assert "stage" not in logged.stderr and "stage" not in logged.stdout, logged.stderr
    asked = run(fogpipe, "sweep", rec, "-o", out, *grid, "--progress")
    # In a log each step is printed, the stages' counts at most every 10 s (none in this short run).
    for line in ["sweep " + rec + ": table 1/1", "writing "]:
        assert line in asked.stderr, (line, asked.stderr)
    assert "\r\x1b[K" not in asked.stderr, "a log's progress lines are not redrawn"
    assert "stage" not in asked.stdout and "rank" in asked.stdout, asked.stdout


def main():
    fogpipe, source = sys.argv[1], sys.argv[2]
    tmp = tempfile.mkdtemp(prefix="fogpipe_sweep_cli_")
    rec = os.path.join(tmp, "moving.h5")
    run(fogpipe, "simulate", "-o", rec, "--duration-s", "1200", "--sample-rate-hz", "10",
        "--seed", "4", "--n-deg-sqrt-h", "0.05", "--rate-profile", "step:300:20,sine:0.005:10")
    config = os.path.join(tmp, "grid.toml")
    with open(config, "w") as f:
        # A grid as the command line spells it, or as a TOML array; in [sweep] or at the top.
        f.write('ar-order = "2,4"\n[sweep]\nq-scale = [0.1, 1]\nr-scale = [1, 10, 100]\n')
    out = os.path.join(tmp, "sweep")
    p = run(fogpipe, "sweep", rec, "-o", out, "--config", config, "--threads", "2")
    print(p.stdout)
    with h5py.File(os.path.join(out, "moving.sweep.h5"), "r") as h5:
        assert h5.attrs["fogpipe_format"] == "fogpipe-sweep-v1"
        t = h5["axes/axis0/emd_sifts_10"]
        rows = 2 * (2 * 3 + 1)
        for name, ds in t.items():
            if ds.dtype.kind == "f":
                assert "units" in ds.attrs, name
                assert ds.shape[0] == rows, (name, ds.shape)
        assert t["rms_error"].attrs["units"] == "deg/h"
        assert int(t.attrs["has_truth"]) == 1
        assert t["fit_one_step_percent"].shape == (rows, int(t.attrs["num_imfs"]) + 1)
        assert np.sum(t["default_rule"][()]) == 2
        rms = t["rms_error"][()]
        ranking = t["ranking"][()]
        assert np.all(np.diff(rms[ranking]) >= 0), "ranking not sorted by rms_error"
        # Every evaluated setting has an RMS error; a setting whose filter diverged on a component
        # (README, Known limitations: it happens to AR(4) on imf10 here in a build without fused
        # multiply-adds) is reported, not ranked, and has none.
        ok = np.array([s == b"ok" for s in t["status"][()]])
        assert np.all(np.isfinite(rms[ok])) and np.all(rms[ok] > 0)
        assert np.all(np.isnan(rms[~ok])) and not set(ranking) & set(np.flatnonzero(~ok))
        assert np.all(ok[t["default_rule"][()] == 1]), "the default rule is evaluated"
    with open(os.path.join(out, "moving.sweep.csv")) as f:
        assert len(list(csv.DictReader(f))) == rows
    run("/usr/bin/python3", os.path.join(source, "scripts/plot_sweep.py"),
        os.path.join(out, "moving.sweep.h5"), "-o", os.path.join(tmp, "sweep.png"))
    assert os.path.getsize(os.path.join(tmp, "sweep.png")) > 1000
    with open(config, "a") as f:
        f.write("no-such-key = 1\n")
    run(fogpipe, "sweep", rec, "-o", out, "--config", config, ok=(2,))
    check_progress(fogpipe, rec, os.path.join(tmp, "progress"))

    data = os.path.join(tmp, "data")
    run(fogpipe, "simulate", "-o", data, "--files", "3", "--profile", "paper", "--duration-s",
        "600", "--sample-rate-hz", "10", "--seed", "8", "--serial", "FOG-7")
    manifest = os.path.join(tmp, "manifest.txt")
    run(fogpipe, "plan", data, "-o", manifest)
    listed = [l.split()[0] for l in open(manifest) if not l.startswith("#")]
    assert len(listed) == 3 and listed == sorted(listed)
    outdir = os.path.join(tmp, "out")
    run(fogpipe, "run", listed[0], listed[1], "-o", outdir, "--threads", "1")
    run(fogpipe, "run", listed[0], "-o", outdir, "--threads", "1", "--force")
    campaign = os.path.join(tmp, "campaign.h5")
    for _ in range(2):  # idempotent
        run(fogpipe, "merge", outdir, "-o", campaign, "--manifest", manifest, ok=(1,))
        with h5py.File(campaign, "r") as h5:
            c = h5["campaign"]
            inputs = [v.decode() for v in c["input_path"][()]]
            status = [v.decode() for v in c["status"][()]]
            assert sorted(inputs) == sorted(listed), inputs
            assert status.count("ok") == 2 and status.count("missing") == 1, status
            assert [v.decode() for v in c["serial"][()]][:2] == ["FOG-7", "FOG-7"]
            for name in h5["results"]:
                assert h5["results"][name]["provenance"].attrs["input_path"] in listed
    shutil.rmtree(tmp)
    print("sweep_cli_test: ok")


if __name__ == "__main__":
    main()
