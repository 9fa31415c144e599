#!/usr/bin/env python3
"""The scaling check's figure and table (tools/scaling-check.sh).

Reads scaling.csv (one row per run: kind, scene, scheduler, block_size, threads, rep and
its times) and draws, for the refinement and for the whole run, each scheduler's
speed-up T(1) / T(P) on the lab against threads P (medians over repetitions, T(1) the
scheduler's own one-thread time), with:
  - the machine's limit from the hardware control: P x the speed of N independent
    one-thread solves run at once against one alone (drawn from 1 to N as a line; the
    efficiency at P < N lies between 1 and the one measured at N);
  - the fixed block sizes of `blocked` at N threads, and the cabin at N threads, as
    separate markers.
Prints the same figures as a Markdown table. Writes scaling.pdf, .svg, .png (300 dpi)
and scaling.caption.txt beside the CSV (or --out-dir, or --out PATH: PATH without its
extension names them), in the common style of plots/common.py (--size, --caption-in-image).
The caption names the revisions and hosts of the rows (columns `revision` and `host`;
a CSV from before they were written says that it does not record them).
Usage:
  scaling_check.py scaling.csv [--out scaling.png | --out-dir DIR] [--size page|column]
                   [--caption-in-image]
"""
import argparse
import csv
import os
import statistics
import sys

import common


