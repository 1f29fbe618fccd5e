#!/usr/bin/python3
"""Fuzz campaign: mutants of valid recordings (random byte overwrites, truncations, and the
global-heap corruptions of tests/pipeline/reliability/hostile_corpus.py) run through
`fogpipe run` beside valid files. Passes when the process never dies of a signal or a timeout,
every input has one status line, every failure names its file, and every valid file is ok.

Usage: fuzz_campaign.py FOGPIPE_BINARY MUTANTS [SEED] [BATCH]
"""
import json
import os
import random
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests",
                                "pipeline", "reliability"))
import hostile_corpus  # noqa: E402

FOGPIPE, MUTANTS = sys.argv[1], int(sys.argv[2])
SEED = int(sys.argv[3]) if len(sys.argv) > 3 else 1
BATCH = int(sys.argv[4]) if len(sys.argv) > 4 else 100


def mutate(data, rng):
    data = bytearray(data)
    kind = rng.random()
    if kind < 0.1:
        return bytes(data[: rng.randrange(1, len(data))]), "truncated"
    if kind < 0.2:
        at = data.find(b"GCOL")
        data[at + rng.randrange(16, 40)] = rng.randrange(256)
        return bytes(data), "heap byte"
    for _ in range(rng.randrange(1, 9)):
        data[rng.randrange(len(data))] = rng.randrange(256)
    return bytes(data), "bytes"


def main():
    rng = random.Random(SEED)
    crashes = hangs = unnamed = lost = valid_bad = 0
    kinds = {}
    with tempfile.TemporaryDirectory() as tmp:
        seeds = []
        for i in range(3):
            p = os.path.join(tmp, f"seed{i}.h5")
            hostile_corpus.write_valid(p, 500 + i, n=600, axes=1 + i % 2)
            seeds.append(open(p, "rb").read())
        done = 0
        batch_index = 0
        while done < MUTANTS:
            folder = os.path.join(tmp, f"batch{batch_index}")
            os.makedirs(folder)
            count = min(BATCH, MUTANTS - done)
            for j in range(count):
                data, kind = mutate(rng.choice(seeds), rng)
                with open(os.path.join(folder, f"m{done + j:05d}.h5"), "wb") as f:
                    f.write(data)
            valid = os.path.join(folder, "zz_valid.h5")
            hostile_corpus.write_valid(valid, 600 + batch_index)
            outdir = os.path.join(tmp, f"out{batch_index}")
            try:
                r = subprocess.run([FOGPIPE, "run", folder, "-o", outdir, "--threads", "2"],
                                   capture_output=True, text=True, errors="replace",
                                   timeout=1800)
                if r.returncode < 0 or r.returncode > 2:
                    crashes += 1
                    print(f"batch {batch_index}: exit {r.returncode}; stderr ends:\n"
                          + r.stderr[-600:], flush=True)
            except subprocess.TimeoutExpired:
                hangs += 1
                done += count
                batch_index += 1
                continue
            lines = [json.loads(l) for l in open(os.path.join(outdir, "status.jsonl"))]
            by_file = {l["file"]: l for l in lines}
            lost += count + 1 - len(by_file)
            for f, l in by_file.items():
                if f == valid:
                    valid_bad += l["status"] != "ok"
                elif l["status"] == "failed":
                    unnamed += f not in l["message"]
                    tag = l["message"][len(f) + 2:].split(":")[0][:40]
                    kinds[tag] = kinds.get(tag, 0) + 1
                else:
                    kinds["ok (mutation harmless)"] = kinds.get("ok (mutation harmless)", 0) + 1
            done += count
            batch_index += 1
    print(f"{MUTANTS} mutants (seed {SEED}): {crashes} crashes, {hangs} hangs, {lost} inputs "
          f"without a status line, {unnamed} failures not naming their file, {valid_bad} valid "
          f"files not ok")
    for tag, n in sorted(kinds.items(), key=lambda kv: -kv[1])[:15]:
        print(f"  {n:5d}  {tag}")
    sys.exit(1 if crashes + hangs + lost + unnamed + valid_bad else 0)


if __name__ == "__main__":
    main()
