#!/usr/bin/env python3
"""Accuracy against cost: probe error vs wall time and vs memory, per scene.

Reads runs.csv of an experiment with an `accuracy` block (probe_err_mean: mean over the
probes of the relative irradiance error against the path-traced reference). One row of
panels per scene: left, error against wall time (wall_s, the solve without the probe
gather); right, error against the memory of the hierarchy at the end of the run
(bytes_total = elements + links). Log-log; one marker set per oracle (per oracle and
row_sums when the sweep varies row_sums), each set's own Pareto front joined by a line; the Pareto front over all runs (no other run is both
faster/smaller and more accurate) is circled in black and its points labelled with
their settings. The fronts are also printed on stdout. Where the folder holds the scene's
cached reference (reference-<scene>.csv), its noise is shaded: the mean over the probes
of the reference's relative standard error (channel of the largest irradiance), below
which an error is not resolved and a fall is no trend.
Usage: accuracy_time.py RESULT_DIR [--out-dir DIR] [--size page|column] [--caption-in-image]
"""
import os
import statistics

import common

ERROR = "probe_err_mean"
MARKERS = ["o", "s", "^", "D", "v", "P"]
COLOURS = ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown"]


def pareto(points, x, y):
    """The non-dominated points (smaller x and smaller y are better), by increasing x."""
    front, best = [], float("inf")
    for p in sorted(points, key=lambda p: (p[x], p[y])):
        if p[y] < best:
            front.append(p)
            best = p[y]
    return front


def short(v):
    """1e-05 -> 1e-5, 0.0003 -> 3e-4, 4 -> 4."""
    if isinstance(v, float):
        m, _, e = f"{v:.0e}".partition("e")
        return f"{m}e{int(e)}"
    return str(v)


def reference_noise_pct(result_dir, scene):
    """The mean relative standard error (%) of the scene's cached reference in the
    result folder (named as experiments/harness/accuracy.cpp names it); None without."""
    name = "".join(c if (c.isascii() and c.isalnum()) or c in "_.-" else "_" for c in scene)
    path = os.path.join(result_dir, f"reference-{name}.csv")
    if not os.path.exists(path):
        return None
    rel = []
    for r in common.load_csv(path):
        c = max("rgb", key=lambda c: r.get(f"E_{c}") or 0)
        e, se = r.get(f"E_{c}"), r.get(f"SE_{c}")
        if e and se is not None and e > 0:
            rel.append(se / e)
    return 100 * statistics.fmean(rel) if rel else None


def settings_label(p):
    parts = []
    for key, name in (("oracle", ""), ("row_sums", ""), ("eps", "eps "), ("min_area", "a "),
                      ("visibility_rays", "v ")):
        if key == "row_sums" and not VARY_ROW_SUMS:
            continue
        if p.get(key) is not None:
            parts.append(name + short(p[key]))
    return " ".join(parts)


args = common.parse_args(__doc__)
runs, _, manifest = common.load_result(args.result_dir)
rows = [r for r in runs if r.get(ERROR) is not None]
if not rows:
    raise SystemExit(f"{args.result_dir}: runs.csv has no {ERROR} values (run the experiment "
                     "with an 'accuracy' block)")

# Mean over repetitions of each point.
points = []
for key, (err, _, _) in common.mean_by(rows, ("scene", "point"), ERROR).items():
    same = [r for r in rows if (r["scene"], r["point"]) == key]
    p = dict(same[0])
    p[ERROR] = err
    p["wall_s"] = sum(r["wall_s"] for r in same) / len(same)
    p["mib"] = sum(r["bytes_total"] for r in same) / len(same) / 2**20
    p["err_pct"] = max(err, 1e-9) * 100
    points.append(p)

scenes = common.unique(points, "scene")
VARY_ROW_SUMS = len(common.unique(points, "row_sums")) > 1
for p in points:
    # Short legend labels (oracle, then row_sums when swept): long ones took a column-wide
    # figure's legend to ten rows of one column.
    p["set"] = p["oracle"] + (f", {p['row_sums']}" if VARY_ROW_SUMS else "")
