#!/usr/bin/python3
"""A new user's walkthrough, through the binary: a CSV file and a MATLAB v7.3 file to a campaign
HTML report, rendered in headless Chromium and checked on the rendered page.

Usage: walkthrough_test.py FOGPIPE_BINARY SOURCE_DIR
Steps: `fogpipe import` of a CSV file (time column, three rate columns, a temperature column)
and of a MATLAB v7.3 file (an N x 3 matrix in counts with a scale factor, the sample rate in a
variable); a damaged file beside them; `fogpipe run`, `fogpipe merge`, scripts/campaign_report.py;
then Debian's chromium renders the overview and every recording page (--dump-dom after the load
event), and the checks read the rendered DOM: one overview row per recording and axis with units
in the headers, the damaged file as a failed row naming it, a link per analysed recording, every
image loaded (the page's own count of images with a natural width), Table 5 with a row per signal
on each axis. Exit 77 (skipped) when chromium is not installed: `scripts/install-deps.sh --test`
installs it.
"""
import os
import shutil
import subprocess
import sys
import tempfile
from html.parser import HTMLParser

import numpy as np

import recording_sources  # beside this script

FOGPIPE = sys.argv[1]
SOURCE_DIR = sys.argv[2]
REPORT = os.path.join(SOURCE_DIR, "scripts", "campaign_report.py")
N = 6000  # 10 min at 10 Hz
RATE_HZ = 10.0
failures = []


def check(condition, message):
    print(("ok   " if condition else "FAIL ") + message, flush=True)
    if not condition:
        failures.append(message)


def run(args):
    return subprocess.run([FOGPIPE] + args, capture_output=True, text=True)


def write_sources(folder):
    csv = os.path.join(folder, "chamber_25C.csv")
    temperature = 25.0 + 0.5 * np.sin(np.arange(N) / RATE_HZ / 60.0)
    recording_sources.write_csv(csv, recording_sources.gyro_deg_h(1, N), temperature, RATE_HZ)
    mat = os.path.join(folder, "rate_table.mat")
    # A gyro counting 0.001 deg/h per count; MATLAB's N x 3 matrix is HDF5 [3, N].
    counts = np.round(recording_sources.gyro_deg_h(2, N) / 0.001)
    recording_sources.write_mat(mat, "gyro", counts.T, RATE_HZ)
    return csv, mat


class Dom(HTMLParser):
    """The parts of a rendered page the checks read."""

    def __init__(self):
        super().__init__()
        self.body = {}
        self.tables = []  # [(id, class, [[cells]], [row classes])]
        self.links = []
        self._cell = None
        self._row = None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "body":
            self.body = a
        elif tag == "table":
            self.tables.append((a.get("id", ""), a.get("class", ""), [], []))
        elif tag == "tr" and self.tables:
            self._row = []
            self.tables[-1][2].append(self._row)
            self.tables[-1][3].append(a.get("class", ""))
        elif tag in ("td", "th") and self._row is not None:
            self._cell = []
        elif tag == "a" and "href" in a:
            self.links.append(a["href"])

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None:
            self._row.append("".join(self._cell).strip())
            self._cell = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)


def render(chromium, path):
    r = subprocess.run([chromium, "--headless", "--no-sandbox", "--disable-gpu",
                        "--virtual-time-budget=10000", "--dump-dom", "file://" + path],
                       capture_output=True, text=True, timeout=120)
    dom = Dom()
    dom.feed(r.stdout)
    return dom


def images_loaded(dom):
    loaded = int(dom.body.get("data-images-loaded", "-1"))
    total = int(dom.body.get("data-images-total", "-2"))
    return loaded, total


