#!/usr/bin/python3
"""Pictures of one results file: of `fogpipe compare`'s history, or of `fogpipe run`'s results.

    /usr/bin/python3 scripts/report.py RESULTS.h5 -o DIR [--step N]

A file with a /compare history (`fogpipe compare -o`): DIR/allan.png, psd.png, time.png, aux.png,
imf.png and history.png. Each picture shows where the model fails: failing tau ranges, lines, time
windows and aux channels are shaded or marked in red. Layout: schemas/model-history.md.

A results file of `fogpipe run` without that history: DIR/index.html with Table 5 and, per axis,
the Allan deviations of raw, method 1, method 2 and the reference filters with intervals and noise
types, the signals, their spectra and the IMFs (the recording page of scripts/campaign_report.py).

Needs Debian's python3-matplotlib, python3-h5py and numpy only. Any other file: exit 2, naming it.
"""
import argparse
import json
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

RAD_S_TO_DEG_H = 180.0 / np.pi * 3600.0


def load_step(f, step):
    g = f["compare"]
    steps = int(g.attrs["steps"])
    index = steps - 1 if step is None else step
    s = g["step_%03d" % index]
    cj = s["compare_json"][()]
    cj = json.loads(cj.decode() if isinstance(cj, bytes) else cj)
    return index, s, cj


def title(s, cj, what):
    terms = [t.decode() if isinstance(t, bytes) else t for t in s.attrs["terms"]]
    state = "consistent" if cj["consistent"] else "NOT consistent"
    return "%s  |  error %.3g (%s)\nmodel: bias + %s" % (what, cj["error"], state, " + ".join(terms))


def allan_view(s, cj, out):
    a = s["allan"]
    tau = a["tau_s"][()]
    meas = np.sqrt(a["avar_meas"][()]) * RAD_S_TO_DEG_H
    model = np.sqrt(a["avar_model"][()]) * RAD_S_TO_DEG_H
    lo, hi = a["ci_low"][()] * RAD_S_TO_DEG_H, a["ci_high"][()] * RAD_S_TO_DEG_H
    fig, ax = plt.subplots(figsize=(8, 5.5))
    for f in cj["failures"]:
        if f["domain"] == "tau":
            ax.axvspan(f["from"], f["to"], color="red", alpha=0.15)
        if f["domain"] == "frequency":  # where the band shows in the Allan view: 0.371 / f
            fc = f.get("center_hz") or 0.5 * (f["from"] + f["to"])
            t0 = 0.371 / fc
            ax.axvspan(t0 / 1.15, t0 * 1.15, color="orange", alpha=0.35)
    ax.fill_between(tau, lo, hi, color="C0", alpha=0.25, label="measured, 68 % CI")
    ax.loglog(tau, meas, "o-", color="C0", label="measured (residual)")
    ax.loglog(tau, model, "-", color="k", lw=2, label="model")
    for name in a["terms"]:
        v = np.sqrt(np.maximum(a["terms"][name][()], 0)) * RAD_S_TO_DEG_H
        if np.any(v > 0):
            ax.loglog(tau, np.where(v > 0, v, np.nan), "--", lw=1, label=name)
    ax.set_xlabel("tau [s]")
    ax.set_ylabel("Allan deviation [deg/h]")
    ax.set_title(title(s, cj, "Allan view (red: failing tau; orange: a line's tau)"), fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "allan.png"), dpi=110)
    plt.close(fig)


def fitted_bands(s):
    """The step's narrow_band terms (its narrow_bands/ group; none in files without one)."""
    if "narrow_bands" not in s:
        return []
    g = s["narrow_bands"]
    return [{"f0_hz": f0, "width_hz": w, "rms_deg_h": rms * RAD_S_TO_DEG_H}
            for f0, w, rms in zip(g["frequency_hz"][()], g["bandwidth_hz"][()], g["rms_rad_s"][()])]


