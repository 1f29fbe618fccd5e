#!/usr/bin/python3
"""Static HTML report of a `fogpipe run` campaign: one overview page and one page per recording.

    /usr/bin/python3 scripts/campaign_report.py OUTDIR [-o REPORT_DIR] [--table CAMPAIGN.h5]

OUTDIR is the results folder of `fogpipe run` (its *.fogpipe.h5 files and status.jsonl). The
overview is built from the campaign table of `fogpipe merge` (OUTDIR/campaign.h5 by default; run
`fogpipe merge OUTDIR` first), so it shows exactly the rows, flags and messages that table holds:
every recording and axis with its raw noise terms, standard errors, unreliable terms with their
reasons, data warnings, and the failed or missing recordings with their messages. Below it, the
raw Allan deviations of every recording overlaid. Each recording's page has, per axis, Table 5
(every signal's terms, unreliable ones marked with their reason), the Allan deviations of raw,
method 1, method 2 and the reference filters with the raw 68 % interval band and the noise type
identified at each tau, the signals over time, their power spectral densities and the IMFs.

Writes REPORT_DIR (default OUTDIR/report): index.html, overview_allan.png, and
recordings/<results file stem>/{index.html, *.png}. Needs Debian's python3-numpy, python3-h5py and
python3-matplotlib only. Rates are shown in deg/h (the results files store rad/s); every axis and
table header names its unit. The pages carry no script from elsewhere; a short inline script
counts the images that loaded (body data-images-loaded / data-images-total), for tests.
"""
import argparse
import html
import json
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

RAD_S_TO_DEG_H = 180.0 / np.pi * 3600.0
TERMS = ["Q", "N", "B", "K", "R"]
# Noise type per tau (Riley & Greenhall): alpha of S_y(f) ~ f^alpha.
ALPHA_NAMES = {2: "white PM", 1: "flicker PM", 0: "white FM", -1: "flicker FM", -2: "random-walk FM"}
ALPHA_MARKERS = {2: "v", 1: "<", 0: "o", -1: "s", -2: "^"}
SIGNAL_LABELS = {"raw": "raw", "method1": "method 1", "method2": "method 2"}
MAX_PLOT_POINTS = 20000

LOAD_SCRIPT = """<script>
window.addEventListener("load", function () {
  var images = document.images, loaded = 0;
  for (var i = 0; i < images.length; i++) if (images[i].complete && images[i].naturalWidth > 0) loaded++;
  document.body.setAttribute("data-images-loaded", loaded);
  document.body.setAttribute("data-images-total", images.length);
});
</script>"""

STYLE = """<style>
body { font-family: sans-serif; margin: 1.5em; }
table { border-collapse: collapse; font-size: 0.85em; margin-bottom: 1em; }
th, td { border: 1px solid #bbb; padding: 2px 6px; text-align: right; }
th { background: #eee; } td.text { text-align: left; max-width: 40em; }
tr.failed td, tr.missing td { background: #fdd; } tr.warning td { background: #ffd; }
span.unreliable { color: #b00; font-weight: bold; }
img { max-width: 100%; border: 1px solid #ddd; margin: 0.3em 0; }
</style>"""


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def number(value, digits=3):
    value = float(value)
    return "" if not np.isfinite(value) else f"{value:.{digits}g}"


def page(title, body):
    return ("<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" + html.escape(title) +
            "</title>" + STYLE + "</head>\n<body>\n" + body + "\n" + LOAD_SCRIPT +
            "\n</body></html>\n")


def write_text_atomic(path, content):
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(content)
    os.replace(tmp, path)


def save(fig, path):
    fig.tight_layout()
    fig.savefig(path + ".tmp.png", dpi=90)
    plt.close(fig)
    os.replace(path + ".tmp.png", path)


def read_table(path):
    """The campaign table of `fogpipe merge`: {column: list}, with each column's units."""
    columns, units = {}, {}
    with h5py.File(path, "r") as f:
        g = f["campaign"]
        for name, d in g.items():
            values = d[()]
            columns[name] = [text(v) for v in values] if d.dtype.kind in "OS" else list(values)
            units[name] = text(d.attrs.get("units", ""))
    return columns, units


