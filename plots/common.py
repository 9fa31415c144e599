"""Shared helpers for the hrad plot scripts (plots/*.py).

Every script reads only the files of one experiment result folder (runs.csv,
iterations.csv, manifest.json; see docs/results.md) and writes NAME.pdf, NAME.svg and
NAME.png (300 dpi) into that folder (or --out-dir), sized for a paper:
  --size page    7 inches wide (the default): panels side by side, up to three a row;
  --size column  3.3 inches wide (one column of a two-column paper): one panel a row,
                 two when a figure has more than three; rows shorter than a lone
                 panel's, an axis label that a whole grid column (row) of panels has
                 drawn once, and legends that are the same under every panel drawn once
                 above them, so that six panels stay under 7.5 inches.
Text is 8-9 points at either size. The caption (the machine and scenes from
manifest.json, the hrad revision that made the data, and the commands that regenerate
the data and redraw the figure) goes to NAME.caption.txt, for the paper's own caption;
--caption-in-image also draws it under the panels. A --quick run is marked in the
picture itself, since its numbers are not a result. Titles, labels, legends and marks
are wrapped to the figure's width, and save() says on stderr if anything is still
drawn beyond the figure's edge.
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
import textwrap

# Figure widths in inches, by --size.
WIDTHS = {"page": 7.0, "column": 3.3}
# A row's height on a column when a figure has more than one: this share of the panel's
# width, but at least the inches given (a third of a column's 9 usable inches or less,
# less what goes above and under the panels).
COLUMN_ROW = (0.6, 1.75)
# The options of parse_args() that shape every figure of the run.
OPTIONS = {"size": "page", "caption_in_image": False}
# The repository root (commands in captions are written relative to it).
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


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
        "svg.fonttype": "none", "pdf.fonttype": 42, "font.size": 8, "axes.titlesize": 9,
        "axes.labelsize": 8.5, "xtick.labelsize": 8, "ytick.labelsize": 8,
        "legend.fontsize": 8, "legend.title_fontsize": 8, "lines.linewidth": 1.2,
        "lines.markersize": 4, "errorbar.capsize": 2})
    import matplotlib.pyplot as plt

    return plt


def add_figure_options(p):
    """--size and --caption-in-image on an argparse parser."""
    p.add_argument("--size", choices=sorted(WIDTHS), default="page",
                   help="figure width: page (7 in, the default) or column (3.3 in)")
    p.add_argument("--caption-in-image", action="store_true",
                   help="draw the caption under the panels too (it always goes to "
                        "NAME.caption.txt)")


def use_figure_options(a):
    """Takes --size and --caption-in-image from parsed arguments."""
    OPTIONS["size"] = a.size
    OPTIONS["caption_in_image"] = a.caption_in_image


def parse_args(description):
    """RESULT_DIR [--out-dir DIR] [--simulated CSV] [--control CSV] [--size S]
    [--caption-in-image]."""
    p = argparse.ArgumentParser(description=description,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("result_dir", help="experiment result folder (runs.csv, manifest.json)")
    p.add_argument("--out-dir", help="where to write the figures [default: RESULT_DIR]")
    p.add_argument("--simulated", help="simulated speedup CSV (hrad simulate); used by speedup.py")
    p.add_argument("--control", help="a tools/scaling-check.sh scaling.csv whose hardware "
                   "control gives the machine's limit; used by speedup.py")
    add_figure_options(p)
    a = p.parse_args()
    use_figure_options(a)
    ARGS.clear()
    ARGS.extend([as_given(a.result_dir)])
    if a.out_dir is not None and os.path.abspath(a.out_dir) != os.path.abspath(a.result_dir):
        ARGS.extend(["--out-dir", as_given(a.out_dir)])
    for flag, path in (("--simulated", a.simulated), ("--control", a.control)):
        if path:
            ARGS.extend([flag, as_given(path)])
    if a.out_dir is None:
        a.out_dir = a.result_dir
    return a


# The script's own arguments as the caption's "Redraw" command writes them (parse_args).
ARGS = []


def as_given(path):
    """A path as a command run from the repository root reaches it: relative to the root
    when it lies inside it, else absolute."""
    full = os.path.abspath(path)
    if full == ROOT or full.startswith(ROOT + os.sep):
        return os.path.relpath(full, ROOT)
    return full


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


def redraw_command(script=None, args=None):
    """'python3 plots/NAME.py ARGS --size S' (run from the repository root) for the
    caption: the script's arguments as given, the figure options when not the default."""
    script = as_given(script or sys.argv[0])
    words = ["python3", script] + list(ARGS if args is None else args)
    if OPTIONS["size"] != "page":
        words += ["--size", OPTIONS["size"]]
    if OPTIONS["caption_in_image"]:
        words.append("--caption-in-image")
    return " ".join(words)


