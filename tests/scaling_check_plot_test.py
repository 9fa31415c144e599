#!/usr/bin/env python3
"""ctest driver for plots/scaling_check.py (registered in tests/CMakeLists.txt).

Usage: scaling_check_plot_test.py SCRIPT CSV OUT_PNG
Runs SCRIPT on a synthetic scaling.csv (tests/data/plots/scaling-check/) and checks the
PNG, PDF, SVG and caption beside it (which names the rows' revision and host) and the
printed table: the control's efficiency (median of 4 runs at once, 3.1 s,
against 3.0 s alone: 0.968), each scheduler's speed-up (blocked at 4 threads: 3.0 / 0.8 =
3.75), the fixed blocks and the cabin.
"""
import os
import subprocess
import sys

script, csv_path, png = sys.argv[1:4]
if os.path.exists(png):
    os.remove(png)
r = subprocess.run([sys.executable, script, csv_path, "--out", png], capture_output=True,
                   text=True)
if r.returncode != 0:
    sys.exit(f"scaling_check_plot_test: {script} failed:\n{r.stdout}\n{r.stderr}")
with open(png, "rb") as f:
    if f.read(8) != b"\x89PNG\r\n\x1a\n":
        sys.exit(f"scaling_check_plot_test: {png} is not a PNG")
base = os.path.splitext(png)[0]
for ext, magic in ((".pdf", b"%PDF-"), (".svg", None), (".caption.txt", None)):
    if not os.path.isfile(base + ext):
        sys.exit(f"scaling_check_plot_test: {base + ext} not written")
    if magic and open(base + ext, "rb").read(len(magic)) != magic:
        sys.exit(f"scaling_check_plot_test: {base + ext} is not a {ext[1:].upper()}")
caption = open(base + ".caption.txt", encoding="utf-8").read()
if ("Redraw: python3 plots/scaling_check.py" not in caption or "beyond the figure" in r.stderr
        or "hrad abc1234 on node7." not in caption):
    sys.exit(f"scaling_check_plot_test: caption or layout:\n{caption}\n{r.stderr}")
for needle in ("4 one-thread solves at once run at 0.968", "| blocked | 1.00 | 1.94 | 3.75 |",
               "| blocked, block 1 at 4 | 2.14 |", "| cabin (blocked) at 4 | 3.75 |"):
    if needle not in r.stdout:
        sys.exit(f"scaling_check_plot_test: the table lacks {needle!r}:\n{r.stdout}")