def stem(results_file):
    return results_file[:-len(".fogpipe.h5")] if results_file.endswith(".fogpipe.h5") \
        else os.path.splitext(results_file)[0]


def allan_curves(axis_group):
    """{signal: (tau_s, sigma_deg_h, ci_low, ci_high, alpha)} for every Allan table present."""
    out = {}
    for name, g in axis_group["allan"].items():
        if "table" not in g:
            continue
        t = g["table"][()]  # one row per tau (schemas/results-v2.md)
        out[name] = (t["tau_s"], t["sigma"] * RAD_S_TO_DEG_H, t["ci_low"] * RAD_S_TO_DEG_H,
                     t["ci_high"] * RAD_S_TO_DEG_H, t["alpha"])
    return out


def signal_order(axis_group):
    names = ["raw", "method1", "method2"]
    ref = axis_group["signals/reference"] if "signals/reference" in axis_group else None
    if ref is not None and "names" in ref.attrs:
        names += [text(n) for n in ref.attrs["names"]]
    return [n for n in names if n in axis_group["allan"]]


def overview_figure(rows, outdir, path):
    fig, ax = plt.subplots(figsize=(9, 5.5))
    drawn = 0
    for results_file, axis in rows:
        try:
            with h5py.File(os.path.join(outdir, results_file), "r") as f:
                tau, sigma, _, _, _ = allan_curves(f["axes"][axis])["raw"]
        except (OSError, KeyError):
            continue
        ax.loglog(tau, sigma, "-", lw=1, label=f"{stem(results_file)} / {axis}")
        drawn += 1
    ax.set_xlabel("tau [s]")
    ax.set_ylabel("raw overlapping Allan deviation [deg/h]")
    ax.set_title(f"Every recording's raw Allan deviation ({drawn} axes)")
    ax.grid(True, which="both", alpha=0.3)
    if 0 < drawn <= 20:
        ax.legend(fontsize=7)
    save(fig, path)


def allan_figure(curves, order, title, path):
    fig, ax = plt.subplots(figsize=(9, 6))
    tau, sigma, low, high, alpha = curves["raw"]
    ax.fill_between(tau, low, high, color="C0", alpha=0.2, label="raw, 68 % interval")
    ax.loglog(tau, sigma, "-", color="C0", lw=1.5, label="raw")
    if alpha is not None:
        for a, marker in ALPHA_MARKERS.items():
            at = np.round(alpha) == a
            if np.any(at):
                ax.loglog(tau[at], sigma[at], marker, color="C0", ms=6, mfc="none",
                          label=f"noise type: {ALPHA_NAMES[a]}")
    for i, name in enumerate(n for n in order if n != "raw"):
        t, s, _, _, _ = curves[name]
        ax.loglog(t, s, "-" if name.startswith("method") else "--", color=f"C{i + 1}", lw=1.2,
                  label=SIGNAL_LABELS.get(name, name))
    ax.set_xlabel("tau [s]")
    ax.set_ylabel("overlapping Allan deviation [deg/h]")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    save(fig, path)


def stored_signals(axis_group):
    """{label: rate_deg_h} of the stored signals (raw from the IMFs + residue when stored)."""
    out = {}
    d = axis_group["decomposition"]
    if "imfs" in d and "residue" in d:
        out["raw"] = (d["imfs"][()].sum(axis=1) + d["residue"][()].reshape(-1)) * RAD_S_TO_DEG_H
    for name in ("method1", "method2"):
        if name in axis_group["signals"] and isinstance(axis_group["signals"][name], h5py.Dataset):
            out[SIGNAL_LABELS[name]] = axis_group["signals"][name][()] * RAD_S_TO_DEG_H
    ref = axis_group["signals/reference"] if "signals/reference" in axis_group else None
    if ref is not None:
        for name, g in ref.items():
            if "signal" in g:
                out[name] = g["signal"][()] * RAD_S_TO_DEG_H
    return out