def psd_view(s, cj, out):
    g = s["frequency"]
    f = g["frequency_hz"][()]
    scale = RAD_S_TO_DEG_H ** 2
    fig, ax = plt.subplots(figsize=(8, 5))
    ax.loglog(f, g["psd"][()] * scale, color="C0", lw=0.8, label="residual PSD (Welch)")
    ax.loglog(f, g["model_psd"][()] * scale, color="k", lw=2, label="model PSD")
    # One failure per band (merged failing bins): shaded, labelled with its centre and peak ratio.
    bands = [fl for fl in cj["failures"] if fl["domain"] == "frequency"]
    for fl in bands:
        ax.axvspan(fl["from"], fl["to"], color="red", alpha=0.3)
    # Labels for the 4 most severe bands, staggered so that neighbours stay legible.
    top = sorted(bands, key=lambda fl: -fl["severity"])[:4]
    for k, fl in enumerate(sorted(top, key=lambda fl: fl["from"])):
        if fl.get("center_hz"):
            ax.annotate("%.3g Hz, %.3gx" % (fl["center_hz"], fl.get("peak_ratio") or 0),
                        (fl["center_hz"], 1.0), xycoords=("data", "axes fraction"),
                        xytext=(0, -3 - 10 * k), textcoords="offset points", va="top",
                        ha="center", fontsize=7, color="red")
    for fl in g["line_frequency_hz"][()]:
        ax.axvline(fl, color="red", ls=":", lw=1)
    # The model's fitted narrow bands (term narrow_band): centre and half-power width, in green.
    fitted = fitted_bands(s)
    for k, b in enumerate(fitted):
        ax.axvspan(b["f0_hz"] - b["width_hz"] / 2, b["f0_hz"] + b["width_hz"] / 2, color="green",
                   alpha=0.25)
        ax.axvline(b["f0_hz"], color="green", lw=1)
        ax.annotate("narrow_band %.4g Hz\nwidth %.3g Hz, rms %.3g deg/h" % (
                        b["f0_hz"], b["width_hz"], b["rms_deg_h"]),
                    (b["f0_hz"], 0.0), xycoords=("data", "axes fraction"),
                    xytext=(-3, 3 + 20 * k), textcoords="offset points", va="bottom", ha="right",
                    fontsize=7, color="green")
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("PSD [(deg/h)^2/Hz]")
    what = "Frequency view (red: %d failing band%s; centre, peak psd/model; green: %d fitted)" % (
        len(bands), "" if len(bands) == 1 else "s", len(fitted))
    ax.set_title(title(s, cj, what), fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "psd.png"), dpi=110)
    plt.close(fig)
    return fitted


def time_view(s, cj, out):
    g = s["time"]
    c = g["center_s"][()] / 3600.0
    fig, (a1, a2, a3) = plt.subplots(3, 1, figsize=(8, 7), sharex=True)
    a1.plot(c, g["mean"][()] * RAD_S_TO_DEG_H, "o-", ms=3)
    a1.set_ylabel("window mean\n[deg/h]")
    a2.plot(c, np.sqrt(g["variance"][()]) * RAD_S_TO_DEG_H, "o-", ms=3, color="C1")
    a2.set_ylabel("window sd\n[deg/h]")
    b = g["boundary_s"][()] / 3600.0
    z = g["z_mean"][()]
    w = g["boundary_window_s"][()]
    for win in np.unique(w):
        m = w == win
        a3.plot(b[m], z[m], ".-", ms=2, lw=0.8, label="window %.0f s" % win)
    crit = g.attrs["critical"]
    a3.axhline(crit, color="red", ls="--", lw=1)
    a3.axhline(-crit, color="red", ls="--", lw=1)
    a3.set_ylabel("jump z")
    a3.legend(fontsize=6, ncol=4)
    for ax in (a1, a2, a3):
        for fl in cj["failures"]:
            if fl["domain"] == "time":
                ax.axvspan(fl["from"] / 3600.0, fl["to"] / 3600.0, color="red", alpha=0.15)
        for cp in g["change_point_s"][()]:
            ax.axvline(cp / 3600.0, color="red", lw=1)
        ax.grid(True, alpha=0.3)
    a3.set_xlabel("time [h]")
    a1.set_title(title(s, cj, "Time view (red: failing windows, change points)"), fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "time.png"), dpi=110)
    plt.close(fig)


