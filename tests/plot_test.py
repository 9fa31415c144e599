#!/usr/bin/env python3
"""ctest driver for one plot script (registered in tests/CMakeLists.txt).

Usage: plot_test.py SCRIPT DATA_DIR OUT_DIR FIGURE CONFIG LABEL [extra args...]
Runs SCRIPT on the synthetic result folder DATA_DIR, writing into OUT_DIR, and checks
that FIGURE.png is a PNG and FIGURE.svg an SVG whose text holds the axis label LABEL,
the machine from the manifest and "Regenerate: hrad experiment
experiments/configs/CONFIG.json". Then checks that the script refuses a folder without
runs.csv (non-zero exit, no figure written).
"""
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
for path in (png, svg):
    if not os.path.isfile(path) or os.path.getsize(path) < 1000:
        fail(f"{path} missing or too small")
with open(png, "rb") as f:
    if f.read(8) != b"\x89PNG\r\n\x1a\n":
        fail(f"{png} is not a PNG")
text = open(svg, encoding="utf-8").read()
for needle in ("<svg", label, "synthetic-host",
               f"Regenerate: hrad experiment experiments/configs/{config}.json"):
    if needle not in text:
        fail(f"{svg} lacks {needle!r}")
if extra and "simulated" not in text:
    fail(f"{svg}: the simulated curves are not labelled")

empty = tempfile.mkdtemp()
try:
    r = subprocess.run([sys.executable, script, empty], capture_output=True, text=True)
    if r.returncode == 0 or os.listdir(empty):
        fail(f"{script} accepted a folder without runs.csv")
finally:
    shutil.rmtree(empty)
print(f"plot_test: {figure} ok")