def signals_figure(signals, fs, title, path):
    fig, ax = plt.subplots(figsize=(9, 4.5))
    for i, (name, x) in enumerate(signals.items()):
        step = max(1, len(x) // MAX_PLOT_POINTS)
        t = np.arange(0, len(x), step) / fs
        ax.plot(t, x[::step], lw=0.6 if name == "raw" else 1.0, color=f"C{i}", label=name,
                alpha=0.5 if name == "raw" else 1.0)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("rate, mean removed [deg/h]")
    ax.set_title(title)
    ax.legend(fontsize=7, ncol=3)
    save(fig, path)


def psd(x, fs, segment=4096):
    """One-sided PSD by averaged Hann-windowed periodograms (Welch 1967, 50 % overlap)."""
    n = min(segment, len(x))
    step = n // 2
    window = np.hanning(n)
    scale = fs * np.sum(window ** 2)
    acc, count = np.zeros(n // 2 + 1), 0
    for start in range(0, len(x) - n + 1, step):
        seg = x[start:start + n]
        spectrum = np.fft.rfft((seg - seg.mean()) * window)
        acc += np.abs(spectrum) ** 2
        count += 1
    p = 2.0 * acc / max(count, 1) / scale
    return np.fft.rfftfreq(n, 1.0 / fs)[1:], p[1:]


def psd_figure(signals, fs, title, path):
    fig, ax = plt.subplots(figsize=(9, 4.5))
    for i, (name, x) in enumerate(signals.items()):
        f, p = psd(x, fs)
        ax.loglog(f, np.maximum(p, 1e-300), lw=0.8, color=f"C{i}", label=name)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("PSD [(deg/h)^2/Hz]")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=3)
    save(fig, path)


def imf_figure(axis_group, fs, title, path):
    d = axis_group["decomposition"]
    imfs = d["imfs"][()] * RAD_S_TO_DEG_H
    residue = d["residue"][()].reshape(-1) * RAD_S_TO_DEG_H
    parts = [imfs[:, k] for k in range(imfs.shape[1])] + [residue]
    fig, axes = plt.subplots(len(parts), 1, figsize=(9, 0.9 * len(parts) + 1), sharex=True)
    step = max(1, len(residue) // MAX_PLOT_POINTS)
    t = np.arange(0, len(residue), step) / fs
    for k, (ax, x) in enumerate(zip(np.atleast_1d(axes), parts)):
        ax.plot(t, x[::step], lw=0.5, color="k")
        ax.set_ylabel("residue" if k == len(parts) - 1 else f"imf{k + 1}", fontsize=7)
        ax.tick_params(labelsize=6)
    np.atleast_1d(axes)[-1].set_xlabel("time [s]")
    np.atleast_1d(axes)[0].set_title(title + " (deg/h)")
    save(fig, path)


def noise_terms(axis_group, name):
    """The noise-term table of one signal as {term: row} (allan/<signal>/noise/terms of
    schemas/results-v2.md), or None when the signal has no noise fit."""
    allan = axis_group["allan"]
    if name not in allan or "noise" not in allan[name]:
        return None
    return {text(row["name"]): row for row in allan[name]["noise/terms"][()]}


def table5_html(axis_group, order):
    raw = noise_terms(axis_group, "raw") or {}
    head = "".join(f"<th>{t} [{html.escape(text(raw[t]['units']))}]</th>" if t in raw
                   else f"<th>{t}</th>" for t in TERMS)
    rows = []
    reasons = []
    for name in order:
        terms = noise_terms(axis_group, name)
        cells = []
        for t in TERMS:
            if terms is None or t not in terms:
                cells.append("<td></td>")
                continue
            row = terms[t]
            value, se = number(row["value"]), number(row["std_error"], 2)
            reason = text(row["reason"])
            content = value + (" &plusmn; " + se if se else "")
            if reason:
                content = (f'<span class="unreliable" title="{html.escape(reason)}">{content} '
                           f"(unreliable)</span>")
                reasons.append(f"<li>{html.escape(SIGNAL_LABELS.get(name, name))} {t}: "
                               f"{html.escape(reason)}</li>")
            cells.append(f"<td>{content}</td>")
        rows.append(f'<tr class="signal"><td class="text">{html.escape(SIGNAL_LABELS.get(name, name))}'
                    f"</td>{''.join(cells)}</tr>")
    return (f'<table class="table5"><tr><th>signal</th>{head}</tr>{"".join(rows)}</table>' +
            (f"<details><summary>{len(reasons)} unreliable terms: reasons</summary><ul>"
             f"{''.join(reasons)}</ul></details>" if reasons else ""))


def recording_page(outdir, results_file, report_dir):
    """The page of one recording of the campaign, linked back to the overview."""
    name = stem(results_file)
    write_recording_page(os.path.join(outdir, results_file),
                         os.path.join(report_dir, "recordings", name), "../../index.html")
    return f"recordings/{name}/index.html"


def write_recording_page(results_path, folder, overview_link=None):
    """FOLDER/index.html and its pictures for one results file of `fogpipe run` (also used by
    scripts/report.py for a single results file)."""
    name = stem(os.path.basename(results_path))
    os.makedirs(folder, exist_ok=True)
    parts = [f"<h1>{html.escape(name)}</h1>"]
    if overview_link:
        parts.insert(0, f'<p><a href="{overview_link}">campaign overview</a></p>')
    with h5py.File(results_path, "r") as f:
        prov = f["provenance"].attrs
        parts.append(f"<p>input {html.escape(text(prov.get('input_path', '')))}, fogpipe "
                     f"{html.escape(text(prov.get('fogpipe_version', '')))}</p>")
        for axis, g in f["axes"].items():
            fs = float(g.attrs["sample_rate_hz"])
            order = signal_order(g)
            curves = allan_curves(g)
            parts.append(f'<h2 class="axis">axis {html.escape(axis)}</h2>')
            pre = g["preprocessing"]
            warning = text(pre.attrs.get("repeat_warning", ""))
            if warning:
                parts.append(f'<p class="warning"><b>data warning:</b> {html.escape(warning)}</p>')
            note = text(g["allan/raw"].attrs.get("preprocessing", ""))
            parts.append("<h3>Table 5: noise terms (IEEE Std 952)</h3>" + table5_html(g, order) +
                         f"<p>{html.escape(note)}</p>")
            figures = []
            if "raw" in curves:
                allan_figure(curves, order, f"{name} / {axis}", os.path.join(folder, f"allan_{axis}.png"))
                figures.append((f"allan_{axis}.png", "Allan deviations with the raw 68 % interval and noise types"))
            signals = stored_signals(g)
            if signals:
                signals_figure(signals, fs, f"{name} / {axis}", os.path.join(folder, f"signals_{axis}.png"))
                psd_figure(signals, fs, f"{name} / {axis}", os.path.join(folder, f"psd_{axis}.png"))
                figures += [(f"signals_{axis}.png", "signals over time"),
                            (f"psd_{axis}.png", "power spectral densities")]
            if "imfs" in g["decomposition"]:
                imf_figure(g, fs, f"{name} / {axis}: IMFs", os.path.join(folder, f"imfs_{axis}.png"))
                figures.append((f"imfs_{axis}.png", "IMFs and residue"))
            for file, caption in figures:
                parts.append(f'<figure><img src="{file}" alt="{html.escape(caption)}">'
                             f"<figcaption>{html.escape(caption)}</figcaption></figure>")
    write_text_atomic(os.path.join(folder, "index.html"), page(name, "\n".join(parts)))


def overview_table(columns, units, links):
    def unit(c):
        return f" [{html.escape(units[c])}]" if units.get(c) else ""

    head = ["recording", "axis", "duration" + unit("duration_s")]
    head += [f"raw {t}{unit('raw_' + t)}" for t in TERMS]
    head += ["unreliable raw terms", "data warning", "status", "message"]
    rows = []
    count = len(columns["input_path"])
    for i in range(count):
        results_file = columns["results_file"][i]
        status = columns["status"][i]
        cls = status if status != "ok" else ("warning" if columns["data_warning"][i] else "ok")
        label = html.escape(os.path.basename(columns["input_path"][i]))
        link = links.get(results_file)
        anchor = f'<a href="{link}">{label}</a>' if link else label
        cells = [f'<td class="text">{anchor}</td>',
                 f'<td class="text">{html.escape(columns["axis"][i])}</td>',
                 f"<td>{number(columns['duration_s'][i], 4)}</td>"]
        unreliable = columns["raw_unreliable_terms"][i].split(",")
        for t in TERMS:
            value, se = number(columns[f"raw_{t}"][i]), number(columns[f"raw_{t}_std_error"][i], 2)
            content = value + (f" &plusmn; {se}" if se else "")
            if t in unreliable:
                content = f'<span class="unreliable">{content}</span>'
            cells.append(f"<td>{content}</td>")
        cells += [f'<td class="text" title="{html.escape(columns["raw_unreliable_reasons"][i])}">'
                  f'{html.escape(columns["raw_unreliable_terms"][i])}</td>',
                  f'<td class="text">{html.escape(columns["data_warning"][i])}</td>',
                  f'<td class="text">{html.escape(status)}</td>',
                  f'<td class="text">{html.escape(columns["message"][i])}</td>']
        rows.append(f'<tr class="{cls}">{"".join(cells)}</tr>')
    header = "".join(f"<th>{h}</th>" for h in head)
    return f'<table id="overview"><tr>{header}</tr>\n' + "\n".join(rows) + "</table>"


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("outdir", help="results folder of `fogpipe run`")
    parser.add_argument("-o", "--output", help="report folder (default OUTDIR/report)")
    parser.add_argument("--table", help="campaign table of `fogpipe merge` (default OUTDIR/campaign.h5)")
    args = parser.parse_args(argv)
    table = args.table or os.path.join(args.outdir, "campaign.h5")
    if not os.path.isfile(table):
        print(f"campaign_report: {table}: no campaign table; run `fogpipe merge {args.outdir}` first",
              file=sys.stderr)
        return 2
    report_dir = args.output or os.path.join(args.outdir, "report")
    os.makedirs(report_dir, exist_ok=True)
    columns, units = read_table(table)
    links, problems = {}, []
    for results_file in sorted({r for r in columns["results_file"] if r}):
        try:
            links[results_file] = recording_page(args.outdir, results_file, report_dir)
        except (OSError, KeyError, ValueError) as e:
            problems.append(f"{results_file}: {e}")
    rows = [(r, a) for r, a in zip(columns["results_file"], columns["axis"]) if r and a]
    overview_figure(rows, args.outdir, os.path.join(report_dir, "overview_allan.png"))
    status = columns["status"]
    summary = (f"{len(set(columns['input_path']))} recordings, {len(status)} rows: "
               f"{status.count('ok')} ok, {status.count('failed')} failed, "
               f"{status.count('missing')} missing; "
               f"{sum(1 for w in columns['data_warning'] if w)} with data warnings, "
               f"{sum(1 for u in columns['raw_unreliable_terms'] if u)} with unreliable raw terms")
    body = [f"<h1>fogpipe campaign report</h1><p>results {html.escape(os.path.abspath(args.outdir))}</p>",
            f'<p id="summary">{html.escape(summary)}</p>',
            "<h2>Recordings</h2><p>Raw noise terms (IEEE Std 952) with standard errors; red: "
            "unreliable (hover for the reason; every reason is on the recording's page).</p>",
            overview_table(columns, units, links),
            '<h2>Raw Allan deviations</h2><figure><img src="overview_allan.png" '
            'alt="raw Allan deviations overlaid"></figure>']
    if problems:
        body.append("<h2>Pages not written</h2><ul>" +
                    "".join(f"<li>{html.escape(p)}</li>" for p in problems) + "</ul>")
    write_text_atomic(os.path.join(report_dir, "index.html"), page("fogpipe campaign report", "\n".join(body)))
    print(f"campaign_report: {os.path.join(report_dir, 'index.html')} ({len(links)} recording pages)"
          + (f"; {len(problems)} pages not written" if problems else ""))
    for p in problems:
        print(f"campaign_report: {p}", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
