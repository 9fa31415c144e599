"""Shared helpers for the hrad plot scripts (plots/*.py).

Every script reads only the files of one experiment result folder (runs.csv,
iterations.csv, manifest.json; see docs/results.md) and writes NAME.pdf, NAME.svg and
NAME.png (300 dpi) into that folder (or --out-dir), sized for a paper: 3.4 inches a
panel (one column; two panels fill a two-column width), 7-8 point text. The caption
(the machine and scenes from manifest.json, and the command that regenerates the
figure) goes to NAME.caption.txt, for the paper's own caption, not into the picture;
a --quick run is marked in the picture itself, since its numbers are not a result.
Only the standard library and matplotlib (Debian: python3-matplotlib) are used;
pandas is not needed.
"""

import argparse
import csv
import json
import math
import os
import re
import statistics
import sys



def _pyplot():
    """matplotlib.pyplot, imported on first use (bad input fails before the slow import).
    Without matplotlib the script exits with one line saying so (no traceback)."""
    try:
        import matplotlib
    except ImportError as e:
        reason = (str(e).splitlines() or ["not found"])[0]
        sys.exit(f"{os.path.basename(sys.argv[0]) or 'plot'}: cannot import matplotlib with "
                 f"{sys.executable} ({reason}); install python3-matplotlib (Debian) or run "
                 "the script with a Python that has it: nothing drawn")

    matplotlib.use("Agg")  # files only, no display
    # Text in the SVG stays text (searchable, editable), not outlines; the PDF embeds
    # TrueType fonts (Type 42), which journals accept.
    matplotlib.rcParams.update({
        "svg.fonttype": "none", "pdf.fonttype": 42, "font.size": 8, "axes.titlesize": 8,
        "axes.labelsize": 8, "xtick.labelsize": 7, "ytick.labelsize": 7, "legend.fontsize": 6.5,
        "lines.linewidth": 1.2, "lines.markersize": 4, "errorbar.capsize": 2})
    import matplotlib.pyplot as plt

    return plt


def parse_args(description):
    """RESULT_DIR [--out-dir DIR] [--simulated CSV] [--control CSV]."""
    p = argparse.ArgumentParser(description=description)
    p.add_argument("result_dir", help="experiment result folder (runs.csv, manifest.json)")
    p.add_argument("--out-dir", help="where to write the figures [default: RESULT_DIR]")
    p.add_argument("--simulated", help="simulated speedup CSV (hrad simulate); used by speedup.py")
    p.add_argument("--control", help="a tools/scaling-check.sh scaling.csv whose hardware "
                   "control gives the machine's limit; used by speedup.py")
    a = p.parse_args()
    if a.out_dir is None:
        a.out_dir = a.result_dir
    return a


def _value(text):
    """CSV text -> int, float or str (empty -> None)."""
    if text == "":
        return None
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def load_csv(path):
    """Rows of a CSV file as dicts with numbers converted."""
    with open(path, newline="") as f:
        return [{k: _value(v) for k, v in row.items()} for row in csv.DictReader(f)]


def load_result(result_dir):
    """(runs, iterations, manifest) of a result folder; missing files give [] / {}."""
    def maybe(name, loader, empty):
        path = os.path.join(result_dir, name)
        return loader(path) if os.path.exists(path) else empty

    runs = maybe("runs.csv", load_csv, [])
    iterations = maybe("iterations.csv", load_csv, [])
    manifest = maybe("manifest.json", lambda p: json.load(open(p)), {})
    if not runs:
        sys.exit(f"{result_dir}: no runs in runs.csv: nothing to plot")
    return runs, iterations, manifest


def scene_label(spec):
    """'builtin:office,desks=2,lights=1' (or 'builtin:office?desks=2&lights=1') ->
    'office (desks=2, lights=1)'; a file path -> its name."""
    spec = str(spec)
    if spec.startswith("builtin:"):
        parts = re.split(r"[?&,]", spec[len("builtin:"):])
        name, params = parts[0], [p for p in parts[1:] if p]
        return f"{name} ({', '.join(params)})" if params else name
    return os.path.basename(spec)


def unique(rows, key):
    """The distinct values of a column, in first-seen order."""
    seen = []
    for r in rows:
        if r.get(key) not in seen:
            seen.append(r.get(key))
    return seen


def mean_by(rows, keys, value):
    """{tuple of keys: (mean, min, max)} of `value` over the rows (repetitions)."""
    groups = {}
    for r in rows:
        v = r.get(value)
        if v is None:
            continue
        groups.setdefault(tuple(r.get(k) for k in keys), []).append(float(v))
    return {k: (statistics.fmean(v), min(v), max(v)) for k, v in groups.items()}


class Caption(str):
    """A figure's caption (str), knowing whether its runs were a --quick smoke test."""

    quick = False


