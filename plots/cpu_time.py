#!/usr/bin/env python3
"""Figure 4 of Sillion & Hasenfratz (2000): CPU refinement time per iteration.

For each scene, the refinement time summed over all refiners (refine_cpu_s of
iterations.csv, busy time of every refiner) against the number of refiner threads,
one line per iteration. Constant lines mean no parallel overhead.
Usage: cpu_time.py RESULT_DIR [--out-dir DIR] [--size page|column] [--caption-in-image]
"""
import common

args = common.parse_args(__doc__)
runs, iterations, manifest = common.load_result(args.result_dir)
scenes = common.unique(iterations, "scene")
fig, axes = common.figure(1, len(scenes))
for ax, scene in zip(axes, scenes):
    rows = [r for r in iterations if r["scene"] == scene]
    for var in common.unique([dict(r, v=common.variant(r, ("threads",))) for r in rows], "v"):
        sub = [r for r in rows if common.variant(r, ("threads",)) == var]
        stats = common.mean_by(sub, ("iteration", "threads"), "refine_cpu_s")
        for it in sorted(common.unique(sub, "iteration")):
            xs = sorted(t for (i, t) in stats if i == it)
            label = f"iteration {it}" + (f", {var}" if var else "")
            common.errorbar(ax, xs, [stats[(it, t)] for t in xs], label=label)
    common.threads_axis(ax, common.unique(rows, "threads"))
    ax.set_ylabel("refinement CPU time, all refiners (s)")
    ax.set_ylim(bottom=0)
    ax.set_title(common.scene_label(scene))
    common.legend_below(ax)
common.save(fig, args.out_dir, "cpu_time",
            common.caption(manifest, runs, "CPU refinement time per iteration (paper Fig. 4)"))
