#!/usr/bin/env python3
"""ctest driver for one plot script (registered in tests/CMakeLists.txt).

Usage: plot_test.py SCRIPT DATA_DIR OUT_DIR FIGURE CONFIG LABEL [extra args...]
Runs SCRIPT on the synthetic result folder DATA_DIR, writing into OUT_DIR, and checks
that FIGURE.png is a PNG, FIGURE.pdf a PDF and FIGURE.svg an SVG whose text holds the
axis label LABEL, and that FIGURE.caption.txt names the machine from the manifest and
says "Regenerate: hrad experiment experiments/configs/CONFIG.json" and "Redraw: python3
plots/SCRIPT DATA_DIR" with the paths as a command run from the repository root reaches
them (the caption is not drawn in the figure, but is with --caption-in-image), that
nothing is drawn beyond the figure's edge, and that --size column gives 3.3 inches. A manifest marked quick puts the quick-run mark in the figure.
Then checks that the script refuses a folder without
runs.csv (non-zero exit, no figure written), and that without matplotlib (hidden by a
stand-in package on PYTHONPATH whose import fails) the script exits non-zero with one
line on stderr naming matplotlib, no traceback and no figure. For numa, a one-node
manifest must get the note saying why every ratio is 1.0; for speedup with
--simulated, the caption's command carries --simulated and the dashed curve's label
says that it is not the measured runs' settings; with --control, the machine's limit
from a scaling check's hardware control is drawn.
"""
import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile


def fail(msg):
    sys.exit(f"plot_test: {msg}")


script, data, out, figure, config, label, *extra = sys.argv[1:]
shutil.rmtree(out, ignore_errors=True)
r = subprocess.run([sys.executable, script, data, "--out-dir", out, *extra],
                   capture_output=True, text=True)
if r.returncode != 0:
    fail(f"{script} failed ({r.returncode}):\n{r.stdout}\n{r.stderr}")

png = os.path.join(out, figure + ".png")
svg = os.path.join(out, figure + ".svg")
pdf = os.path.join(out, figure + ".pdf")
for path in (png, svg, pdf):
    if not os.path.isfile(path) or os.path.getsize(path) < 1000:
        fail(f"{path} missing or too small")
with open(png, "rb") as f:
    if f.read(8) != b"\x89PNG\r\n\x1a\n":
        fail(f"{png} is not a PNG")
with open(pdf, "rb") as f:
    if f.read(5) != b"%PDF-":
        fail(f"{pdf} is not a PDF")
text = open(svg, encoding="utf-8").read()
caption_file = os.path.join(out, figure + ".caption.txt")
caption = open(caption_file, encoding="utf-8").read() if os.path.isfile(caption_file) else ""
for needle in ("synthetic-host", f"Regenerate: hrad experiment experiments/configs/{config}.json"):
    if needle not in caption:
        fail(f"{caption_file} lacks {needle!r}")
    if needle in text:
        fail(f"{svg}: the caption's {needle!r} is drawn in the figure")
for needle in ("<svg", label):
    if needle not in text:
        fail(f"{svg} lacks {needle!r}")
if "quick run" in text:
    fail(f"{svg}: a full run is marked as a quick one")
if "--control" in extra and "machine's limit" not in text:
    fail(f"{svg}: the hardware control's limit is not drawn")
if extra and "simulated" not in text:
    fail(f"{svg}: the simulated curves are not labelled")
if "beyond the figure's edge" in r.stderr:
    fail(f"{script}: {r.stderr.strip()}")
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def as_given(path):
    """The path as the caption writes it: relative to the repository root inside it."""
    full = os.path.abspath(path)
    return os.path.relpath(full, root) if full.startswith(root + os.sep) else full


if f"Redraw: python3 plots/{os.path.basename(script)} {as_given(data)}" not in caption:
    fail(f"{caption_file} lacks the command that redraws the figure:\n{caption}")
if extra and figure == "speedup":
    needle = f"--simulated {as_given(extra[extra.index('--simulated') + 1])}"
    if needle not in caption:
        fail(f"{caption_file} lacks {needle!r}")
    if "not those of the measured" not in text:
        fail(f"{svg}: the simulated curves do not say whose settings they have")

