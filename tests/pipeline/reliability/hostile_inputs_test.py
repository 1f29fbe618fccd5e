#!/usr/bin/python3
"""Hostile inputs through the binary: every file of hostile_corpus.py fails with its named error
kind beside valid files that all finish, in `run` (twice: a rerun does not crash either) and in
`validate`; a FIFO given by name is refused at once; a write error (EFBIG through RLIMIT_FSIZE,
the same path as ENOSPC) is a named failure with no partial output, in `run`, `simulate` and
`merge`; a full output device (ENOSPC on a tmpfs) stops the campaign cleanly; planted
status.jsonl and campaign.csv symlinks are refused; overlapping runs into one folder never fail spuriously.

Usage: hostile_inputs_test.py FOGPIPE_BINARY [TRIALS]   (TRIALS: overlapping-run trials, default 3)
"""
import csv
import json
import os
import resource
import signal
import subprocess
import sys
import tempfile

import h5py
import numpy as np

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
    suspect = hostile_corpus.write_suspects(folder)
    valid = [os.path.join(folder, f"valid_{i}.h5") for i in range(3)]
    for i, p in enumerate(valid):
        hostile_corpus.write_valid(p, 200 + i)
    # Inside the magnitude limits at both ends: analysed like any other record.
    for p, scale in ((valid[1], 1e55), (valid[2], 1e-55)):
        with h5py.File(p, "a") as f:
            f["rate"][...] = f["rate"][...] * scale
    fifo = bad[os.path.join(folder, "fifo.h5")]  # listed by the folder, and given by name below
    for attempt in ("first run", "rerun"):
        outdir = os.path.join(tmp, "out")
        r = run(["run", folder, "-o", outdir, "--threads", "2"])
        check(r.returncode == 1, f"{attempt}: exit code 1 (some files failed), got {r.returncode}")
        count = len(bad) + len(valid) + len(suspect)
        lines = {line["file"]: line for line in status_lines(outdir)[-count:]}
        for p in valid:
            status = lines.get(p, {}).get("status")
            check(status in ("ok", "skipped"), f"{attempt}: {os.path.basename(p)} finished ({status})")
        for p, phrase in sorted(suspect.items()):
            line = lines.get(p, {})
            if attempt == "first run":
                check(line.get("status") == "ok" and "warning: axis" in line.get("message", "")
                      and phrase in line.get("message", ""),
                      f"{attempt}: {os.path.basename(p)} analysed with a warning naming "
                      f"'{phrase}' ({line})")
            else:
                check(line.get("status") == "skipped", f"{attempt}: {os.path.basename(p)} skipped")
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
        expected = f"[{kind}]"
        check(expected in block, f"validate names {os.path.basename(p)}: {expected}")
        check("missing required" not in block,
              f"validate does not call a link it did not follow missing ({os.path.basename(p)})")
    # The warning reaches the campaign table, `info` and `allan`.
    outdir = os.path.join(tmp, "out")
    csv_path = os.path.join(tmp, "campaign.csv")
    run(["merge", outdir, "-o", os.path.join(tmp, "campaign.h5"), "--csv", csv_path])
    with open(csv_path) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    for p, phrase in sorted(suspect.items()):
        row = [r for r in rows if r["input_path"] == p]
        check(len(row) == 1 and phrase in row[0]["data_warning"],
              f"the campaign table's data_warning names {os.path.basename(p)}: '{phrase}'")
    valid_rows = [r for r in rows if r["input_path"] in valid]
    check(len(valid_rows) == len(valid) and all(r["data_warning"] == "" for r in valid_rows),
          "the campaign table warns of no valid file")
    frozen = os.path.join(folder, "frozen_output.h5")
    info = run(["info", os.path.join(outdir, "frozen_output.fogpipe.h5")])
    check("warning: " + suspect[frozen] in info.stdout, "info prints the warning")
    a = run(["allan", frozen, "--json"])
    check(a.returncode == 0 and suspect[frozen] in json.loads(a.stdout)["data_warning"],
          "allan --json carries the warning")
    v = run(["validate"] + sorted(suspect), timeout=600)
    check(v.returncode == 0, f"validate calls the suspect files valid (rc {v.returncode})")
    for p, phrase in sorted(suspect.items()):
        block = "\n".join(l for l in v.stdout.splitlines() if p in l)
        check("warning" in block and phrase in block,
              f"validate warns of {os.path.basename(p)}: '{phrase}'")
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


