#!/usr/bin/env python3
"""Figure 6 of Sillion & Hasenfratz (2000): links and memory by iteration.

Left: links alive at the end of each refinement iteration; right: the bytes held by
the hierarchy's structures (bytes_total = elements + links, iterations.csv) at the end
of each iteration, in MiB; one line per scene (and per other swept value). The link
set does not depend on the thread count, so the fewest-threads runs are shown.
Usage: memory.py RESULT_DIR [--out-dir DIR] [--size page|column] [--caption-in-image]
"""
import common

args = common.parse_args(__doc__)
runs, iterations, manifest = common.load_result(args.result_dir)
fewest = min(common.unique(iterations, "threads"))
rows = [r for r in iterations if r["threads"] == fewest]
for r in rows:
    r["variant"] = common.variant(r, ("threads",))
    r["mib"] = r["bytes_total"] / 2**20
fig, (a, b) = common.figure(1, 2)
for ax, column, ylabel in ((a, "links", "links alive at the end of the iteration"),
                           (b, "mib", "memory of elements + links (MiB)")):
    stats = common.mean_by(rows, ("scene", "variant", "iteration"), column)
    for key in sorted({k[:2] for k in stats}, key=str):
        its = sorted(k[2] for k in stats if k[:2] == key)
        label = common.scene_label(key[0]) + (f", {key[1]}" if key[1] else "")
        common.errorbar(ax, its, [stats[key + (i,)] for i in its], label=label)
    ax.set_xlabel("refinement iteration (state at its end)")
    ax.set_xticks(sorted(common.unique(rows, "iteration")))
    ax.set_ylabel(ylabel)
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
# One legend (the panels show the same lines), under the left panel.
common.legend_below(a)
a.set_title("links")
b.set_title("memory")
common.save(fig, args.out_dir, "memory",
            common.caption(manifest, runs,
                           f"Links and memory at the end of each iteration (paper Fig. 6; "
                           f"{fewest} thread{'' if fewest == 1 else 's'})"))