def caption(manifest, rows, figure, extra_flags=""):
    """Machine, scenes, revision and the command that regenerates the figure
    (`extra_flags` appended to it, e.g. ' --simulated sim.csv'), as a Caption."""
    m = manifest.get("machine", {})
    exp = manifest.get("experiment", {})
    hrad = manifest.get("hrad", {})
    # Blanks tidied: older manifests kept the CPU model's padding.
    cpu = " ".join(str(m.get("cpu", "?")).removeprefix("this machine: ").split())
    machine = f"{m.get('hostname', '?')} ({cpu}, {m.get('pus_online', '?')} PUs)"
    scenes = ", ".join(scene_label(s) for s in unique(rows, "scene"))
    config = exp.get("config_file") or "experiments/configs/<config>.json"
    if "experiments/configs/" in config:
        config = config[config.index("experiments/configs/"):]
    flags = " --quick" if exp.get("quick") else ""
    for s in exp.get("sets", []):
        flags += f" --set {s}"
    flags += extra_flags
    reps = exp.get("repetitions", "?")
    spread = (f"{reps} repetitions, mean (bars: min-max)" if isinstance(reps, int) and reps > 1
              else "one run per point")
    text = Caption(f"{figure}. Machine {machine}; hrad {hrad.get('git_revision', '?')}; "
                   f"{spread}.\nScenes: {scenes}.\n"
                   f"Regenerate: hrad experiment {config}{flags}")
    text.quick = bool(exp.get("quick"))
    return text


def figure(nrows=1, ncols=1, width=3.4, height=2.6):
    """A figure of nrows x ncols panels, each width x height inches (a journal column
    is about 3.4 inches wide, a page 7)."""
    fig, axes = _pyplot().subplots(nrows, ncols, figsize=(width * ncols, height * nrows),
                                   squeeze=False)
    return fig, [ax for row in axes for ax in row]


def errorbar(ax, xs, stats, **kw):
    """Plots means with min-max bars; `stats` is a list of (mean, min, max)."""
    ys = [s[0] for s in stats]
    lo = [s[0] - s[1] for s in stats]
    hi = [s[2] - s[0] for s in stats]
    return ax.errorbar(xs, ys, yerr=[lo, hi], marker="o", **kw)


QUICK_MARK = "quick run (--quick): a smoke test of the pipeline, not a result"


def save(fig, out_dir, name, text, top_inches=0.0):
    """Writes NAME.pdf, NAME.svg, NAME.png (300 dpi) and the caption `text` to
    NAME.caption.txt (printed too); `top_inches` are kept free above the axes (for a
    figure legend or title). A caption of --quick runs puts QUICK_MARK above the axes."""
    height = fig.get_figheight()
    if getattr(text, "quick", False):
        fig.text(0.5, 1 - 0.04 / height, QUICK_MARK, ha="center", va="top", color="#b00000",
                 fontsize=8, fontweight="bold")
        top_inches += 0.2
    fig.tight_layout(rect=(0, 0, 1, 1 - top_inches / height), pad=0.3)
    os.makedirs(out_dir, exist_ok=True)
    paths = [os.path.join(out_dir, f"{name}.{ext}") for ext in ("pdf", "svg", "png")]
    for p in paths:
        fig.savefig(p, dpi=300)
    _pyplot().close(fig)
    caption_path = os.path.join(out_dir, f"{name}.caption.txt")
    with open(caption_path, "w") as f:
        f.write(str(text) + "\n")
    paths.append(caption_path)
    for p in paths:
        print(f"wrote {p}")
    print(str(text))
    return paths


def threads_axis(ax, threads, top=None):
    """Thread counts on x; a log2 axis once they span 16x or more (1 ... 64)."""
    ticks = sorted(t for t in threads if t is not None)
    top = max(ticks + [top or 0])
    ax.set_xlabel("refiner threads (processors)")
    if top >= 16 * ticks[0]:
        ax.set_xscale("log", base=2)
        ticks = [2**k for k in range(0, top.bit_length()) if 2**k >= ticks[0]]
        plain_log2(ax.xaxis)
    ax.set_xticks(ticks)
    ax.set_xticklabels([str(t) for t in ticks])
    ax.grid(True, alpha=0.3)


def plain_log2(axis):
    """A base-2 log axis labelled 1, 2, 4 ... 64 (matplotlib writes 2^0 ... 2^6)."""
    from matplotlib import ticker

    axis.set_major_formatter(ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    axis.set_minor_formatter(ticker.NullFormatter())


def is_finite(x):
    return x is not None and not (isinstance(x, float) and math.isnan(x))


def variant(row, exclude):
    """The row's swept values other than `exclude`, as 'scheduler=stack block_size=10'."""
    parts = [p for p in str(row.get("swept") or "").split(" ")
             if p and p.split("=", 1)[0] not in exclude]
    return " ".join(parts)


def label_log_axis(axis, lo, hi):
    """Tick labels on a log axis spanning [lo, hi] that can be read whatever its span:
    plain numbers (0.7, not 7e-1); every minor tick (2 ... 9) labelled when the span is
    under a decade, 2 and 5 under three decades; under half a decade, evenly spaced
    ticks instead (a log locator would leave one label or none there)."""
    from matplotlib import ticker

    decades = math.log10(hi / lo) if lo > 0 and hi > lo else 0.0
    axis.set_major_formatter(ticker.FuncFormatter(lambda v, _: f"{v:.3g}"))
    if decades < 0.5:
        axis.set_major_locator(ticker.MaxNLocator(5))
        axis.set_minor_locator(ticker.NullLocator())
        return
    keep = "23456789" if decades < 1 else "25" if decades < 3 else ""
    axis.set_minor_formatter(ticker.FuncFormatter(
        lambda v, _: f"{v:.3g}" if f"{v:.0e}"[0] in keep else ""))