def load(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{path}: no runs")
    for r in rows:
        for k in ("wall_s", "refine_wall_s", "propagate_wall_s"):
            r[k] = float(r[k])
        r["threads"] = int(r["threads"])
    return rows


def median_of(rows, key, **match):
    vals = [r[key] for r in rows if all(r[k] == v for k, v in match.items())]
    return statistics.median(vals) if vals else None


def control(rows):
    """(N, refinement efficiency, whole-run efficiency) of the control, or None."""
    par = [r for r in rows if r["kind"] == "control-parallel"]
    if not par:
        return None
    n = sum(1 for r in par if r["rep"].startswith("1-"))  # solves at once, first repetition
    eff = []
    for key in ("refine_wall_s", "wall_s"):
        alone = median_of(rows, key, kind="control-alone")
        together = statistics.median(r[key] for r in par)
        eff.append(alone / together if alone and together else float("nan"))
    return n, eff[0], eff[1]


def speedups(rows, key):
    """{scheduler: [(threads, speed-up)]} of the sweep."""
    out = {}
    sweep = [r for r in rows if r["kind"] == "sweep"]
    for s in sorted({r["scheduler"] for r in sweep}):
        base = median_of(sweep, key, scheduler=s, threads=1)
        if not base:
            continue
        pts = []
        for t in sorted({r["threads"] for r in sweep if r["scheduler"] == s}):
            m = median_of(sweep, key, scheduler=s, threads=t)
            pts.append((t, base / m))
        out[s] = pts
    return out


def extras(rows, key, n):
    """[(label, speed-up at N)]: blocked's fixed blocks (against blocked's 1-thread sweep
    time) and the cabin (against its own 1-thread time)."""
    out = []
    base = median_of(rows, key, kind="sweep", scheduler="blocked", threads=1)
    for b in sorted({r["block_size"] for r in rows if r["kind"] == "block"}, key=int):
        m = median_of(rows, key, kind="block", block_size=b, threads=n)
        if base and m:
            out.append((f"blocked, block {b}", base / m))
    c1 = median_of(rows, key, kind="cabin", threads=1)
    cn = median_of(rows, key, kind="cabin", threads=n)
    if c1 and cn and n > 1:
        out.append(("cabin (blocked)", c1 / cn))
    return out


def table(rows, ctl):
    n = max(r["threads"] for r in rows)
    lines = []
    if ctl:
        lines.append(f"control: {ctl[0]} one-thread solves at once run at {ctl[1]:.3f} of one "
                     f"alone in refinement, {ctl[2]:.3f} over the whole run: limits "
                     f"{ctl[0] * ctl[1]:.1f}x and {ctl[0] * ctl[2]:.1f}x at {ctl[0]} threads")
    for key, title in (("refine_wall_s", "refinement"), ("wall_s", "whole run")):
        sp = speedups(rows, key)
        ts = sorted({t for pts in sp.values() for t, _ in pts})
        lines.append(f"\n{title} speed-up (lab, medians)\n")
        lines.append("| scheduler | " + " | ".join(str(t) for t in ts) + " |")
        lines.append("|---|" + "---|" * len(ts))
        for s, pts in sp.items():
            d = dict(pts)
            lines.append(f"| {s} | " + " | ".join(f"{d[t]:.2f}" if t in d else "" for t in ts) +
                         " |")
        for label, v in extras(rows, key, n):
            lines.append(f"| {label} at {n} | {v:.2f} |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("--out", default=None,
                    help="figure path; its folder and name without the extension are used "
                         "[default: scaling.* beside the CSV]")
    ap.add_argument("--out-dir", default=None, help="folder for scaling.* [default: the CSV's]")
    common.add_figure_options(ap)
    a = ap.parse_args()
    common.use_figure_options(a)
    rows = load(a.csv)
    ctl = control(rows)
    print(table(rows, ctl))
    if a.out:
        out_dir, name = os.path.dirname(a.out) or ".", os.path.splitext(os.path.basename(a.out))[0]
    else:
        out_dir, name = a.out_dir or os.path.dirname(a.csv) or ".", "scaling"
    n = max(r["threads"] for r in rows)
    fig, axes = common.figure(1, 2)
    for ax, (key, title) in zip(axes, (("refine_wall_s", "refinement"), ("wall_s", "whole run"))):
        ts = [1, n]
        ax.plot(ts, ts, color="0.8", lw=1, label="linear")
        if ctl:
            eff = ctl[1] if key == "refine_wall_s" else ctl[2]
            ax.plot([1, ctl[0]], [1, ctl[0] * eff], color="0.3", ls="--", lw=1,
                    label="machine's limit (hardware control)")
        for s, pts in speedups(rows, key).items():
            ax.plot([t for t, _ in pts], [v for _, v in pts], marker="o", label=s)
        for label, v in extras(rows, key, n):
            ax.plot([n], [v], marker="x", ls="none", label=f"{label} at {n}")
        ax.set_title(f"lab, {title}" + (f"; control: {eff:.2f} at {ctl[0]}" if ctl else ""))
        ax.set_xticks(sorted({r["threads"] for r in rows}))
        ax.set_xlabel("threads")
        ax.set_ylabel("speed-up over 1 thread (medians)")
        ax.set_ylim(bottom=0)
        ax.grid(alpha=0.3)
    # One legend for both panels (the same lines), above them.
    common.legend_above(fig, axes[1])
    scenes = sorted({r["scene"] for r in rows})
    revisions = sorted({r.get("revision") or "" for r in rows} - {""})
    hosts = sorted({r.get("host") or "" for r in rows} - {""})
    made = (f"hrad {', '.join(revisions)} on {', '.join(hosts) or 'an unrecorded host'}."
            if revisions else "hrad revision not recorded in scaling.csv.")
    args = [common.as_given(a.csv)]
    if a.out:
        args += ["--out", common.as_given(a.out)]
    elif a.out_dir:
        args += ["--out-dir", common.as_given(a.out_dir)]
    text = common.Caption(
        "Scaling check: speed-up over one thread of the refinement and of the whole run "
        f"against threads, medians over repetitions; machine's limit from the hardware "
        f"control. {made}\n"
        f"Scenes: {', '.join(scenes)}.\n"
        f"Regenerate: tools/scaling-check.sh {n}\n"
        f"Redraw: {common.redraw_command(args=args)}")
    common.save(fig, out_dir, name, text)


if __name__ == "__main__":
    main()