# A column-wide figure (3.3 in) with the caption drawn in it: nothing beyond its edge.
column = tempfile.mkdtemp()
try:
    r = subprocess.run([sys.executable, script, data, "--out-dir", column, "--size", "column",
                        "--caption-in-image", *extra], capture_output=True, text=True)
    if r.returncode != 0 or "beyond the figure's edge" in r.stderr:
        fail(f"{script} --size column --caption-in-image: {r.returncode}\n{r.stderr}")
    svg_text = open(os.path.join(column, figure + ".svg"), encoding="utf-8").read()
    if "synthetic-host" not in svg_text:
        fail(f"{script} --caption-in-image: the caption is not drawn")
    if 'width="237.6pt"' not in svg_text:
        fail(f"{script} --size column: the SVG is not 3.3 in (237.6 pt) wide")
finally:
    shutil.rmtree(column)

# Without matplotlib: one clear line, not a traceback.
hidden = tempfile.mkdtemp()
try:
    os.makedirs(os.path.join(hidden, "stub", "matplotlib"))
    with open(os.path.join(hidden, "stub", "matplotlib", "__init__.py"), "w") as f:
        f.write("raise ImportError(\"No module named 'matplotlib' (hidden by plot_test)\")\n")
    env = dict(os.environ, PYTHONPATH=os.path.join(hidden, "stub"))
    out_dir = os.path.join(hidden, "out")
    r = subprocess.run([sys.executable, script, data, "--out-dir", out_dir, *extra],
                       capture_output=True, text=True, env=env)
    lines = r.stderr.strip().splitlines()
    if r.returncode == 0 or "Traceback" in r.stderr or len(lines) != 1 \
            or "matplotlib" not in lines[0]:
        fail(f"{script} without matplotlib: status {r.returncode}, stderr:\n{r.stderr}")
    if os.path.exists(out_dir) and os.listdir(out_dir):
        fail(f"{script} without matplotlib wrote {os.listdir(out_dir)}")
finally:
    shutil.rmtree(hidden)

# Runs made with --quick: the figure itself says that they are no result.
quick = tempfile.mkdtemp()
try:
    shutil.copytree(data, os.path.join(quick, "data"))
    path = os.path.join(quick, "data", "manifest.json")
    with open(path) as f:
        manifest = json.load(f)
    manifest.setdefault("experiment", {})["quick"] = True
    with open(path, "w") as f:
        json.dump(manifest, f)
    r = subprocess.run([sys.executable, script, os.path.join(quick, "data"), "--out-dir",
                        os.path.join(quick, "out"), *extra], capture_output=True, text=True)
    if r.returncode != 0:
        fail(f"{script} on a quick run failed:\n{r.stderr}")
    if "quick run (--quick)" not in open(os.path.join(quick, "out", figure + ".svg"),
                                         encoding="utf-8").read():
        fail(f"{script}: a quick run's figure is not marked as one")
finally:
    shutil.rmtree(quick)

# numa on a one-node machine: every ratio is 1.0, and the figure says why.
if figure == "numa":
    one = tempfile.mkdtemp()
    try:
        with open(os.path.join(data, "manifest.json")) as f:
            manifest = json.load(f)
        manifest["topology"] = {"numa_nodes": 1}
        with open(os.path.join(one, "manifest.json"), "w") as f:
            json.dump(manifest, f)
        with open(os.path.join(data, "runs.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        for row in rows:
            row["local_access_ratio"] = "1.0"
        with open(os.path.join(one, "runs.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
        r = subprocess.run([sys.executable, script, one], capture_output=True, text=True)
        if r.returncode != 0:
            fail(f"{script} on one node failed:\n{r.stderr}")
        if "one NUMA node" not in open(os.path.join(one, "numa.svg"), encoding="utf-8").read():
            fail(f"{script}: the one-node figure does not say why every ratio is 1.0")
    finally:
        shutil.rmtree(one)

empty = tempfile.mkdtemp()
try:
    r = subprocess.run([sys.executable, script, empty], capture_output=True, text=True)
    if r.returncode == 0 or os.listdir(empty):
        fail(f"{script} accepted a folder without runs.csv")
finally:
    shutil.rmtree(empty)
print(f"plot_test: {figure} ok")
