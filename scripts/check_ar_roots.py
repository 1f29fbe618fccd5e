#!/usr/bin/python3
"""Independent check of the AR models stored in fogpipe results files: the roots of every stored
model's characteristic polynomial z^p - phi_1 z^{p-1} - ... - phi_p, computed from the stored
doubles with mpmath at 60 significant digits (no fogpipe code involved).

Usage: scripts/check_ar_roots.py RESULTS.fogpipe.h5 ...
Prints one line per explosive model (max root modulus >= 1) and a summary per file; exits 1 if any
stored model is explosive or its `stationary` flag disagrees with the 60-digit roots.
"""
import sys

import h5py
import mpmath
import numpy as np

mpmath.mp.dps = 60


def max_root_modulus(phi):
    coefficients = [mpmath.mpf(1)] + [-mpmath.mpf(float(v)) for v in phi]
    roots = mpmath.polyroots(coefficients, maxsteps=400, extraprec=400)
    return max(abs(r) for r in roots)


def main(paths):
    bad = 0
    for path in paths:
        total = explosive = disagree = 0
        with h5py.File(path, "r") as f:
            groups = [(axis, f["axes"][axis][g]) for axis in f["axes"]
                      for g in ("models", "signals/method2_model") if g in f["axes"][axis]]
            for axis, models in groups:
                orders = models["order"][()]
                coefficients = models["coefficients"][()]
                flags = models["stationary"][()]
                names = [c.decode() if isinstance(c, bytes) else c for c in models["component"][()]]
                for i, p in enumerate(orders):
                    if p <= 0 or not np.all(np.isfinite(coefficients[i][:p])):
                        continue
                    total += 1
                    modulus = max_root_modulus(np.asarray(coefficients[i])[:p])
                    is_explosive = modulus >= 1
                    explosive += is_explosive
                    if bool(flags[i]) == bool(is_explosive):
                        disagree += 1
                    if is_explosive or bool(flags[i]) == bool(is_explosive):
                        print(f"{path}: {axis} {names[i]} AR({p}) max |root| = "
                              f"{mpmath.nstr(modulus, 15)}, stored flag stationary={bool(flags[i])}")
        print(f"{path}: {total} models, {explosive} explosive at 60 digits, "
              f"{disagree} stationarity flags that disagree")
        bad += explosive + disagree
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
