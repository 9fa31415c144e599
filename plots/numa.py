#!/usr/bin/env python3
"""NUMA: thread pinning x memory placement x scheduler.

Left: refinement wall time of every (pin, placement) pair, one bar group per pair and
one bar per scheduler (mean over repetitions, min-max bars), for the largest thread
count of the first scene. Right: the local-access ratio (fraction of memory accesses
served by the refiner's own NUMA node: tasks whose receiver lives there), from the
local_access_ratio column of runs.csv; a panel without data says so instead of drawing zeros.
Usage: numa.py RESULT_DIR [--out-dir DIR]
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
have_ratio = any(common.is_finite(r.get("local_access_ratio")) for r in rows)
for panel, column in ((a, "refine_wall_s"), (b, "local_access_ratio")):
    if column == "local_access_ratio" and not have_ratio:
        panel.text(0.5, 0.5, "local-access ratio:\nno data in runs.csv (not measured)",
                   ha="center", va="center", transform=panel.transAxes)
        panel.set_xticks([])
        panel.set_yticks([])
        continue
    stats = common.mean_by(rows, ("pin", "placement", "scheduler"), column)
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
    panel.set_xticklabels([f"pin {p}\n{q}" for p, q in pairs], fontsize=7)
    panel.set_xlabel("thread pinning / memory placement")
    panel.legend(fontsize=7, title="scheduler", title_fontsize=7)
    panel.grid(True, axis="y", alpha=0.3)
a.set_ylabel(f"refinement wall time (s), {threads} threads")
a.set_title(common.scene_label(scene))
b.set_ylabel("local-access ratio (fraction of accesses)")
b.set_title("memory locality")
common.save(fig, args.out_dir, "numa",
            common.caption(manifest, rows, "NUMA pinning and placement"))
