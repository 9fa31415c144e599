#!/usr/bin/env python3
"""NUMA: thread pinning x memory placement x scheduler.

Left: refinement wall time of every (pin, placement) pair, one bar group per pair and
one bar per scheduler (mean over repetitions, min-max bars), for the largest thread
count of the first scene. Right: the local-access ratio (fraction of memory accesses
served by the refiner's own NUMA node: tasks whose receiver lives there), from the
local_access_ratio column of runs.csv; a panel without data says so instead of drawing zeros,
and on a machine with one NUMA node (manifest.json's topology) a note says why every
ratio is 1.0. One legend (the schedulers) above both panels; the pairs' labels are
slanted so that neighbours do not run into each other.
Usage: numa.py RESULT_DIR [--out-dir DIR] [--size page|column] [--caption-in-image]
"""
import common

args = common.parse_args(__doc__)
runs, iterations, manifest = common.load_result(args.result_dir)
scene = common.unique(runs, "scene")[0]
threads = max(common.unique(runs, "threads"))
rows = [r for r in runs if r["scene"] == scene and r["threads"] == threads]
pairs = sorted({(r["pin"], r["placement"]) for r in rows})
schedulers = common.unique(rows, "scheduler")
fig, (a, b) = common.figure(1, 2)
width = 0.8 / max(1, len(schedulers))
nodes = manifest.get("topology", {}).get("numa_nodes")
have_ratio = any(common.is_finite(r.get("local_access_ratio")) for r in rows)
for panel, column in ((a, "refine_wall_s"), (b, "local_access_ratio")):
    if column == "local_access_ratio" and not have_ratio:
        panel.text(0.5, 0.5, "local-access ratio:\nno data in runs.csv (not measured)",
                   ha="center", va="center", transform=panel.transAxes)
        panel.set_xticks([])
        panel.set_yticks([])
        continue
    stats = common.mean_by(rows, ("pin", "placement", "scheduler"), column)
    top = max([v[2] for v in stats.values()] + [0])
    for i, s in enumerate(schedulers):
        xs, means, err = [], [], [[], []]
        for j, pair in enumerate(pairs):
            if pair + (s,) in stats:
                m, lo, hi = stats[pair + (s,)]
                xs.append(j + (i - (len(schedulers) - 1) / 2) * width)
                means.append(m)
                err[0].append(m - lo)
                err[1].append(hi - m)
        panel.bar(xs, means, width, yerr=err, capsize=2, label=s)
    panel.set_xticks(range(len(pairs)))
    panel.set_xticklabels([f"{p}\n{q}" for p, q in pairs], fontsize=8, rotation=45,
                          ha="right", rotation_mode="anchor")
    panel.set_xlabel("thread pinning / memory placement")
    panel.set_ylim(0, 1.05 * top if top > 0 else 1)
    panel.grid(True, axis="y", alpha=0.3)
    if column == "local_access_ratio" and nodes == 1:
        panel.text(0.5, 0.5, "this machine has one NUMA node: every task's receiver is on\n"
                   "the refiner's node, so every ratio is 1.0 (multi-node studies:\n"
                   "HWLOC_SYNTHETIC or HWLOC_XMLFILE, see docs/numa.md)",
                   ha="center", va="center", fontsize=8, transform=panel.transAxes,
                   bbox={"facecolor": "white", "alpha": 0.85, "edgecolor": "grey"})
a.set_ylabel(f"refinement wall time (s), {threads} threads")
a.set_title(common.scene_label(scene))
b.set_ylabel("local-access ratio (fraction of accesses)")
b.set_title("memory locality")
common.legend_above(fig, a, title="scheduler")
common.save(fig, args.out_dir, "numa",
            common.caption(manifest, rows, "NUMA pinning and placement"))