def in_tmpfs(room_kib, outdir, report, command):
    """Runs `command` with a tmpfs of `room_kib` KiB mounted at `outdir`, in a private mount
    namespace (unshare(1)); its stdout, stderr, exit code, the folder's listing and copies of
    its files land in `report`. False (and a skip message) where no namespace can be made."""
    os.makedirs(outdir)
    os.makedirs(report)
    script = ('mount -t tmpfs -o size="$1"k tmpfs "$2" || exit 97; out="$2"; rep="$3"; '
              'shift 3; "$@" >"$rep/stdout" 2>"$rep/stderr"; '
              'echo $? >"$rep/rc"; ls -a "$out" >"$rep/listing"; '
              'for f in "$out"/*; do [ -f "$f" ] && cp "$f" "$rep/"; done; exit 0')
    try:
        ns = subprocess.run(["unshare", "-rm", "sh", "-c", script, "sh", str(room_kib), outdir,
                             report] + command, capture_output=True, text=True, timeout=600)
    except FileNotFoundError:
        ns = None
    if ns is None or ns.returncode != 0:
        print("skip full disk: no private mount namespace with a tmpfs here "
              f"({ns.stderr.strip() if ns else 'no unshare'})", flush=True)
        return False
    return True


def full_disk(tmp):
    """A real ENOSPC: the output folder is a tmpfs with room for about two results files, in a
    private mount namespace (unshare(1); skipped where the machine allows none). The campaign
    stops starting recordings once the device is full, names the ones it did not start, and
    leaves only whole results files and whole status lines."""
    srcs = []
    for i in range(8):
        srcs.append(os.path.join(tmp, f"full{i}.h5"))
        hostile_corpus.write_valid(srcs[-1], 500 + i)
    probe = os.path.join(tmp, "out_probe")
    r = run(["run", srcs[0], "-o", probe])
    check(r.returncode == 0, f"a results file to size the device ({r.returncode})")
    size = max(os.path.getsize(os.path.join(probe, n)) for n in os.listdir(probe))
    room_kib = (5 * size // 2) // 1024 + 8
    outdir = os.path.join(tmp, "out_tmpfs")
    report = os.path.join(tmp, "full_report")
    if not in_tmpfs(room_kib, outdir, report, [FOGPIPE, "run"] + srcs +
                    ["-o", outdir, "--threads", "1"]):
        return
    rc = int(open(os.path.join(report, "rc")).read())
    err = open(os.path.join(report, "stderr")).read()
    check(rc == 1, f"full disk: exit code 1, no crash (got {rc})")
    check("is full" in err and "no further recording is started" in err,
          "full disk: the campaign says the device is full and stops")
    not_started = [s for s in srcs if f"{s}: not started: the output device" in err]
    check(len(not_started) >= 3, f"full disk: the recordings not started are named "
          f"({len(not_started)} of {len(srcs)})")
    names = open(os.path.join(report, "listing")).read().split()
    temps = [n for n in names if ".tmp-" in n]
    check(temps == [], f"full disk: no temporary or partial output is left ({temps})")
    written = [n for n in names if n.endswith(".h5")]
    whole = 0
    for n in written:
        try:
            with h5py.File(os.path.join(report, n), "r") as f:
                whole += "axes" in f
        except OSError:
            pass
    check(whole == len(written) and len(written) >= 1,
          f"full disk: every results file left is whole ({whole} of {len(written)})")
    status = os.path.join(report, "status.jsonl")
    lines = open(status).read().splitlines() if os.path.exists(status) else []
    parsed = 0
    for line in lines:
        try:
            json.loads(line)
            parsed += 1
        except ValueError:
            pass
    check(parsed == len(lines), f"full disk: every status line is whole ({parsed} of {len(lines)})")

    # simulate: each recording with its truth or neither, and it stops at the full device.
    probe = os.path.join(tmp, "sim_probe")
    r = run(["simulate", "-o", probe, "--files", "1", "--profile", "paper", "--seed", "5"])
    check(r.returncode == 0, f"a simulated recording to size the device ({r.returncode})")
    size = sum(os.path.getsize(os.path.join(probe, n)) for n in os.listdir(probe))
    outdir = os.path.join(tmp, "sim_tmpfs")
    report = os.path.join(tmp, "sim_full_report")
    if not in_tmpfs((3 * size // 2) // 1024 + 8, outdir, report,
                    [FOGPIPE, "simulate", "-o", outdir, "--files", "6", "--profile", "paper",
                     "--seed", "5"]):
        return
    rc = int(open(os.path.join(report, "rc")).read())
    err = open(os.path.join(report, "stderr")).read()
    names = open(os.path.join(report, "listing")).read().split()
    recordings = sorted(n for n in names if n.endswith(".h5"))
    truths = sorted(n[:-len(".truth.json")] for n in names if n.endswith(".truth.json"))
    check(rc == 1 and "is full" in err and "more file(s) not written" in err,
          f"full disk: simulate stops at the full device and says so (rc {rc})")
    check(recordings == truths and len(recordings) >= 1,
          f"full disk: every simulated recording has its truth and no truth is alone "
          f"({recordings} / {truths})")
    check(not any(".tmp-" in n for n in names), "full disk: simulate leaves no temporary file")
    check(err.count("HDF5 error stack") <= 1,
          f"full disk: simulate reports the write error once ({err.count('HDF5 error stack')})")


def write_mat(path, seed, external=None):
    """A MATLAB v7.3-like file: a 512-byte user block, /rate stored [1, N] (MATLAB's column-major
    N x 1) with a variable-length MATLAB_class string attribute (kept in the global heap)."""
    data = np.random.default_rng(seed).standard_normal((1, 2000))
    with h5py.File(path, "w", userblock_size=512) as f:
        if external:
            data.tofile(external)
            d = f.create_dataset("rate", shape=(1, 2000), dtype="f8",
                                 external=[(external, 0, 16000)])
        else:
            d = f.create_dataset("rate", data=data)
        d.attrs["MATLAB_class"] = "double"


def hostile_import(tmp):
    """`import` of hostile MATLAB files beside a good one: a damaged heap byte (HDF5 crashes), a
    heap object of size 0 (HDF5 loops), samples kept in an external raw file, and a FIFO. Each is
    named and refused, the good file is imported, and nothing outside the inputs is read."""
    folder = os.path.join(tmp, "import")
    os.makedirs(folder)
    paths = {name: os.path.join(folder, name + ".mat")
             for name in ("crash", "loop", "external", "good")}
    write_mat(paths["crash"], 1)
    hostile_corpus.corrupt_units_heap(paths["crash"])
    write_mat(paths["loop"], 2)
    hostile_corpus.corrupt_units_heap(paths["loop"], offset=24, value=0)
    write_mat(paths["external"], 3, external=os.path.join(folder, "secret.bin"))
    write_mat(paths["good"], 4)
    fifo = os.path.join(folder, "pipe.csv")
    os.mkfifo(fifo)
    out = os.path.join(tmp, "import_out")
    os.makedirs(out)
    r = run(["import", "--units", "deg/h", "--variable", "rate", "--sample-rate-hz", "100",
             "-o", out + "/", paths["crash"], paths["loop"], paths["external"], fifo,
             paths["good"]], timeout=120)
    check(r.returncode == 1, f"import of hostile files: exit 1, no crash ({r.returncode})")
    for name, expected in (("crash", "crashed"), ("loop", "did not finish"),
                           ("external", "external raw file")):
        line = [l for l in r.stderr.splitlines() if paths[name] in l]
        check(bool(line) and expected in line[0],
              f"import names {name}.mat: {expected} ({line[0] if line else r.stderr[-300:]})")
    check(any(fifo in l and "FIFO" in l for l in r.stderr.splitlines()),
          "import refuses a FIFO by name before opening it")
    check(sorted(os.listdir(out)) == ["good.h5"], f"only the good file is imported ({os.listdir(out)})")


def full_scratch(tmp):
    """A real ENOSPC in the scratch folder (--scratch-dir on a 64 KiB tmpfs, where a recording's
    IMFs take about 200 KiB): the recording fails with the folder and the system's message, the
    campaign stops as on a full output device and names what it did not start, and nothing is
    left in either folder."""
    srcs = []
    for i in range(4):
        srcs.append(os.path.join(tmp, f"scratch{i}.h5"))
        hostile_corpus.write_valid(srcs[-1], 700 + i)
    scratch = os.path.join(tmp, "scratch_tmpfs")
    outdir = os.path.join(tmp, "out_scratch_full")
    os.makedirs(outdir)
    report = os.path.join(tmp, "scratch_report")
    if not in_tmpfs(64, scratch, report, [FOGPIPE, "run"] + srcs +
                    ["-o", outdir, "--threads", "1", "--scratch-dir", scratch]):
        return
    rc = int(open(os.path.join(report, "rc")).read())
    err = open(os.path.join(report, "stderr")).read()
    check(rc == 1, f"full scratch: exit code 1, no crash (got {rc})")
    lines = [json.loads(l) for l in open(os.path.join(outdir, "status.jsonl"))]
    failed = [l for l in lines if l["status"] == "failed" and f"scratch file in {scratch}" in
              l["message"] and "No space left on device" in l["message"] and
              l["message"].startswith(l["file"])]
    check(len(failed) >= 1, f"full scratch: the recording's failure names it, the scratch "
          f"folder and the error ({[l['message'][:200] for l in lines][:2]})")
    check("is full" in err and "no further recording is started" in err,
          f"full scratch: the campaign says the device is full and stops ({err.strip()[:200]})")
    not_started = [s for s in srcs if f"{s}: not started:" in err]
    check(len(not_started) >= 2, f"full scratch: the recordings not started are named "
          f"({len(not_started)} of {len(srcs)})")
    listing = [n for n in open(os.path.join(report, "listing")).read().split()
               if n not in (".", "..")]
    check(listing == [], f"full scratch: nothing is left in the scratch folder ({listing})")
    check([n for n in os.listdir(outdir) if ".tmp-" in n] == [],
          "full scratch: no temporary output is left")


def damaged_results(tmp):
    """`info` on results files with one size byte of a global-heap object set to 0xFF (the byte
    that crashes HDF5 1.10's attribute reader): never a crash, each damaged file named, and the
    files beside it still summarised."""
    src = os.path.join(tmp, "res.h5")
    hostile_corpus.write_valid(src, 302)
    outdir = os.path.join(tmp, "out_res")
    r = run(["run", src, "-o", outdir])
    check(r.returncode == 0, f"a results file to damage ({r.returncode})")
    good = os.path.join(outdir, "res.fogpipe.h5")
    data = open(good, "rb").read()
    objects = hostile_corpus.heap_objects(data)
    check(len(objects) >= 3, f"the results file has global-heap strings ({len(objects)})")
    crashed, named = 0, 0
    for index, offset in objects:
        bad = os.path.join(tmp, f"res_heap{index}.fogpipe.h5")
        damaged = bytearray(data)
        damaged[offset + 10] = 0xFF
        open(bad, "wb").write(damaged)
        r = run(["info", good, bad, good], timeout=120)
        crashed += r.returncode < 0 or r.returncode > 1
        named += r.returncode == 0 or bad in r.stderr
        check(r.stdout.count(good + "\n  input ") == 2,
              f"info still summarises the good files beside heap object {index}")
    check(crashed == 0, f"info on {len(objects)} damaged results files: {crashed} crashes")
    check(named == len(objects), f"every failing damaged file is named ({named} of {len(objects)})")


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
    # A FIFO (whose open would block) and a hard link to a file elsewhere, planted at the log's
    # name: refused at once, nothing written through.
    for kind in ("fifo", "hardlink"):
        out = os.path.join(tmp, f"out_planted_{kind}")
        os.makedirs(out)
        log = os.path.join(out, "status.jsonl")
        if kind == "fifo":
            os.mkfifo(log)
        else:
            os.link(target, log)
        r = run(["run", src, "-o", out], timeout=60)
        check(r.returncode == 2 and "status.jsonl" in r.stderr and "refused" in r.stderr,
              f"a planted status.jsonl {kind} is refused (rc {r.returncode}: {r.stderr.strip()})")
    with open(target) as f:
        check(f.read() == "untouched\n", "the hard link's target is not written")
    # merge --csv: the table is written beside a planted link, never through or over it.
    done = os.path.join(tmp, "out_link_merge")
    r = run(["run", src, "-o", done])
    check(r.returncode == 0, f"a results folder to merge ({r.returncode})")
    csv = os.path.join(done, "campaign.csv")
    os.symlink(target, csv)
    r = run(["merge", done, "--csv", csv])
    check(r.returncode == 2 and "symbolic link" in r.stderr,
          f"a planted campaign.csv symlink is refused (rc {r.returncode}: {r.stderr.strip()})")
    with open(target) as f:
        check(f.read() == "untouched\n", "the campaign.csv symlink's target is not written")
    check(os.path.islink(csv), "the planted link itself is left in place")
    check(not any(".tmp-" in n for n in os.listdir(done)), "merge leaves no temporary file")


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
    # Two runs at once with different inputs of one name (A/rec.h5, B/rec.h5): one is written,
    # the other fails naming the first; neither result is lost silently.
    for trial in range(TRIALS):
        pair = []
        for side in ("A", "B"):
            folder = os.path.join(tmp, f"same_name{trial}", side)
            os.makedirs(folder)
            pair.append(os.path.join(folder, "rec.h5"))
            hostile_corpus.write_valid(pair[-1], 450 + trial * 2 + len(pair), n=20000)
        outdir = os.path.join(tmp, f"out_same_name{trial}")
        procs = [subprocess.Popen([FOGPIPE, "run", src, "-o", outdir, "--threads", "1"],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                 for src in pair]
        codes = sorted(p.wait(timeout=600) for p in procs)
        lines = status_lines(outdir)
        ok = [l["file"] for l in lines if l["status"] == "ok"]
        failed = [l for l in lines if l["status"] == "failed"]
        with h5py.File(os.path.join(outdir, "rec.fogpipe.h5"), "r") as f:
            kept = f["provenance"].attrs["input_path"]
            kept = kept.decode() if isinstance(kept, bytes) else kept
        check(codes == [0, 1] and len(ok) == 1 and len(failed) == 1 and ok[0] == kept and
              "already holds the results of another input" in failed[0]["message"],
              f"trial {trial}: two runs with inputs of one name: one written, one named collision "
              f"(exit codes {codes}, ok {ok}, kept {kept})")


with tempfile.TemporaryDirectory() as tmp:
    campaign(tmp)
    write_error(tmp)
    full_disk(tmp)
    full_scratch(tmp)
    damaged_results(tmp)
    hostile_import(tmp)
    planted_symlink(tmp)
    overlapping(tmp)
print(f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