def main():
    chromium = shutil.which("chromium")
    if chromium is None:
        print("skipped: chromium is not installed (scripts/install-deps.sh --test installs it)")
        return 77
    with tempfile.TemporaryDirectory(prefix="fogpipe_walkthrough_") as tmp:
        sources = os.path.join(tmp, "sources")
        os.makedirs(sources)
        csv, mat = write_sources(sources)
        rec = os.path.join(tmp, "recordings")
        os.makedirs(rec)
        r = run(["import", csv, "-o", os.path.join(rec, "chamber_25C.h5"), "--units", "deg/h",
                 "--time-column", "t", "--rate-columns", "gx,gy,gz",
                 "--aux", "temperature=temp:degC", "--serial", "FOG-17"])
        check(r.returncode == 0, f"import of the CSV ({r.stderr.strip()[-300:]})")
        r = run(["import", mat, "-o", os.path.join(rec, "rate_table.h5"), "--units", "deg/h",
                 "--variable", "gyro", "--sample-rate-variable", "fs", "--scale-factor", "0.001",
                 "--axes", "x,y,z", "--serial", "FOG-18"])
        check(r.returncode == 0, f"import of the MATLAB v7.3 file ({r.stderr.strip()[-300:]})")
        broken = os.path.join(rec, "broken.h5")
        with open(os.path.join(rec, "chamber_25C.h5"), "rb") as f:
            data = f.read()
        with open(broken, "wb") as f:
            f.write(data[: len(data) // 2])  # a copy cut short
        out = os.path.join(tmp, "results")
        r = run(["run", rec, "-o", out, "--threads", "2"])
        check(r.returncode == 1, f"run exits 1 (one file failed): {r.returncode}")
        m = run(["merge", out])
        check(m.returncode == 1 and os.path.isfile(os.path.join(out, "campaign.h5")),
              f"merge writes the campaign table and exits 1 for the failed file ({m.returncode})")
        report = os.path.join(tmp, "report")
        g = subprocess.run(["/usr/bin/python3", REPORT, out, "-o", report], capture_output=True,
                           text=True)
        check(g.returncode == 0, f"campaign_report.py exits 0 ({g.stdout.strip()} {g.stderr.strip()})")

        index = render(chromium, os.path.join(report, "index.html"))
        overview = [t for t in index.tables if t[0] == "overview"]
        check(len(overview) == 1, "the overview table is rendered")
        if not overview:
            return 1
        rows, classes = overview[0][2][1:], overview[0][3][1:]
        header = overview[0][2][0]
        check(any("[deg/sqrt(h)]" in h for h in header) and any("[deg/h]" in h for h in header)
              and "duration [s]" in header, f"the overview's headers carry units: {header}")
        check(len(rows) == 7, f"7 overview rows: 2 recordings x 3 axes + the failed file ({len(rows)})")
        failed = [row for row, c in zip(rows, classes) if c == "failed"]
        check(len(failed) == 1 and "broken.h5" in failed[0][0] and
              any("broken.h5" in cell for cell in failed[0][-1:]),
              f"the damaged file is a failed row whose message names it: {failed}")
        ok_rows = [row for row, c in zip(rows, classes) if c in ("ok", "warning")]
        check(len(ok_rows) == 6 and all(row[4] for row in ok_rows),
              "six analysed axes, each with its raw N")
        pages = sorted(set(link for link in index.links if link.startswith("recordings/")))
        check(len(pages) == 2, f"one page per analysed recording is linked: {pages}")
        loaded, total = images_loaded(index)
        check(total >= 1 and loaded == total, f"the overview's images loaded ({loaded} of {total})")
        for link in pages:
            dom = render(chromium, os.path.join(report, link))
            loaded, total = images_loaded(dom)
            check(total >= 12 and loaded == total,
                  f"{link}: every image loaded, at least 4 per axis ({loaded} of {total})")
            tables = [t for t in dom.tables if t[1] == "table5"]
            check(len(tables) == 3, f"{link}: Table 5 for each of the 3 axes ({len(tables)})")
            for _, _, t_rows, _ in tables:
                signals = [row[0] for row in t_rows[1:]]
                check(signals[:3] == ["raw", "method 1", "method 2"] and len(signals) == 7,
                      f"{link}: Table 5 rows raw, method 1, method 2 and 4 reference filters "
                      f"({signals})")
                check(any("[deg/sqrt(h)]" in h for h in t_rows[0]), f"{link}: Table 5 units")
    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
