#!/usr/bin/python3
"""Checks fogpipe results files against their recordings, independently of fogpipe's C++ code.

Usage: check_results_h5py.py RESULTS.fogpipe.h5 [RESULTS...]

For every results file (Debian's python3-h5py + numpy only):
  - layout: every dataset in the file is read in full (so every compressed chunk is inflated) and
    must be described by schemas/results-v2.json: its type class, rank, `units` attribute (one of
    the allowed values), the fields of a table (compound dataset) and described attributes are checked against the schema, every required
    object of the schema must exist, and every numeric dataset has a `units` attribute;
  - shapes: with N samples, K IMFs and C = K + 1 components per axis, imfs is [N, K], residue,
    method1 and method2 are [N], kalman/filtered is [N, C], per-component tables have C rows
    (method 2's tables 1 row), per-IMF vectors K, one unit per field of each Allan table;
  - numbers, recomputed in numpy from the input recording named in /provenance:
      * the preprocessed signal x (rate converted to rad/s, start dropped, outliers replaced by the
        median of the 11 centred samples, mean removed); the stationarity windows' mean and
        variance of x before the mean was removed;
      * sum of IMFs + residue = x to 1e-12 (relative to max |x|) for float64 storage; for float32
        storage to the rounding bound 2^-24 (sum_k |imf_k| + |residue|) per sample;
      * per IMF: energy = mean square, mean period = 2 N / zero crossings;
      * per component (float64 storage): the AR mean, and one-step residuals from the stored
        coefficients, hence fit_one_step_percent, residual_variance and the Ljung-Box Q at lags 10
        and 20, with tolerances from the residuals' rounding bound (components fitted to 100.00 %
        are too ill-conditioned to compare and are counted as skipped); the same for method 2;
      * method 1 = sum of the filtered components when they are stored;
      * the overlapping Allan deviation (NIST SP 1065 eq. 14 on the cumulative sum) of x, method 1
        and method 2 agrees with the stored sigma to 1e-9; tau = m / rate, count = N + 1 - 2m,
        ci_low <= sigma <= ci_high;
      * the noise-term table has the rows Q, N, B, K, R, whose values and standard errors are
        finite and >= 0.
Exit code 0 when every check passes, 1 otherwise (each failure printed).
"""
import json
import os
import re
import sys

import h5py
import numpy as np

SCHEMA_PATH = os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "schemas",
                           "results-v2.json")
UNITS_TO_RAD_S = {"rad/s": 1.0, "deg/s": np.pi / 180.0, "deg/h": np.pi / 180.0 / 3600.0}
FLOAT32_UNIT_ROUNDOFF = 2.0 ** -24  # IEEE binary32 round to nearest: |error| <= 2^-24 |value|
# The signal-length datasets of an axis that check_numbers reads in full anyway: the layout check
# leaves them to it, so each is read (and its chunks inflated) once; read_deferred reads those
# the numbers did not get to.
LARGE_DATASETS = ("decomposition/imfs", "decomposition/residue", "kalman/filtered",
                  "signals/method1", "signals/method2")
failures = []
deferred = set()  # full paths of large datasets not read yet


def fail(path, message):
    failures.append(f"{path}: {message}")


def read_full(dataset):
    """dataset[()], the one full read of a large dataset."""
    deferred.discard(dataset.name)
    return dataset[()]


def read_deferred(f):
    while deferred:
        f[deferred.pop()][()]


def text(value):
    if isinstance(value, np.ndarray) and value.shape == ():
        value = value[()]
    return value.decode() if isinstance(value, bytes) else str(value)


# ---- Layout against the schema ----------------------------------------------------------------

def type_matches(kind, wanted):
    wanted = wanted if isinstance(wanted, list) else [wanted]
    classes = {"f": "float", "i": "integer", "u": "integer", "O": "string", "S": "string",
               "U": "string", "V": "compound"}
    have = classes.get(kind, "other")
    return have in wanted or ("number" in wanted and have in ("float", "integer"))


