#!/usr/bin/env python3
"""Figure 5 of Sillion & Hasenfratz (2000): speedup.

(a) Speedup of the refinement over all iterations, T(1) / T(P) of refine_wall_s
    (runs.csv), against refiner threads P, per scene (and per other swept value);
(b) the same per iteration (iterations.csv) for one scene: the cabin if present
    (the paper's Aircraft), else the last scene.
T(1) is the mean one-thread time of the same scene and other swept values; a curve
without a one-thread run is not drawn. With --simulated CSV (from `hrad simulate
--out`: columns kind, scheduler, block_size, procs, iteration, speedup, source, and
optionally scene; rows of kind "simulated" and iteration "all" are used) the simulated
curves are drawn dashed and labelled "simulated"; when the CSV also holds measured
rows (kind "measured", from `hrad simulate --measured STATS.json`), each simulated
curve's label gives its error against them at 1 and 2 processors and says whether it
is within 10% (the simulator's validation target).
The caption's command then carries --simulated, and the dashed curves' labels say that
they replay a trace of their own scene and settings (the trace file, `source`).
With --control CSV (a tools/scaling-check.sh scaling.csv) the machine's limit from its
hardware control (P x the efficiency of N one-thread solves run at once) is drawn dashed.
The legends sit under each panel, outside the data.
Usage: speedup.py RESULT_DIR [--out-dir DIR] [--simulated CSV] [--control CSV]
                  [--size page|column] [--caption-in-image]
"""
import os

import common


def speedups(rows, keys):
    """{variant key: [(threads, speedup mean, min, max)]} against the 1-thread mean."""
    out = {}
    stats = common.mean_by(rows, keys + ("threads",), "refine_wall_s")
    for k in {k[:-1] for k in stats}:
        base = stats.get(k + (1,))
        if not base or base[0] <= 0:
            continue
        pts = []
        for t in sorted(kk[-1] for kk in stats if kk[:-1] == k):
            m, lo, hi = stats[k + (t,)]
            pts.append((t, base[0] / m, base[0] / hi, base[0] / lo))
        out[k] = pts
    return out


def draw(ax, curves, label_of):
    top = 1
    for k in sorted(curves, key=str):
        pts = curves[k]
        common.errorbar(ax, [p[0] for p in pts], [(p[1], p[2], p[3]) for p in pts],
                        label=label_of(k))
        top = max(top, max(p[0] for p in pts))
    return top


def ideal(ax, top):
    xs = list(range(1, int(top) + 1))
    ax.plot(xs, xs, color="grey", linestyle=":", label="ideal")


def validation(sim, measured, key):
    """' (vs measured: P=1 +7%, P=2 -24%; not within 10%)' for one simulated curve."""
    parts, worst = [], 0.0
    for p in (1, 2):
        same = lambda r: (float(r["procs"]) == p and r.get("scheduler") == key[1]
                          and str(r.get("block_size")) == str(key[2]))
        m = sorted(float(r["time_s"]) for r in measured if same(r))
        s = [float(r["time_s"]) for r in sim if same(r) and (r["scene"]) == key[0]]
        if m and s and m[len(m) // 2] > 0:
            err = (s[0] - m[len(m) // 2]) / m[len(m) // 2]
            worst = max(worst, abs(err))
            parts.append(f"P={p} {100 * err:+.0f}%")
    if not parts:
        return ""
    verdict = "within 10%" if worst <= 0.10 else "NOT within 10%"
    return f"\n(vs measured: {', '.join(parts)}; {verdict})"


args = common.parse_args(__doc__)
runs, iterations, manifest = common.load_result(args.result_dir)
for r in runs + iterations:
    r["variant"] = common.variant(r, ("threads",))
fig, (a, b) = common.figure(1, 2)

curves = speedups(runs, ("scene", "variant"))
top = draw(a, curves, lambda k: common.scene_label(k[0]) + (f", {k[1]}" if k[1] else ""))
if args.simulated:
    # `hrad simulate --out` rows: kind simulated / measured, iteration N or "all"; the
    # scene is named by a `scene` column when there is one, else by the trace (`source`).
    sim_rows = common.load_csv(args.simulated)
    sim = [r for r in sim_rows
           if r.get("kind", "simulated") == "simulated" and r.get("iteration", "all") == "all"]
    measured = [r for r in sim_rows
                if r.get("kind") == "measured" and r.get("iteration", "all") == "all"]
    for r in sim:
        r["scene"] = r.get("scene") or r.get("source") or "trace"
    for key in sorted({(r["scene"], r.get("scheduler"), r.get("block_size")) for r in sim}, key=str):
        pts = sorted((r["procs"], r["speedup"]) for r in sim
                     if (r["scene"], r.get("scheduler"), r.get("block_size")) == key)
        traces = sorted({os.path.basename(str(r.get("source") or "")) for r in sim
                         if (r["scene"], r.get("scheduler"), r.get("block_size")) == key} - {""})
        a.plot([p[0] for p in pts], [p[1] for p in pts], linestyle="--",
               label=f"simulated (hrad simulate{' of ' + ', '.join(traces) if traces else ''}):"
                     f" {common.scene_label(key[0])}, {key[1]}, block {key[2]}, its own trace's "
                     "settings, not those of the measured curves" + validation(sim, measured, key))
        top = max(top, max(p[0] for p in pts))
ideal(a, top)
if args.control:
    # The hardware control of tools/scaling-check.sh: N one-thread solves at once against
    # one alone; P threads can at best reach P x that efficiency (drawn from 1 to N).
    ctl = common.load_csv(args.control)
    alone = [r["refine_wall_s"] for r in ctl if r["kind"] == "control-alone"]
    together = [r["refine_wall_s"] for r in ctl if r["kind"] == "control-parallel"]
    if alone and together:
        n = sum(1 for r in ctl if r["kind"] == "control-parallel" and str(r["rep"]).startswith("1-"))
        eff = sorted(alone)[len(alone) // 2] / sorted(together)[len(together) // 2]
        a.plot([1, n], [1, n * eff], color="0.3", linestyle="--",
               label=f"machine's limit (hardware control: {eff:.2f} at {n})")
if top > 8:  # simulated curves far beyond the measured threads: log-log
    a.set_yscale("log", base=2)
    common.plain_log2(a.yaxis)
a.set_title("(a) speedup of the refinement, all iterations")

scenes = common.unique(runs, "scene")
focus = next((s for s in scenes if "cabin" in str(s)), scenes[-1])
per_it = speedups([r for r in iterations if r["scene"] == focus], ("iteration", "variant"))
ideal(b, draw(b, per_it, lambda k: f"iteration {k[0]}" + (f", {k[1]}" if k[1] else "")))
b.set_title(f"(b) per iteration: {common.scene_label(focus)}")

common.threads_axis(a, common.unique(runs, "threads"), int(top))
common.threads_axis(b, common.unique(runs, "threads"))
for ax in (a, b):
    ax.set_ylabel("speedup T(1) / T(P), refinement")
    common.legend_below(ax, ncol=2)  # outside the data: no curve is covered
title = "Speedup (paper Fig. 5)"
extra = ""
if args.simulated:
    title += ("; dashed: simulated from a task trace (hrad simulate), whose scene, settings "
              "and revision are its own")
    # hrad experiment passes --simulated on to this script (--control it does not know).
    extra = f" --simulated {common.as_given(args.simulated)}"
common.save(fig, args.out_dir, "speedup", common.caption(manifest, runs, title, extra))