oracles = common.unique(points, "set")
fig, axes = common.figure(len(scenes), 2)
keys = []  # the numbered front points' settings, per panel, for the caption
for s, scene in enumerate(scenes):
    mine = [p for p in points if p["scene"] == scene]
    noise = reference_noise_pct(args.result_dir, scene)
    for c, (xkey, xlabel, what) in enumerate((("wall_s", "wall time of the solve (s)", "time"),
                                             ("mib", "memory: elements + links (MiB)",
                                              "memory"))):
        ax = axes[2 * s + c]
        for o, oracle in enumerate(oracles):
            ps = [p for p in mine if p["set"] == oracle]
            if not ps:
                continue
            colour = COLOURS[o % len(COLOURS)]
            ax.scatter([p[xkey] for p in ps], [p["err_pct"] for p in ps], s=14, alpha=0.45,
                       color=colour, marker=MARKERS[o % len(MARKERS)], label=f"{oracle}: runs")
            own = pareto(ps, xkey, "err_pct")
            ax.plot([p[xkey] for p in own], [p["err_pct"] for p in own], color=colour,
                    drawstyle="steps-post", linewidth=1.2,
                    label=f"{oracle}: front")
        front = pareto(mine, xkey, "err_pct")
        ax.scatter([p[xkey] for p in front], [p["err_pct"] for p in front], s=60,
                   facecolors="none", edgecolors="black", linewidths=1.0,
                   label="front of all runs")
        # Numbers beside the front's points (their settings would pile up in a
        # column-wide panel), placed once the panel's size is final so that none covers
        # another (a number with no free place is left out); the settings of each
        # number are in the caption.
        common.after_layout(fig, lambda r, ax=ax, front=front, xkey=xkey: common.label_points(
            ax, [p[xkey] for p in front], [p["err_pct"] for p in front],
            [str(i) for i in range(1, len(front) + 1)]))
        keys.append(f"{common.scene_label(scene)} vs {what}: " +
                    "; ".join(f"{i} {settings_label(p)}" for i, p in enumerate(front, 1)))
        print(f"{common.scene_label(scene)}: Pareto front, error vs {what}:")
        for p in front:
            print(f"  {settings_label(p):40s} error {p['err_pct']:7.2f}%  "
                  f"max {p.get('probe_err_max', 0) * 100:7.2f}%  wall {p['wall_s']:8.3f} s  "
                  f"{p['mib']:8.2f} MiB  links {p.get('links')}")
        ax.set_xscale("log")
        ax.set_yscale("log")
        if noise is not None:  # shaded from the axis' bottom, which it does not move
            lo, hi = ax.get_ylim()
            ax.axhspan(min(lo, noise / 2), noise, color="0.88", zorder=0,
                       label="reference noise (mean SE)")
            ax.set_ylim(min(lo, noise / 2), max(hi, 2 * noise))
        # Labels that can be read on any span (the furnace's errors lie within 0.3-2 %).
        common.label_log_axis(ax.xaxis, *ax.get_xlim())
        common.label_log_axis(ax.yaxis, *ax.get_ylim())
        ax.set_xlabel(xlabel)
        ax.set_ylabel("mean relative probe error (%)")
        ax.set_title(f"{common.scene_label(scene)}: error vs {what}")
        ax.grid(True, which="both", alpha=0.25)

# One legend for every panel, above them, so that none covers a panel's points. A set's
# runs and its front share one entry (marker and line side by side): ten entries took a
# column-wide figure's legend to ten rows.
handles = {}
for ax in axes:
    for h, l in zip(*ax.get_legend_handles_labels()):
        handles.setdefault(l, h)
entries = {}
for oracle in oracles:
    pair = tuple(handles[k] for k in (f"{oracle}: runs", f"{oracle}: front") if k in handles)
    if pair:
        entries[oracle] = pair
for label in ("front of all runs", "reference noise (mean SE)"):
    if label in handles:
        entries[label] = handles[label]
from matplotlib.legend_handler import HandlerTuple  # noqa: E402 (common checks matplotlib)

# At most three columns (save() takes fewer where the labels are too wide for them).
columns = min(3, len(entries))
common.legend_above(fig, handles=entries.values(), labels=entries.keys(), ncol=columns,
                    handler_map={tuple: HandlerTuple(ndivide=None)})

common.save(fig, args.out_dir, "accuracy_time",
            common.caption(manifest, runs,
                           "Mean relative probe error (vs path-traced reference) against wall "
                           "time and memory; circled and numbered: the Pareto front (oracle, "
                           "row_sums when swept, eps, a = min_area, v = visibility rays; a "
                           "number that would cover another is left out): " +
                           ". ".join(keys)))
