#!/usr/bin/python3
"""Hostile inputs through the binary: every file of hostile_corpus.py fails with its named error
kind beside valid files that all finish, in `run` (twice: a rerun does not crash either) and in
`validate`; a FIFO given by name is refused at once; a write error (EFBIG through RLIMIT_FSIZE,
the same path as ENOSPC) is a named failure with no partial output, in `run`, `simulate` and
`merge`; a planted status.jsonl
symlink is refused; overlapping runs into one folder never fail spuriously.

Usage: hostile_inputs_test.py FOGPIPE_BINARY [TRIALS]   (TRIALS: overlapping-run trials, default 3)
"""
import json
import os
import resource
import signal
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import hostile_corpus  # noqa: E402

FOGPIPE = sys.argv[1]
TRIALS = int(sys.argv[2]) if len(sys.argv) > 2 else 3
failures = []


def check(condition, message):
    print(("ok   " if condition else "FAIL ") + message, flush=True)
    if not condition:
        failures.append(message)


def status_lines(outdir):
    with open(os.path.join(outdir, "status.jsonl")) as f:
        return [json.loads(line) for line in f]


def run(args, timeout=300, preexec=None):
    return subprocess.run([FOGPIPE] + args, capture_output=True, text=True, timeout=timeout,
                          preexec_fn=preexec)


def campaign(tmp):
    folder = os.path.join(tmp, "corpus")
    os.makedirs(folder)
    bad = hostile_corpus.write_corpus(folder)
    valid = [os.path.join(folder, f"valid_{i}.h5") for i in range(3)]
    for i, p in enumerate(valid):
        hostile_corpus.write_valid(p, 200 + i)
    fifo = bad.pop(os.path.join(folder, "fifo.h5"))  # given by name below, not listed by a folder
    for attempt in ("first run", "rerun"):
        outdir = os.path.join(tmp, "out")
        r = run(["run", folder, "-o", outdir, "--threads", "2"])
        check(r.returncode == 1, f"{attempt}: exit code 1 (some files failed), got {r.returncode}")
        lines = {line["file"]: line for line in status_lines(outdir)[-len(bad) - len(valid):]}
        for p in valid:
            status = lines.get(p, {}).get("status")
            check(status in ("ok", "skipped"), f"{attempt}: {os.path.basename(p)} finished ({status})")
        for p, kind in sorted(bad.items()):
            line = lines.get(p, {})
            check(line.get("status") == "failed" and p in line.get("message", ""),
                  f"{attempt}: {os.path.basename(p)} failed with a message naming it")
        v = run(["validate"] + sorted(bad), timeout=600)
        check(v.returncode == 1, f"{attempt}: validate exit code 1, got {v.returncode}")
        for p, kind in sorted(bad.items()):
            named = any(p in line and "INVALID" in line for line in v.stdout.splitlines())
            check(named, f"{attempt}: validate calls {os.path.basename(p)} INVALID")
    # The kinds, through validate's "[kind]" tags and run's messages.
    v = run(["validate"] + sorted(bad), timeout=600)
    for p, kind in sorted(bad.items()):
        block = "\n".join(l for l in v.stdout.splitlines() if p in l)
        # The schema check comes first in validate and names a soft-link cycle its own way.
        expected = "dangling link" if p.endswith("soft_cycle.h5") else f"[{kind}]"
        check(expected in block, f"validate names {os.path.basename(p)}: {expected}")
    fifo_path = os.path.join(folder, "fifo.h5")
    r = run(["run", fifo_path, valid[0], "-o", os.path.join(tmp, "out_fifo")], timeout=60)
    line = [l for l in status_lines(os.path.join(tmp, "out_fifo")) if l["file"] == fifo_path]
    check(bool(line) and "FIFO" in line[0]["message"], f"a FIFO given by name is refused ({fifo})")
    a = run(["allan", os.path.join(folder, "heap_crash.h5")], timeout=60)
    check(a.returncode == 1 and "reader_crashed" in a.stderr,
          f"allan names the crashing file (rc {a.returncode})")


