#!/usr/bin/env python3
"""Figure 7 of Sillion & Hasenfratz (2000): influence of the block size.

CPU refinement time summed over refiners and over all iterations (refine_cpu_s of
runs.csv) against refiner threads, one line per block size, one panel per scene.
Usage: block_size.py RESULT_DIR [--out-dir DIR] [--size page|column] [--caption-in-image]
"""
import common

args = common.parse_args(__doc__)
runs, iterations, manifest = common.load_result(args.result_dir)
for r in runs:
    r["variant"] = common.variant(r, ("threads", "block_size"))
scenes = common.unique(runs, "scene")
fig, axes = common.figure(1, len(scenes))
for ax, scene in zip(axes, scenes):
    rows = [r for r in runs if r["scene"] == scene]
    stats = common.mean_by(rows, ("block_size", "variant", "threads"), "refine_cpu_s")
    for key in sorted({k[:2] for k in stats}, key=str):
        xs = sorted(k[2] for k in stats if k[:2] == key)
        label = f"block size {key[0]}" + (f", {key[1]}" if key[1] else "")
        common.errorbar(ax, xs, [stats[key + (t,)] for t in xs], label=label)
    common.threads_axis(ax, common.unique(rows, "threads"))
    ax.set_ylabel("CPU refinement time (s)\nsummed over refiners and iterations")
    ax.set_ylim(bottom=0)
    ax.set_title(common.scene_label(scene))
    common.legend_below(ax)
common.save(fig, args.out_dir, "block_size",
            common.caption(manifest, runs, "CPU time vs block size (paper Fig. 7)"))
