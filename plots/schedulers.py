#!/usr/bin/env python3
"""All schedulers side by side.

Six panels against refiner threads, each titled with its quantity and the scene, one
line per scheduler (and per other swept value, e.g. block size); one figure per scene
(NAME-<i>.png when there are several): refinement wall time, speedup T(1)/T(P) (same scheduler),
time waiting on the scheduler lock, time waiting on element and link locks, refiner
idle time, and tasks stolen (stealing) per iteration sum. All from runs.csv.
Usage: schedulers.py RESULT_DIR [--out-dir DIR] [--size page|column] [--caption-in-image]
"""
import common

PANELS = [
    ("refine_wall_s", "refinement wall time (s)", "refinement time"),
    ("speedup", "speedup T(1) / T(P)", "speedup"),
    ("lock_wait_scheduler_s", "summed over refiners (s)", "scheduler lock wait"),
    ("lock_wait_data_s", "summed over refiners (s)", "element + link lock wait"),
    ("idle_s", "summed over refiners (s)", "refiner idle time"),
    ("steals", "tasks stolen", "tasks stolen (stealing)"),
]

args = common.parse_args(__doc__)
runs, iterations, manifest = common.load_result(args.result_dir)
for r in runs:
    r["variant"] = common.variant(r, ("threads", "scheduler"))
    r["lock_wait_data_s"] = (r["lock_wait_element_s"] or 0) + (r["lock_wait_link_s"] or 0)
scenes = common.unique(runs, "scene")
for n, scene in enumerate(scenes):
    rows = [r for r in runs if r["scene"] == scene]
    base = common.mean_by(rows, ("scheduler", "variant", "threads"), "refine_wall_s")
    for r in rows:
        one = base.get((r["scheduler"], r["variant"], 1))
        r["speedup"] = one[0] / r["refine_wall_s"] if one and r["refine_wall_s"] else None
    fig, axes = common.figure(2, 3)
    for ax, (column, ylabel, title) in zip(axes, PANELS):
        stats = common.mean_by(rows, ("scheduler", "variant", "threads"), column)
        for key in sorted({k[:2] for k in stats}, key=str):
            xs = sorted(k[2] for k in stats if k[:2] == key)
            common.errorbar(ax, xs, [stats[key + (t,)] for t in xs],
                            label=key[0] + (f", {key[1]}" if key[1] else ""))
        common.threads_axis(ax, common.unique(rows, "threads"))
        ax.set_ylabel(ylabel)
        ax.set_ylim(bottom=0)
        ax.set_title(f"{title}: {common.scene_label(scene)}")
    common.legend_above(fig, axes[0])
    name = "schedulers" if len(scenes) == 1 else f"schedulers-{n + 1}"
    common.save(fig, args.out_dir, name,
                common.caption(manifest, rows, "Schedulers side by side"))