def aux_view(s, cj, out):
    g = s["aux"]
    names = [n for n in g.keys() if isinstance(g[n], h5py.Group)]
    if not names:
        return
    t = g["block_center_s"][()] / 3600.0
    r = g["residual_lowpass"][()] * RAD_S_TO_DEG_H
    failing = {fl["channel"] for fl in cj["failures"] if fl["domain"] == "aux"}
    fig, axes = plt.subplots(len(names), 1, figsize=(8, 3.2 * len(names)), squeeze=False)
    for ax, name in zip(axes[:, 0], names):
        ch = g[name]
        ax.plot(t, r, color="C0", lw=0.8, label="low-frequency residual [deg/h]")
        ax.set_ylabel("residual [deg/h]")
        ax2 = ax.twinx()
        bad = name in failing or ("d(%s)/dt" % name) in failing
        ax2.plot(t[: len(ch["lowpass"])], ch["lowpass"][()], color="red" if bad else "C1", lw=1.5)
        ax2.set_ylabel("%s [%s]" % (name, ch["lowpass"].attrs.get("units", "")))
        ax.set_title("%s: r = %.2f (z %.1f), with d/dt: r = %.2f (z %.1f), critical |z| %.2f%s" % (
            name, ch.attrs["r"], ch.attrs["z"], ch.attrs["r_derivative"], ch.attrs["z_derivative"],
            g.attrs["critical"], "  FAILS" if bad else ""), fontsize=9)
        ax.set_xlabel("time [h]")
    fig.suptitle(title(s, cj, "Aux view"), fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "aux.png"), dpi=110)
    plt.close(fig)


def imf_view(s, cj, out):
    """Which IMFs of the residual carry the misfit: energy against the fitted noise model (the
    white-noise dyadic law for a white model), AR fit and aux correlation; flagged IMFs in red."""
    if "imf" not in s or "energy" not in s["imf"]:
        return
    g = s["imf"]
    period = g["mean_period_s"][()]
    if len(period) == 0:
        return
    scale = RAD_S_TO_DEG_H ** 2
    energy = g["energy"][()] * scale
    expected = g["expected_energy"][()] * scale
    log_sd = g["log_sd"][()]
    flagged = g["flagged"][()].astype(bool)
    scored = g["scored"][()].astype(bool)
    crit = g.attrs["critical"]
    k = np.arange(1, len(period) + 1)
    aux = g["aux"] if "aux" in g else {}
    names = list(aux.keys())
    fig, (a1, a2, a3) = plt.subplots(3, 1, figsize=(8, 9.5),
                                     gridspec_kw={"height_ratios": [2.2, 1, 1.2]})
    ok = np.isfinite(expected)
    a1.fill_between(period[ok], expected[ok] * np.exp(-crit * log_sd[ok]),
                    expected[ok] * np.exp(crit * log_sd[ok]), color="0.8",
                    label="model band (critical z %.2f)" % crit)
    a1.loglog(period[ok], expected[ok], "k-", lw=2, label="expected under the fitted noise model")
    a1.loglog(period[~flagged], energy[~flagged], "o", color="C0", label="IMF energy")
    a1.loglog(period[flagged], energy[flagged], "o", color="red", ms=9,
              label="IMF energy: carries misfit")
    a1.loglog(period[~scored], energy[~scored], "x", color="0.4", ms=8,
              label="not scored (no model IMF there, or < 3 cycles)")
    for i in range(len(period)):
        a1.annotate("%d" % k[i], (period[i], energy[i]), textcoords="offset points",
                    xytext=(4, 4), fontsize=7)
    a1.set_xlabel("IMF mean period [s]")
    a1.set_ylabel("energy (mean square) [(deg/h)^2]")
    a1.grid(True, which="both", alpha=0.3)
    a1.legend(fontsize=7)
    colors = np.where(flagged, "red", "C0")
    a2.bar(k, g["ar_fit_percent"][()], color=colors)
    a2.set_ylabel("AR one-step fit [%]")
    a2.set_xticks(k)
    a2.grid(True, axis="y", alpha=0.3)
    width = 0.8 / max(1, 2 * len(names))
    for c, name in enumerate(names):
        a3.bar(k + (2 * c - len(names) + 0.5) * width, aux[name]["r"][()], width,
               color="C%d" % (1 + 2 * c), label="r with %s" % name)
        a3.bar(k + (2 * c + 1 - len(names) + 0.5) * width, aux[name]["r_derivative"][()], width,
               color="C%d" % (2 + 2 * c), label="r with d(%s)/dt" % name)
    for i in np.nonzero(flagged)[0]:
        for ax in (a2, a3):
            ax.axvspan(k[i] - 0.5, k[i] + 0.5, color="red", alpha=0.12)
    a3.axhline(0, color="k", lw=0.8)
    a3.set_ylim(-1, 1)
    a3.set_xticks(k)
    a3.set_xlabel("IMF (1 = highest frequency)")
    a3.set_ylabel("correlation r")
    a3.grid(True, axis="y", alpha=0.3)
    if names:
        a3.legend(fontsize=7, ncol=2)
    a1.set_title(title(s, cj, "IMF view (red: IMFs that carry misfit)"), fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "imf.png"), dpi=110)
    plt.close(fig)