def rank_matches(rank, wanted):
    return rank in (wanted if isinstance(wanted, list) else [wanted])


def check_attributes(where, obj, rules):
    for name, rule in rules.items():
        if name not in obj.attrs:
            if rule.get("required", False):
                fail(where, f"required attribute '{name}' is missing")
            continue
        value = obj.attrs[name]
        array = np.asarray(value)
        kind = "O" if isinstance(value, (str, bytes)) else array.dtype.kind
        if "type" in rule and not type_matches(kind, rule["type"]):
            fail(where, f"attribute '{name}' has type {array.dtype}, schema wants {rule['type']}")
        if "rank" in rule and not rank_matches(array.ndim, rule["rank"]):
            fail(where, f"attribute '{name}' has rank {array.ndim}, schema wants {rule['rank']}")
        values = [text(v) if kind in "OSU" else v for v in np.atleast_1d(array)]
        if "enum" in rule and any(v not in rule["enum"] for v in values):
            fail(where, f"attribute '{name}' = {values} is not one of {rule['enum']}")
        if "pattern" in rule and any(not re.fullmatch(rule["pattern"], v) for v in values):
            fail(where, f"attribute '{name}' = {values} does not match {rule['pattern']}")
        if "minimum" in rule and any(v < rule["minimum"] for v in values):
            fail(where, f"attribute '{name}' = {values} < {rule['minimum']}")
        if "exclusive_minimum" in rule and any(not v > rule["exclusive_minimum"] for v in values):
            fail(where, f"attribute '{name}' = {values} <= {rule['exclusive_minimum']}")
        if rule.get("finite", False) and not np.all(np.isfinite(np.asarray(values, float))):
            fail(where, f"attribute '{name}' = {values} is not finite")


def check_dataset(where, dataset, rule):
    # Read in full (every chunk is inflated), now or, for the large ones, by check_numbers.
    if dataset.name.startswith("/axes/") and dataset.name.split("/", 3)[-1] in LARGE_DATASETS:
        deferred.add(dataset.name)
    else:
        dataset[()]
    if not type_matches(dataset.dtype.kind, rule.get("type", ["float", "integer", "string"])):
        fail(where, f"type {dataset.dtype}, schema wants {rule.get('type')}")
    if "rank" in rule and not rank_matches(dataset.ndim, rule["rank"]):
        fail(where, f"rank {dataset.ndim}, schema wants {rule['rank']}")
    for name, field in rule.get("fields", {}).items():
        names = dataset.dtype.names or ()
        if name not in names:
            if field.get("required", True):
                fail(where, f"table has no field '{name}'")
            continue
        kind = h5py.check_string_dtype(dataset.dtype[name]) and "O" or dataset.dtype[name].kind
        if "type" in field and not type_matches(kind, field["type"]):
            fail(where, f"field '{name}' has type {dataset.dtype[name]}, schema wants "
                        f"{field['type']}")
    units = rule.get("units", False)
    if units is not False:
        have = text(dataset.attrs["units"]) if "units" in dataset.attrs else None
        if have is None:
            fail(where, "no units attribute")
        elif isinstance(units, list) and have not in units:
            fail(where, f"units '{have}', schema allows {units}")
    check_attributes(where, dataset, rule.get("attributes", {}))


def match_rule(rules, name):
    if name in rules:
        return rules[name]
    for key, rule in rules.items():
        if key.startswith("<") and key.endswith(">"):
            return rule
    return None