def write_error(tmp):
    src = os.path.join(tmp, "w.h5")
    hostile_corpus.write_valid(src, 300)
    outdir = os.path.join(tmp, "out_full")
    os.makedirs(outdir)

    def small_files():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (20 * 1024, 20 * 1024))

    r = run(["run", src, "-o", outdir], preexec=small_files)
    check(r.returncode == 1, f"a write error: exit code 1, no crash (got {r.returncode})")
    lines = status_lines(outdir)
    check(len(lines) == 1 and lines[0]["status"] == "failed" and "File too large" in
          lines[0]["message"], "the write error is that file's named failure")
    check(sorted(os.listdir(outdir)) == ["status.jsonl"], "no partial output is left")

    # simulate and merge under the same limit: a named error, no partial file, and none of the
    # HDF5 C++ destructors' own complaints on stderr.
    sim = os.path.join(tmp, "sim_full")
    r = run(["simulate", "-o", sim, "--files", "2", "--profile", "paper", "--seed", "5"],
            preexec=small_files)
    check(r.returncode == 1 and "sim_000.h5" in r.stderr and "sim_001.h5" in r.stderr and
          "File too large" in r.stderr, f"simulate names each file it could not write ({r.returncode})")
    check(os.listdir(sim) == [], f"simulate leaves no partial recording ({os.listdir(sim)})")
    check("~" not in r.stderr, "simulate's stderr has no destructor messages")
    done = os.path.join(tmp, "out_merge")
    r = run(["run", src, "-o", done])
    check(r.returncode == 0, f"a results folder to merge ({r.returncode})")
    r = run(["merge", done], preexec=small_files)
    check(r.returncode == 2 and "campaign.h5" in r.stderr and "File too large" in r.stderr,
          f"merge names the table it could not write ({r.returncode})")
    check(not any(n.startswith("campaign") for n in os.listdir(done)),
          f"merge leaves no partial table ({sorted(os.listdir(done))})")
    check("~" not in r.stderr, "merge's stderr has no destructor messages")


def planted_symlink(tmp):
    src = os.path.join(tmp, "s.h5")
    hostile_corpus.write_valid(src, 301)
    outdir = os.path.join(tmp, "out_link")
    os.makedirs(outdir)
    target = os.path.join(tmp, "victim.txt")
    with open(target, "w") as f:
        f.write("untouched\n")
    os.symlink(target, os.path.join(outdir, "status.jsonl"))
    r = run(["run", src, "-o", outdir])
    check(r.returncode == 2, f"a planted status.jsonl symlink is refused (rc {r.returncode})")
    with open(target) as f:
        check(f.read() == "untouched\n", "the symlink's target is not written")


def overlapping(tmp):
    srcs = []
    for i in range(4):
        srcs.append(os.path.join(tmp, f"c{i}.h5"))
        hostile_corpus.write_valid(srcs[-1], 400 + i, n=20000)
    spurious = 0
    for trial in range(TRIALS):
        outdir = os.path.join(tmp, f"out_overlap{trial}")
        procs = [subprocess.Popen([FOGPIPE, "run", "--force"] + srcs + ["-o", outdir, "--threads",
                                  "1"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                  text=True) for _ in range(2)]
        for p in procs:
            _, err = p.communicate(timeout=600)
            spurious += p.returncode != 0
        bad = [l for l in status_lines(outdir) if l["status"] != "ok"]
        spurious += len(bad)
        lines = open(os.path.join(outdir, "status.jsonl")).read().splitlines()
        check(all(l.startswith("{") and l.endswith("}") for l in lines),
              f"trial {trial}: every status line whole")
    check(spurious == 0, f"{TRIALS} trials of two overlapping runs: {spurious} spurious failures")


with tempfile.TemporaryDirectory() as tmp:
    campaign(tmp)
    write_error(tmp)
    planted_symlink(tmp)
    overlapping(tmp)
print(f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