def history_view(f, out):
    g = f["compare"]
    steps = int(g.attrs["steps"])
    err, labels = [], []
    for i in range(steps):
        s = g["step_%03d" % i]
        err.append(s.attrs["error"])
        terms = [t.decode() if isinstance(t, bytes) else t for t in s.attrs["terms"]]
        labels.append(terms[-1] if i > 0 else "default")
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.semilogy(range(steps), err, "o-", lw=2)
    ax.axhline(1.0, color="green", ls="--", label="consistent below 1")
    ax.set_xticks(range(steps))
    ax.set_xticklabels(["%d: +%s" % (i, l) if i else "0: default" for i, l in enumerate(labels)],
                       fontsize=8, rotation=15)
    ax.set_ylabel("error")
    ax.set_title("Model history: how the error fell")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "history.png"), dpi=110)
    plt.close(fig)


def kind_of(path):
    """'compare', 'run' or an explanation of why the file has no pictures here."""
    try:
        with h5py.File(path, "r") as f:
            if "compare" in f:
                return "compare"
            tag = f.attrs.get("fogpipe_format", b"")
            tag = tag.decode() if isinstance(tag, bytes) else str(tag)
            if tag == "fogpipe-results-v2":
                return "run"
            if tag == "fogpipe-results-v1":
                return ("a results file of the previous layout (fogpipe-results-v1); rerun "
                        "`fogpipe run` on its recording to rewrite it")
            return (f"neither a results file of `fogpipe run` nor one with a `fogpipe compare` "
                    f"history (fogpipe_format '{tag}')")
    except OSError as e:
        return f"cannot be read as HDF5 ({e})"


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("results")
    p.add_argument("-o", "--output", required=True)
    p.add_argument("--step", type=int, default=None,
                   help="history step of a compare file (default: the last)")
    a = p.parse_args()
    kind = kind_of(a.results)
    if kind not in ("compare", "run"):
        print(f"report.py: {a.results}: {kind}", file=sys.stderr)
        return 2
    os.makedirs(a.output, exist_ok=True)
    if kind == "run":
        if a.step is not None:
            print(f"report.py: {a.results}: --step needs a `fogpipe compare` history; this "
                  "file has none", file=sys.stderr)
            return 2
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        import campaign_report  # noqa: E402  (beside this script, in the source tree and installed)
        campaign_report.write_recording_page(a.results, a.output)
        print(f"report.py: {os.path.join(a.output, 'index.html')}")
        return 0
    with h5py.File(a.results, "r") as f:
        _, s, cj = load_step(f, a.step)
        allan_view(s, cj, a.output)
        for b in psd_view(s, cj, a.output):
            print("report.py: psd.png marks narrow_band %.4g Hz (width %.3g Hz, rms %.3g deg/h)" % (
                b["f0_hz"], b["width_hz"], b["rms_deg_h"]))
        time_view(s, cj, a.output)
        aux_view(s, cj, a.output)
        imf_view(s, cj, a.output)
        history_view(f, a.output)
    return 0


if __name__ == "__main__":
    sys.exit(main())
