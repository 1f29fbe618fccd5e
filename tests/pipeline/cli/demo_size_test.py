#!/usr/bin/python3
"""The demo campaign's results total at most 10x its inputs (a user requirement).

Runs what scripts/demo.sh runs: `simulate --profile paper --files 4 --seed 1`, `run`, then
compares the bytes of every file under the results folder with those under the recordings folder
(what `du -sb` counts, without the folders' own 4 KB, which would flatter the ratio). Prints the per-file breakdown (objects, IMFs, signals, the rest)
so that a layout change which regrows the files is seen where it happens (docs/performance.md,
"Results size").

Usage: demo_size_test.py FOGPIPE
"""
import os
import shutil
import subprocess
import sys
import tempfile

import h5py

LIMIT = 10.0


def folder_bytes(folder):
    return sum(os.path.getsize(os.path.join(d, n)) for d, _, names in os.walk(folder)
               for n in names)


def breakdown(path):
    """Objects, and the stored bytes of the IMFs (+ residue), of the large signals and of the
    rest (headers, small datasets, free space) of one results file."""
    sizes = {"imfs": 0, "signals": 0, "objects": 0}
    with h5py.File(path, "r") as f:
        def visit(name, obj):
            sizes["objects"] += 1
            if isinstance(obj, h5py.Dataset):
                if name.endswith(("decomposition/imfs", "decomposition/residue")):
                    sizes["imfs"] += obj.id.get_storage_size()
                elif "/signals/" in name and obj.size > 1000:
                    sizes["signals"] += obj.id.get_storage_size()
        f.visititems(visit)
    total = os.path.getsize(path)
    return (f"{os.path.basename(path)}: {total} bytes, {sizes['objects']} objects; IMFs "
            f"{sizes['imfs']}, signals {sizes['signals']}, the rest "
            f"{total - sizes['imfs'] - sizes['signals']}")


def main():
    fogpipe = sys.argv[1]
    tmp = tempfile.mkdtemp(prefix="fogpipe_demo_size_")
    try:
        rec, res = os.path.join(tmp, "rec"), os.path.join(tmp, "res")
        for args in (["simulate", "--profile", "paper", "--files", "4", "--seed", "1", "-o", rec],
                     ["run", rec, "-o", res, "--threads", "2"]):
            r = subprocess.run([fogpipe] + args, capture_output=True, text=True, timeout=900)
            if r.returncode != 0:
                print(f"FAIL fogpipe {args[0]} exits {r.returncode}: {r.stderr[-2000:]}")
                return 1
        for name in sorted(os.listdir(res)):
            if name.endswith(".fogpipe.h5"):
                print(breakdown(os.path.join(res, name)))
        inputs, results = folder_bytes(rec), folder_bytes(res)
        ratio = results / inputs
        print(f"recordings {inputs} bytes, results {results} bytes (with status.jsonl): "
              f"{ratio:.2f}x, limit {LIMIT:g}x")
        # The campaign table of `merge` is reported, not held to the limit: it grows with its
        # columns, not with the recordings.
        r = subprocess.run([fogpipe, "merge", res], capture_output=True, text=True, timeout=300)
        if r.returncode == 0:
            print(f"with campaign.h5 ({os.path.getsize(os.path.join(res, 'campaign.h5'))} bytes): "
                  f"{folder_bytes(res) / inputs:.2f}x")
        if ratio > LIMIT:
            print(f"FAIL the demo campaign's results are {ratio:.2f}x its inputs, more than "
                  f"{LIMIT:g}x")
            return 1
        return 0
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