def check_group(where, group, rule, every_numeric_has_units):
    check_attributes(where or "/", group, rule.get("attributes", {}))
    groups, datasets = rule.get("groups", {}), rule.get("datasets", {})
    for name, child in group.items():
        path = f"{where}/{name}"
        if isinstance(child, h5py.Group):
            sub = match_rule(groups, name)
            if sub is None:
                fail(path, "group not described by the schema")
            else:
                check_group(path, child, sub, every_numeric_has_units)
        else:
            sub = match_rule(datasets, name)
            if sub is None:
                fail(path, "dataset not described by the schema")
                child[()]
            else:
                check_dataset(path, child, sub)
            if every_numeric_has_units and child.dtype.kind in "fiu" and \
                    "units" not in child.attrs:
                fail(path, "numeric dataset without a units attribute")
    for table in (groups, datasets):
        for name, sub in table.items():
            if name.startswith("<"):
                count = sum(1 for n, c in group.items()
                            if isinstance(c, h5py.Group) == (table is groups))
                if count < sub.get("min_count", 0):
                    fail(where or "/", f"needs at least {sub['min_count']} {name}")
            elif sub.get("required", False) and name not in group:
                fail(where or "/", f"required {'group' if table is groups else 'dataset'} "
                                   f"'{name}' is missing")


# ---- Shapes -------------------------------------------------------------------------------------

def check_shapes(where, g):
    n = int(g.attrs["samples"])
    dec = g["decomposition"]
    k = int(dec.attrs["num_imfs"])
    c = k + 1
    want = {"decomposition/imfs": (n, k), "decomposition/residue": (n,),
            "kalman/filtered": (n, c), "signals/method1": (n,), "signals/method2": (n,),
            "preprocessing/dropped_samples": (1,), "preprocessing/window_samples": (1,),
            "preprocessing/mean_removed": ()}
    for name in ("sifts", "stop_reason", "mean_period_samples", "energy"):
        want[f"decomposition/{name}"] = (k,)
    for table, rows in (("models", c), ("kalman", c), ("signals/method2_model", 1),
                        ("signals/method2_kalman", 1)):
        for name, d in g[table].items():
            if isinstance(d, h5py.Dataset) and name != "filtered":
                if d.ndim not in (1, 2) or d.shape[0] != rows:
                    fail(f"{where}/{table}/{name}", f"shape {d.shape}, wants {rows} rows")
    for name, shape in want.items():
        if name in g and g[name].shape != shape:
            fail(f"{where}/{name}", f"shape {g[name].shape}, wants {shape}")
    pre = g["preprocessing"]
    if pre["window_mean"].shape != pre["window_variance"].shape:
        fail(f"{where}/preprocessing", "window_mean and window_variance differ in length")
    for signal in ("raw", "method1", "method2"):
        a = g[f"allan/{signal}"]
        table = a["table"]
        if table.ndim != 1 or table.shape[0] < 1:
            fail(f"{where}/allan/{signal}", f"table of shape {table.shape}")
        units = [text(u) for u in table.attrs["field_units"]]
        if len(units) != len(table.dtype.names):
            fail(f"{where}/allan/{signal}/table", f"{len(units)} field_units for "
                                                  f"{len(table.dtype.names)} fields")
    return n, k


# ---- Numbers ------------------------------------------------------------------------------------

def oadev_from_cumsum(y, rate_hz, m_values):
    """Overlapping Allan deviation from phase = cumulative sum (NIST SP 1065 eq. 14)."""
    tau0 = 1.0 / rate_hz
    phase = np.concatenate([[0.0], np.cumsum(y - np.mean(y), dtype=np.float64)]) * tau0
    n = phase.size
    out = []
    for m in m_values:
        d = phase[2 * m:] - 2.0 * phase[m:n - m] + phase[:n - 2 * m]
        tau = m * tau0
        out.append(np.sqrt(np.sum(d * d) / (2.0 * tau * tau * d.size)))
    return np.array(out)


def rebuild_signal(recording, column, axis_group):
    """The kept signal before and after mean removal."""
    with h5py.File(recording, "r") as r:
        rate = r["rate"]
        units = text(rate.attrs["units"])
        x = rate[:, column] if rate.ndim == 2 else rate[:]
    x = np.asarray(x, dtype=np.float64) * UNITS_TO_RAD_S[units]
    pre = axis_group["preprocessing"]
    drop = int(pre["dropped_samples"][0])
    # NaN bridging (the reader's linear interpolation) is not redone here: test recordings have no
    # NaN, and a NaN left over makes every comparison below fail loudly.
    x = x[drop:].copy()
    original = x.copy()
    for index in pre["outlier_indices"][:]:
        k = int(index) - drop
        lo, hi = max(0, k - 5), min(x.size, k + 6)
        x[k] = np.median(original[lo:hi])
    return x, x - np.mean(x)