def caption(manifest, rows, figure, extra_flags="", plot_flags=""):
    """Machine, scenes, the revision that made the data and the commands that regenerate
    the data (`extra_flags` appended to `hrad experiment`, e.g. ' --simulated sim.csv')
    and redraw the figure (`plot_flags` appended to the script's own arguments), as a
    Caption."""
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
    text = Caption(f"{figure}. Machine {machine}; data from hrad "
                   f"{hrad.get('git_revision', '(revision not recorded)')}; {spread}.\n"
                   f"Scenes: {scenes}.\n"
                   f"Regenerate: hrad experiment {config}{flags}\n"
                   f"Redraw: {redraw_command()}{plot_flags}")
    text.quick = bool(exp.get("quick"))
    return text


def grid(nrows, ncols):
    """The (rows, columns) that nrows x ncols panels take at the chosen --size: as asked
    on a page; on a column one a row, or two when there are more than three."""
    if OPTIONS["size"] == "page" or ncols == 1:
        return nrows, ncols
    n = nrows * ncols
    cols = 1 if n <= 3 else 2
    return -(-n // cols), cols


def figure(nrows=1, ncols=1, height=None, extra_height=0.0):
    """A figure of nrows x ncols panels (laid out again for a column, see grid()) as
    wide as --size says; `height` inches a row [default: from the panel's width; on a
    column, rows of a figure with several are shorter, see COLUMN_ROW], plus
    `extra_height` inches (for legends below the panels). Panels are in reading order,
    so a script can index them alike at either size; a grid cell left over (an odd
    count two a row) is left empty."""
    n = nrows * ncols
    nrows, ncols = grid(nrows, ncols)
    width = WIDTHS[OPTIONS["size"]]
    panel = width / ncols
    if height is None and OPTIONS["size"] == "column" and nrows > 1:
        height = max(COLUMN_ROW[0] * panel, COLUMN_ROW[1])
    elif height is None:
        height = min(max(0.72 * panel, 1.9), 2.9)
    fig, axes = _pyplot().subplots(nrows, ncols, figsize=(width, height * nrows + extra_height), dpi=300,
                                   squeeze=False)
    axes = [ax for row in axes for ax in row]
    for ax in axes[n:]:
        fig.delaxes(ax)
    return fig, axes[:n]


def errorbar(ax, xs, stats, **kw):
    """Plots means with min-max bars; `stats` is a list of (mean, min, max)."""
    ys = [s[0] for s in stats]
    lo = [s[0] - s[1] for s in stats]
    hi = [s[2] - s[0] for s in stats]
    return ax.errorbar(xs, ys, yerr=[lo, hi], marker="o", **kw)


def legend_below(ax, ncol=4, **kw):
    """A legend under the panel's x label, outside the data; save() moves it there once
    the layout is known and gives it as many columns (ncol at most) as the panel's width
    holds."""
    handles, labels = ax.get_legend_handles_labels()
    if not handles:
        return None
    spec = {"handles": handles, "labels": labels, "most": ncol, "kw": kw}
    return _legend_below(ax, spec, ncol)


def _legend_below(ax, spec, ncol):
    leg = ax.legend(spec["handles"], spec["labels"], loc="upper center", frameon=False,
                    bbox_to_anchor=(0.5, -0.2), ncol=ncol, **spec["kw"])
    leg._hrad_below = spec
    return leg


def legend_above(fig, ax=None, handles=None, labels=None, ncol=None, **kw):
    """One legend for every panel, with `ax`'s lines (or the handles and labels given),
    above the panels: save() keeps room for it and gives it as many columns (ncol at
    most) as the figure's width holds."""
    if ax is not None:
        handles, labels = ax.get_legend_handles_labels()
    fig._hrad_above = getattr(fig, "_hrad_above", []) + [
        {"handles": list(handles), "labels": list(labels), "most": ncol or len(labels),
         "kw": kw}]


def after_layout(fig, fn):
    """Calls fn(renderer) in save(), once the panels have their final place (for labels
    placed so as not to overlap)."""
    fig._hrad_after = getattr(fig, "_hrad_after", []) + [fn]


QUICK_MARK = "quick run (--quick): a smoke test of the pipeline, not a result"


def _wrap(text, max_px, renderer):
    """Re-wraps a Text artist's lines (kept where they break already) until it is at
    most max_px long (along its lines: a y label's height), or its words allow no
    shorter."""
    s = text.get_text()
    upright = text.get_rotation() % 180 == 90
    for _ in range(4):
        box = text.get_window_extent(renderer)
        width = box.height if upright else box.width
        if not s or width <= max_px:
            return
        longest = max(len(line) for line in s.split("\n"))
        chars = max(8, int(longest * max_px / width * 0.97))
        wrapped = "\n".join(textwrap.fill(line, chars, break_on_hyphens=False) or line
                            for line in s.split("\n"))
        if wrapped == s:
            return
        s = wrapped
        text.set_text(s)


def _inches(artist, renderer, fig):
    return artist.get_window_extent(renderer).height / fig.dpi


def _share_axis_labels(fig):
    """An x label that every panel of a grid column has is kept under the lowest one
    only, a y label that every panel of a grid row has beside the leftmost one only (the
    panels keep their own ticks). A figure with two axes in one cell is left alone."""
    cells = [(ax, ax.get_subplotspec()) for ax in fig.axes]
    cells = [(ax, s.rowspan.start, s.colspan.start) for ax, s in cells if s is not None]
    if len({(r, c) for _, r, c in cells}) < len(cells):
        return
    shared = []
    for ax, r, c in cells:
        column = [(a, rr) for a, rr, cc in cells if cc == c]
        row = [(a, cc) for a, rr, cc in cells if rr == r]
        if r < max(rr for _, rr in column) and len({a.get_xlabel() for a, _ in column}) == 1:
            shared.append((ax, "xlabel"))
        if c > min(cc for _, cc in row) and len({a.get_ylabel() for a, _ in row}) == 1:
            shared.append((ax, "ylabel"))
    for ax, label in shared:
        ax.set(**{label: ""})


def _merge_legends_below(fig):
    """legend_below() legends with the same labels under every panel that has one become
    one legend above the panels (as legend_above())."""
    legs = [ax.get_legend() for ax in fig.axes]
    legs = [leg for leg in legs if leg is not None and hasattr(leg, "_hrad_below")]
    if len(legs) < 2 or any(leg._hrad_below["labels"] != legs[0]._hrad_below["labels"]
                            for leg in legs):
        return
    spec = legs[0]._hrad_below
    for leg in legs:
        leg.remove()
    legend_above(fig, handles=spec["handles"], labels=spec["labels"], ncol=spec["most"],
                 **spec["kw"])


def _fit_axes_text(fig, renderer, panel_w, panel_h):
    """Titles and axis labels wrapped to a panel's nominal size (in pixels)."""
    inner = panel_w - 0.5 * fig.dpi  # less the y axis' labels
    for ax in fig.axes:
        _wrap(ax.title, inner, renderer)
        _wrap(ax.xaxis.label, inner, renderer)
        _wrap(ax.yaxis.label, 0.8 * panel_h, renderer)


def _fit_legend(make, most, width, renderer, dpi):
    """The legend make(ncol) with the most columns (up to `most`) that fit in `width`
    pixels as they are, or fewer where they take as many rows (four entries in two
    columns of two, not three over one); when not even one column does, one column with
    its labels wrapped to that width."""
    for n in range(most, 0, -1):
        leg = make(n)
        if leg.get_window_extent(renderer).width <= width:
            count = len(leg.get_texts())
            even = -(-count // -(-count // n))  # the fewest columns for as many rows
            if even < n:
                leg.remove()
                leg = make(even)
            return leg
        leg.remove()
    leg = make(1)
    for t in leg.get_texts():
        _wrap(t, width - 40 * dpi / 72, renderer)
    return leg


def _fit_legends_below(fig, renderer, width):
    """Each legend_below() legend fitted to `width` pixels; {grid row: the tallest
    legend's height in inches}."""
    rows = {}
    for ax in fig.axes:
        leg = ax.get_legend()
        if leg is None or not hasattr(leg, "_hrad_below"):
            continue
        spec = leg._hrad_below
        leg = _fit_legend(lambda n: _legend_below(ax, spec, n), spec["most"], width, renderer,
                          fig.dpi)
        row = ax.get_subplotspec().rowspan.start if ax.get_subplotspec() else 0
        rows[row] = max(rows.get(row, 0.0), _inches(leg, renderer, fig) + 0.08)
    return rows


def _place_legends_below(fig, renderer):
    """Each legend_below() legend under its panel's x axis."""
    from matplotlib.transforms import ScaledTranslation

    for ax in fig.axes:
        leg = ax.get_legend()
        if leg is None or not hasattr(leg, "_hrad_below"):
            continue
        # Anchored by the depth of the x axis' labels under the panel (in inches, which
        # the layout does not change), so that it stays under them when the panel moves.
        axis = ax.xaxis.get_tightbbox(renderer)
        depth = (ax.get_window_extent(renderer).y0 - axis.y0) / fig.dpi if axis else 0.4
        leg.set_bbox_to_anchor((0.5, 0), transform=ax.transAxes + ScaledTranslation(
            0, -depth - 0.03, fig.dpi_scale_trans))


def _thin_tick_labels(fig, renderer):
    """Where an axis' tick labels run into each other (a narrow panel of a log axis with
    labelled minor ticks), the minor ticks whose labels cover a major tick's label or an
    earlier minor one's lose their labels."""
    from matplotlib import ticker

    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            lo, hi = sorted(axis.get_view_interval())

            def shown(ticks):
                return [(t.get_loc(), t.label1.get_window_extent(renderer)) for t in ticks
                        if t.label1.get_visible() and t.label1.get_text()
                        and lo <= t.get_loc() <= hi]

            kept = [b for _, b in shown(axis.get_major_ticks())]
            minor = shown(axis.get_minor_ticks())
            keep = []
            for loc, box in minor:
                if not any(box.overlaps(b) for b in kept):
                    kept.append(box)
                    keep.append(loc)
            if len(keep) < len(minor):
                old = axis.get_minor_formatter()
                axis.set_minor_formatter(ticker.FuncFormatter(
                    lambda v, pos, old=old, keep=keep:
                    old(v, pos) if any(abs(v - k) <= 1e-9 * abs(k) for k in keep) else ""))


def save(fig, out_dir, name, text, top_inches=0.0):
    """Writes NAME.pdf, NAME.svg, NAME.png (300 dpi) and the caption `text` to
    NAME.caption.txt (printed too). On a column, axis labels and legend_below() legends
    that repeat are drawn once (_share_axis_labels(), _merge_legends_below()). Text is
    wrapped to the panels' size first; then the figure grows (its width stays) by what
    is drawn outside the panels: legend_below() legends, figure legends
    (fig.legend(loc="upper center"), stacked above the panels), QUICK_MARK above them
    when the caption is of --quick runs, `top_inches` more, and with --caption-in-image
    the caption under the panels."""
    renderer = fig.canvas.get_renderer()
    width_px = fig.bbox.width
    pad = 0.05
    nrows, ncols = fig.axes[0].get_subplotspec().get_gridspec().get_geometry()
    panel_w, panel_h = width_px / ncols, fig.bbox.height / nrows
    if OPTIONS["size"] == "column":  # room is short: what repeats is drawn once
        _share_axis_labels(fig)
        _merge_legends_below(fig)
    _fit_axes_text(fig, renderer, panel_w, panel_h)
    below = _fit_legends_below(fig, renderer, 0.95 * (width_px if ncols == 1 else panel_w))
    above = []  # (artist, inches) stacked from the top
    if getattr(text, "quick", False):
        mark = fig.text(0.5, 1, QUICK_MARK, ha="center", va="top", color="#b00000",
                        fontsize=8, fontweight="bold")
        _wrap(mark, 0.98 * width_px, renderer)
        above.append(mark)
    for leg in fig.legends:  # made with fig.legend()
        for t in leg.get_texts():
            _wrap(t, 0.95 * width_px / max(1, leg._ncols) - 40 * fig.dpi / 72, renderer)
        above.append(leg)
    for spec in getattr(fig, "_hrad_above", []):  # legend_above()
        above.append(_fit_legend(
            lambda n, spec=spec: fig.legend(spec["handles"], spec["labels"],
                                            loc="upper center", ncol=n, frameon=False,
                                            **spec["kw"]),
            spec["most"], 0.97 * width_px, renderer, fig.dpi))
    cap = None
    if OPTIONS["caption_in_image"]:
        cap = fig.text(0.01, 0.0, str(text), ha="left", va="bottom", fontsize=8)
        _wrap(cap, 0.98 * width_px, renderer)
    top = sum(_inches(a, renderer, fig) + pad for a in above) + top_inches
    bottom = _inches(cap, renderer, fig) + 3 * pad if cap is not None else 0.0
    w, h = fig.get_size_inches()
    height = h + top + bottom + sum(below.values())
    fig.set_size_inches(w, height)
    y = height - pad
    for a in above:
        if a in fig.legends:
            a.set_bbox_to_anchor((0.5, y / height), transform=fig.transFigure)
        else:
            a.set_y(y / height)
        y -= _inches(a, renderer, fig) + pad
    if cap is not None:
        cap.set_y(pad / height)
    for i in range(3):
        fig.tight_layout(rect=(0, bottom / height, 1, 1 - top / height), pad=0.3)
        _place_legends_below(fig, renderer)
        if i == 0:
            # The layout leaves out how far a title is wider than its panel: wrapped to
            # the panel's real width now (the next pass makes room for the new lines).
            for ax in fig.axes:
                box = ax.get_window_extent(renderer)
                _wrap(ax.title, box.width + 0.1 * fig.dpi, renderer)
                _wrap(ax.xaxis.label, box.width + 0.1 * fig.dpi, renderer)
            _thin_tick_labels(fig, renderer)
    for fn in getattr(fig, "_hrad_after", []):
        fn(renderer)
    drawn = fig.get_tightbbox(renderer)
    edge = fig.bbox_inches
    over = max(edge.x0 - drawn.x0, drawn.x1 - edge.x1, edge.y0 - drawn.y0, drawn.y1 - edge.y1)
    if over > 0.02:
        print(f"{os.path.basename(sys.argv[0])}: {name}: something is drawn {over:.2f} in "
              "beyond the figure's edge", file=sys.stderr)
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


def label_points(ax, xs, ys, labels, fontsize=7.5, marker_pt=4.5):
    """Labels beside points, each where it covers no label already placed and no other
    point (a square of marker_pt points around each), inside the panel (right-above,
    right-below, left-above, left-below, right, left); a label with no free place
    is left out. Call from after_layout(), when the panel's size is final. Returns how
    many were left out."""
    from matplotlib.transforms import Bbox

    renderer = ax.figure.canvas.get_renderer()
    r = marker_pt * ax.figure.dpi / 72
    centres = [ax.transData.transform((x, y)) for x, y in zip(xs, ys)]
    placed = [Bbox.from_extents(cx - r, cy - r, cx + r, cy + r) for cx, cy in centres]
    inside = ax.get_window_extent(renderer).padded(-1)
    left_out = 0
    offsets = [(3, 2), (3, -9), (-4, 2), (-4, -9), (6, -3), (-7, -3)]
    for x, y, label in zip(xs, ys, labels):
        for dx, dy in offsets:
            a = ax.annotate(label, (x, y), xytext=(dx, dy), textcoords="offset points",
                            fontsize=fontsize, ha="left" if dx >= 0 else "right")
            box = a.get_window_extent(renderer)
            free = not any(box.overlaps(b) for b in placed)
            if free and inside.containsx(box.x0) and inside.containsx(box.x1) \
                    and inside.containsy(box.y0) and inside.containsy(box.y1):
                placed.append(box)
                break
            a.remove()
        else:
            left_out += 1
    return left_out


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
