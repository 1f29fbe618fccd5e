#!/usr/bin/python3
"""Checks a campaign table written by `fogpipe merge` (fogpipe-campaign-v1) with h5py.

  check_campaign.py CAMPAIGN_H5 MANIFEST [--expect-complete | --expect-missing K]
                    [--status-log OUTDIR/status.jsonl]

- every column of /campaign has the same length, numeric ones carry a `units` attribute;
- per signal, the terms named in <signal>_unreliable_reasons ("B: ... | K: ...") are exactly
  those of <signal>_unreliable_terms ("B,K"): no flag without its reason, no reason without a flag;
- the recordings in the table are exactly those of the manifest, and every (recording, axis) pair
  appears once (nothing lost, nothing counted twice);
- --expect-complete: every row is "ok", has finite N for raw and method 1, and its external link
  under /results opens the results file of that recording;
- --expect-missing K: exactly K recordings are "missing" and the others "ok";
- --status-log: every recording has exactly one "ok" line (it was analysed once; a resubmitted
  shard skipped what the killed attempt had finished).
Uses only h5py and numpy (Debian python3-h5py).
"""
import argparse
import collections
import json
import math
import re
import sys

import h5py
import numpy as np


def text(values):
    return [v.decode() if isinstance(v, bytes) else str(v) for v in values]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("campaign")
    ap.add_argument("manifest")
    ap.add_argument("--expect-complete", action="store_true")
    ap.add_argument("--expect-missing", type=int, default=None)
    ap.add_argument("--status-log")
    a = ap.parse_args()
    errors = []
    manifest = []
    with open(a.manifest) as f:
        for line in f:
            # The manifest's path field (fogpipe's graph::ParseManifestLine): double-quoted with
            # backslash escapes, or a run of non-blanks; '#' starts a comment where a field would.
            fields = re.findall(r'"(?:[^"\\]|\\.)*"|\S+', line)
            if fields and not fields[0].startswith("#"):
                first = fields[0]
                if first.startswith('"'):
                    first = re.sub(r"\\(.)", r"\1", first[1:-1])
                manifest.append(first)
    with h5py.File(a.campaign, "r") as h5:
        if h5.attrs["fogpipe_format"] != "fogpipe-campaign-v1":
            errors.append("wrong fogpipe_format")
        c = h5["campaign"]
        n = int(h5.attrs["rows"])
        for name, ds in c.items():
            if ds.shape != (n,):
                errors.append(f"column {name} has shape {ds.shape}, expected ({n},)")
            if ds.dtype.kind == "f" and "units" not in ds.attrs:
                errors.append(f"numeric column {name} has no units")
        for signal in ("raw", "method1", "method2"):
            listed = text(c[f"{signal}_unreliable_terms"][()])
            reasons = text(c[f"{signal}_unreliable_reasons"][()])
            for row, (terms, why) in enumerate(zip(listed, reasons)):
                named = [part.split(":", 1)[0] for part in why.split(" | ")] if why else []
                if named != (terms.split(",") if terms else []):
                    errors.append(f"row {row}: {signal}_unreliable_terms {terms!r} but reasons "
                                  f"for {named}")
        inputs = text(c["input_path"][()])
        axes = text(c["axis"][()])
        status = text(c["status"][()])
        files = text(c["results_file"][()])
        pairs = collections.Counter(zip(inputs, axes))
        twice = [p for p, k in pairs.items() if k > 1]
        if twice:
            errors.append(f"counted twice: {twice}")
        if set(inputs) != set(manifest):
            errors.append(f"lost: {sorted(set(manifest) - set(inputs))}, "
                          f"extra: {sorted(set(inputs) - set(manifest))}")
        per_file = {}
        for path, s in zip(inputs, status):
            per_file.setdefault(path, set()).add(s)
        if a.expect_complete:
            bad = {p: s for p, s in per_file.items() if s != {"ok"}}
            if bad:
                errors.append(f"not ok: {bad}")
            for col in ("raw_N", "duration_s"):
                values = c[col][()]
                if not np.all(np.isfinite(values)) or not np.all(values > 0):
                    errors.append(f"{col} not finite and positive: {values}")
            # Method 1 may remove the white noise entirely (its fast IMFs judged pure noise), so
            # its fitted N may be 0; it must be finite and non-negative. It is not bounded by
            # raw's: a filtered output's Allan curve has the filter's shape, and the five-term
            # fit may put more of it into N than the raw curve's fit does.
            m1, raw = c["method1_N"][()], c["raw_N"][()]
            if not np.all(np.isfinite(m1)) or not np.all(m1 >= 0):
                errors.append(f"method1_N not finite and >= 0: {m1} vs {raw}")
            for path, name in zip(inputs, files):
                if not name:
                    continue  # no results file: already reported as not ok
                link = name[: -len(".fogpipe.h5")]
                try:
                    linked = h5["results"][link]["provenance"].attrs["input_path"]
                except KeyError as e:
                    errors.append(f"external link /results/{link} does not resolve: {e}")
                    continue
                if linked != path:
                    errors.append(f"/results/{link} is the results of {linked}, not {path}")
        if a.expect_missing is not None:
            missing = [p for p, s in per_file.items() if s == {"missing"}]
            ok = [p for p, s in per_file.items() if s == {"ok"}]
            if len(missing) != a.expect_missing or len(missing) + len(ok) != len(per_file):
                errors.append(f"expected {a.expect_missing} missing, got {len(missing)} missing "
                              f"and {len(ok)} ok of {len(per_file)}")
        print(f"check_campaign: {n} rows, {len(per_file)} recordings, status "
              f"{dict(collections.Counter(status))}, N(method 1)/N(raw) median "
              f"{np.nanmedian(c['method1_N'][()] / c['raw_N'][()]) if n else math.nan:.3g}")
    if a.status_log:
        ok_lines = collections.Counter()
        with open(a.status_log) as f:
            for line in f:
                entry = json.loads(line)
                if entry["status"] == "ok":
                    ok_lines[entry["file"]] += 1
        wrong = {p: ok_lines[p] for p in manifest if ok_lines[p] != 1}
        if wrong:
            errors.append(f"recordings not analysed exactly once: {wrong}")
    for e in errors:
        print("check_campaign: FAIL:", e, file=sys.stderr)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