def zero_crossings(y):
    s = np.sign(y)
    s = s[s != 0]
    return int(np.count_nonzero(s[1:] != s[:-1]))


UNIT_ROUNDOFF = 2.0 ** -53  # IEEE binary64


def ljung_box(e, lag):
    """Ljung & Box (1978): Q = n (n + 2) sum_k r_k^2 / (n - k), r_k from the centred residuals;
    also sum_k |r_k| (n + 2) n / (n - k), which scales the effect of a perturbation of e on Q."""
    e = e - np.mean(e)
    n = e.size
    c0 = np.dot(e, e)
    r = np.array([np.dot(e[:-k], e[k:]) / c0 for k in range(1, lag + 1)])
    weights = n * (n + 2.0) / (n - np.arange(1, lag + 1))
    return float(np.sum(weights * r * r)), float(np.sum(weights * np.abs(r)))


def close(a, b, rel, scale=None):
    a, b = np.asarray(a, float), np.asarray(b, float)
    s = np.maximum(np.abs(b), 1e-300) if scale is None else scale
    return bool(np.all(np.abs(a - b) <= rel * s))


def check_component_model(where, y, table, row):
    """AR diagnostics of component y recomputed from the stored coefficients. Returns False when
    the residuals are too ill-conditioned to compare (see below), True when compared."""
    p = int(table["order"][row])
    phi = table["coefficients"][row, :p]
    mean = float(table["mean"][row])
    scale = max(float(np.max(np.abs(y))), 1e-300)
    if not close(mean, np.mean(y), 1e-12, scale):
        fail(where, f"AR mean {mean:.6g} != numpy mean {np.mean(y):.6g}")
    z = y - mean
    e = z[p:].copy()
    bound = np.abs(z[p:])
    for i in range(1, p + 1):
        e -= phi[i - 1] * z[p - i:y.size - i]
        bound += abs(phi[i - 1]) * np.abs(z[p - i:y.size - i])
    # Rounding of e_t = z_t - sum phi_i z_{t-i} in any order: |de_t| <= (p + 2) u (|z_t| +
    # sum |phi_i| |z_{t-i}|) (Higham 2002, ch. 3; +1 for z = y - mean). A component the model
    # fits to 100.00 % has |e| ~ 1e-9 |z|, so this relative perturbation eps = ||de|| / ||e|| of
    # the residuals can reach 1e-3: fogpipe's and numpy's residuals then legitimately differ in
    # their leading digits, and such a component is not compared.
    err = float(np.dot(e, e))
    eps = (p + 2) * UNIT_ROUNDOFF * float(np.linalg.norm(bound)) / max(np.sqrt(err), 1e-300)
    if not eps <= 1e-6:
        return False
    tail = y[p:]
    centred = float(np.sum((tail - np.mean(tail)) ** 2))
    fit = 100.0 * (1.0 - np.sqrt(err / centred))
    # E = ||e||^2 moves by <= (2 eps + eps^2) E, sqrt(E / C) by <= eps relative; 1e-10 covers the
    # summation order of N terms (N u ~ 1e-10 for N ~ 1e6).
    if not close(1.0 - table["fit_one_step_percent"][row] / 100.0, 1.0 - fit / 100.0,
                 eps + 1e-10):
        fail(where, f"fit_one_step_percent {table['fit_one_step_percent'][row]:.12g} != "
                    f"numpy {fit:.12g}")
    if not close(table["residual_variance"][row], err / e.size, 3 * eps + 1e-10):
        fail(where, f"residual_variance {table['residual_variance'][row]:.9g} != "
                    f"numpy {err / e.size:.9g}")
    for lag in (10, 20):
        q, sensitivity = ljung_box(e, lag)
        # |dr_k| <= 4 eps (numerator and c0 both perturbed), so |dQ| <= 8 eps sum w_k |r_k|.
        tolerance = 8 * eps * sensitivity + 1e-9 * q + 1e-12
        if not abs(table[f"ljung_box_q{lag}"][row] - q) <= tolerance:
            fail(where, f"ljung_box_q{lag} {table[f'ljung_box_q{lag}'][row]:.9g} != numpy {q:.9g}"
                        f" (tolerance {tolerance:.3g})")
    return True


def check_numbers(path, f, axis_name, g, n, k):
    where = f"{path}: /axes/{axis_name}"
    recording = text(f["provenance"].attrs["input_path"])
    kept, x = rebuild_signal(recording, int(g.attrs["column"]), g)
    if x.size != n:
        fail(where, f"{n} samples stored, {x.size} rebuilt from {recording}")
        return
    scale = max(float(np.max(np.abs(x))), 1e-300)
    rate_hz = float(g.attrs["sample_rate_hz"])
    checked = []

    pre = g["preprocessing"]
    w = int(pre["window_samples"][0])
    windows = kept[:(kept.size // w) * w].reshape(-1, w)
    if not (close(pre["window_mean"][:], windows.mean(axis=1), 1e-12, scale) and
            close(pre["window_variance"][:], windows.var(axis=1), 1e-9)):
        fail(where, "stationarity windows differ from numpy's")
    if not close(pre["mean_removed"][()], np.mean(kept), 1e-12, scale):
        fail(where, "mean_removed differs from numpy's mean")
    checked.append("preprocessing")

    dec = g["decomposition"]
    storage = text(dec.attrs["storage"])
    if storage == "none":
        if "imfs" in dec or "residue" in dec:
            fail(where, "storage none but IMFs are stored")
    elif "imfs" not in dec or "residue" not in dec:
        fail(where, f"storage {storage} but imfs/residue are missing")
    else:
        imfs = dec["imfs"]
        if imfs.dtype != (np.float32 if storage == "float32" else np.float64) or \
                dec["residue"].dtype != imfs.dtype:
            fail(where, f"storage {storage} but IMFs are {imfs.dtype}")
        columns = read_full(imfs).astype(np.float64)
        residue = read_full(dec["residue"]).astype(np.float64)
        total = np.sum(columns, axis=1) + residue
        if storage == "float64":
            bound = 1e-12 * scale
        else:
            # Each stored value is within 2^-24 of the exact one; summing K + 1 of them in
            # float64 adds nothing comparable.
            bound = FLOAT32_UNIT_ROUNDOFF * (np.sum(np.abs(columns), axis=1) + np.abs(residue)) \
                + 1e-12 * scale
        err = np.abs(total - x)
        if not np.all(err <= bound):
            fail(where, f"sum of IMFs + residue differs from the signal by {np.max(err):.3g}")
        checked.append(f"sum(IMFs)+residue ({storage})")
        rel = 1e-12 if storage == "float64" else 4 * FLOAT32_UNIT_ROUNDOFF
        energy = np.mean(columns ** 2, axis=0)
        if not close(dec["energy"][:], energy, rel):
            fail(where, "IMF energies differ from numpy's mean squares")
        for j in range(k):
            zc = zero_crossings(columns[:, j])
            if zc > 0 and not close(dec["mean_period_samples"][j], 2.0 * n / zc, 1e-12):
                fail(where, f"imf{j + 1} mean period {dec['mean_period_samples'][j]} != "
                            f"2N/crossings {2.0 * n / zc}")
        checked.append("energies, mean periods")
        if storage == "float64":
            models = g["models"]
            compared = sum(check_component_model(f"{where}/models[{j}]",
                                                 columns[:, j] if j < k else residue, models, j)
                           for j in range(k + 1))
            checked.append(f"AR mean of every component; fit %, residual variance, Ljung-Box Q "
                           f"of the {compared} of {k + 1} well-conditioned ones")
    if check_component_model(f"{where}/signals/method2_model", x, g["signals/method2_model"], 0):
        checked.append("method 2's AR fit %, residual variance, Ljung-Box Q")

    method1 = read_full(g["signals/method1"])
    kal = g["kalman"]
    if "filtered" in kal:
        filtered = read_full(kal["filtered"]).astype(np.float64)
        s = np.sum(filtered, axis=1)
        if filtered.dtype == np.float64 and kal["filtered"].dtype == np.float64:
            bound = 1e-12 * scale
        else:
            bound = FLOAT32_UNIT_ROUNDOFF * np.sum(np.abs(filtered), axis=1) + 1e-12 * scale
        if not np.all(np.abs(s - method1) <= bound):
            fail(where, "method1 differs from the sum of the filtered components")
        checked.append("method1 = sum(filtered)")

    for signal, y in (("raw", x), ("method1", method1), ("method2", read_full(g["signals/method2"]))):
        a = g[f"allan/{signal}"]
        table = a["table"][()]
        m = table["m"]
        ours = oadev_from_cumsum(y, rate_hz, m)
        stored = table["sigma"]
        rel = np.max(np.abs(ours - stored) / np.maximum(stored, 1e-300))
        if not rel <= 1e-9:
            fail(where, f"{signal} Allan deviation differs from numpy's by {rel:.3g} relative")
        if not close(table["tau_s"], m / rate_hz, 1e-15):
            fail(where, f"{signal} tau_s != m / sample_rate_hz")
        if text(a.attrs["deviation"]) == "oadev" and not np.array_equal(table["count"],
                                                                          n + 1 - 2 * m):
            fail(where, f"{signal} count != N + 1 - 2m")
        lo, hi = table["ci_low"], table["ci_high"]
        ok = np.isnan(lo) | ((lo <= stored) & (stored <= hi))
        if not np.all(ok):
            fail(where, f"{signal} sigma outside [ci_low, ci_high]")
        terms = a["noise/terms"][()]
        if [text(t) for t in terms["name"]] != list("QNBKR"):
            fail(where, f"allan/{signal}/noise/terms rows are {list(terms['name'])}")
        for row in terms:
            for name in ("value", "std_error"):
                if not np.isfinite(row[name]) or row[name] < 0:
                    fail(where, f"allan/{signal}/noise/terms {text(row['name'])} {name} = "
                                f"{row[name]}")
    checked.append(f"OADEV of raw, method 1, method 2 = numpy to 1e-9")
    for name in ("fit_one_step_percent", "innovation_variance", "order"):
        if not np.all(np.isfinite(g["models"][name][:])):
            fail(where, f"models/{name} has non-finite values")
    print(f"{where}: checked {'; '.join(checked)}")


def check_file(path, schema):
    with h5py.File(path, "r") as f:
        if text(f.attrs.get("fogpipe_format", "")) != "fogpipe-results-v2":
            fail(path, "root attribute fogpipe_format is not fogpipe-results-v2")
            return
        before = len(failures)
        check_group("", f, schema["root"], schema.get("every_numeric_dataset_has_units", False))
        if len(failures) == before:
            print(f"{path}: every dataset read and checked against {os.path.basename(SCHEMA_PATH)}")
        if len(failures) == before:  # the numbers below rely on the layout
            for axis_name, g in f["axes"].items():
                n, k = check_shapes(f"{path}: /axes/{axis_name}", g)
                if len(failures) == before:
                    check_numbers(path, f, axis_name, g, n, k)
        read_deferred(f)


def main(argv):
    if len(argv) < 2:
        print(__doc__)
        return 2
    with open(SCHEMA_PATH) as fh:
        schema = json.load(fh)
    for path in argv[1:]:
        check_file(path, schema)
    for message in failures:
        print("FAIL", message)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
