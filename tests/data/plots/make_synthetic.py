#!/usr/bin/env python3
"""Writes the small synthetic result folders the plot tests draw (tests/data/plots/).

Each folder has a runs.csv, an iterations.csv and a manifest.json shaped like
`hrad experiment` writes them, with made-up but plausible numbers: time falls as
1/threads plus overhead, links grow per iteration. Only the columns the plots read
(and the identity columns) are written; the plots look columns up by name.
Run it from anywhere to regenerate: python3 tests/data/plots/make_synthetic.py
"""
import csv
import itertools
import json
import os

HERE = os.path.dirname(os.path.abspath(__file__))
RUN_COLS = ["config", "point", "repetition", "scene", "swept", "scheduler", "block_size",
            "threads", "pin", "placement", "eps", "wall_s", "refine_wall_s", "refine_cpu_s",
            "links", "elements", "bytes_total", "tasks", "scheduler_ops", "steals", "idle_s",
            "lock_wait_scheduler_s", "lock_wait_element_s", "lock_wait_link_s",
            "lock_wait_total_s", "peak_parallelism", "local_access_ratio", "iterations_run"]
IT_COLS = RUN_COLS[:11] + ["iteration", "refine_wall_s", "refine_cpu_s", "links_created",
                           "links", "elements", "bytes_elements", "bytes_links", "bytes_total",
                           "peak_rss_bytes", "tasks", "local_access_ratio"]


def write(name, scenes, sweep, reps=2, fixed=None):
    folder = os.path.join(HERE, name)
    os.makedirs(folder, exist_ok=True)
    base = {"scheduler": "blocked", "block_size": 10, "threads": 1, "pin": "none",
            "placement": "first-touch", "eps": 0.0001}
    base.update(fixed or {})
    keys = list(sweep)
    runs, its = [], []
    point = 0
    for scene_no, scene in enumerate(scenes):
        for values in itertools.product(*(sweep[k] for k in keys)):
            o = dict(base, **dict(zip(keys, values)))
            swept = " ".join(f"{k}={v}" for k, v in zip(keys, values))
            p = o["threads"]
            overhead = {"stack": 0.05, "fifo": 0.06, "priority": 0.08, "blocked": 0.01,
                        "stealing": 0.02}[o["scheduler"]] / (1 + o["block_size"] / 10)
            for rep in range(reps):
                jitter = 1 + 0.02 * rep
                ident = ["synthetic", point, rep, scene, swept] + [o[k] for k in
                         ("scheduler", "block_size", "threads", "pin", "placement", "eps")]
                cpu_total, wall_total, links = 0, 0, 0
                for it in range(1, 5):
                    cpu = (10 + 5 * scene_no) * it * (1 + overhead * p) * jitter
                    wall = cpu / p
                    created = 1000 * (scene_no + 1) * it
                    links += created
                    cpu_total += cpu
                    wall_total += wall
                    its.append(ident + [it, wall, cpu, created, links, links // 3, links * 16,
                                        links * 48, links * 64, 2**27 + links * 64, links,
                                        0.9 if o["pin"] != "none" else 0.5])
                runs.append(ident + [wall_total * 1.1, wall_total, cpu_total, links, links // 3,
                                     links * 64, links * 2, links // 5,
                                     links // 10 if o["scheduler"] == "stealing" else 0,
                                     0.01 * p, 0.001 * p * (o["scheduler"] != "stealing"),
                                     0.0005 * p, 0.0002 * p, 0.0017 * p, p,
                                     0.9 if o["pin"] != "none" else 0.5, 4])
            point += 1
    with open(os.path.join(folder, "runs.csv"), "w", newline="") as f:
        csv.writer(f, lineterminator="\n").writerows([RUN_COLS] + runs)
    with open(os.path.join(folder, "iterations.csv"), "w", newline="") as f:
        csv.writer(f, lineterminator="\n").writerows([IT_COLS] + its)
    manifest = {
        "experiment": {"name": name, "config_file": f"experiments/configs/{name}.json",
                       "quick": False, "sets": [], "repetitions": reps},
        "hrad": {"version": "0.1.0", "git_revision": "synthetic"},
        "machine": {"hostname": "synthetic-host", "cpu": "a made-up 64-core machine",
                    "pus_online": 64},
        "status": "complete",
    }
    with open(os.path.join(folder, "manifest.json"), "w") as f:
        json.dump(manifest, f, indent=2)
        f.write("\n")


PAPER = ["builtin:office", "builtin:lab", "builtin:cabin"]
write("fig4-cpu-time", PAPER, {"threads": [1, 2, 4, 8]})
write("fig5-speedup", PAPER, {"threads": [1, 2, 4, 8]})
write("fig6-memory", PAPER, {"threads": [1]}, reps=1)
write("fig7-block-size", ["builtin:office"], {"block_size": [1, 10, 100], "threads": [1, 2, 4, 8]})
write("schedulers", ["builtin:office"],
      {"scheduler": ["stack", "fifo", "priority", "blocked", "stealing"], "threads": [1, 2, 4, 8]})
write("numa", ["builtin:office"],
      {"pin": ["none", "compact", "scatter"], "placement": ["first-touch", "interleave"],
       "scheduler": ["blocked", "stealing"]}, fixed={"threads": 8})

# A simulated speedup file as `hrad simulate --out` writes it (per iteration and "all";
# measured rows are not drawn).
with open(os.path.join(HERE, "fig5-speedup", "simulated.csv"), "w", newline="") as f:
    w = csv.writer(f, lineterminator="\n")
    w.writerow(["kind", "scheduler", "block_size", "procs", "iteration", "time_s", "speedup",
                "source"])
    for procs in (1, 2, 4, 8, 16, 32, 64):
        s = procs / (1 + 0.004 * procs)
        w.writerow(["simulated", "blocked", 10, procs, 1, 10 / s, s * 0.9, "cabin.trace"])
        w.writerow(["simulated", "blocked", 10, procs, "all", 40 / s, s, "cabin.trace"])
    w.writerow(["measured", "blocked", 10, 2, "all", 21, "", "cabin.trace"])


def write_accuracy(name="accuracy-time"):
    """Error falls and time grows as eps and min_area shrink (accuracy_time.py)."""
    folder = os.path.join(HERE, name)
    os.makedirs(folder, exist_ok=True)
    cols = ["config", "point", "repetition", "scene", "swept", "oracle", "eps", "min_area",
            "visibility_rays", "wall_s", "links", "elements", "bytes_total", "probe_err_mean",
            "probe_err_max", "probe_err_rms", "probe_s"]
    rows, point = [], 0
    for scene_no, scene in enumerate(["builtin:cornell", "builtin:office"]):
        for oracle, eps, area, rays in itertools.product(
                ["bf", "error"], [1e-2, 1e-3, 1e-4], [1e-3, 1e-4], [1, 4]):
            links = int((1 + scene_no) * 200 / eps ** 0.5 * (1 + 0.1 * rays)
                        * (1.3 if oracle == "error" else 1))
            wall = links * 2e-6 * (1 + 0.2 * rays)
            err = (0.02 + 2 * eps ** 0.5 + 3 * area) * (0.8 if oracle == "error" else 1) \
                / (1 + 0.05 * rays)
            swept = f"oracle={oracle} eps={eps} min_area={area} visibility_rays={rays}"
            rows.append(["synthetic", point, 0, scene, swept, oracle, eps, area, rays, wall,
                         links, links // 4, links * 40, err, 2 * err, 1.2 * err, wall / 10])
            point += 1
    with open(os.path.join(folder, "runs.csv"), "w", newline="") as f:
        csv.writer(f, lineterminator="\n").writerows([cols] + rows)
    # The cornell's cached reference (as `hrad experiment` keeps it): 4 probes at a
    # relative standard error of 0.5 % (channel of the largest E).
    with open(os.path.join(folder, "reference-builtin_cornell.csv"), "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["x", "y", "z", "nx", "ny", "nz", "E_r", "E_g", "E_b", "SE_r", "SE_g", "SE_b",
                    "samples"])
        for k in range(4):
            e = 1.0 + k
            w.writerow([k, 0, 0, 0, 1, 0, e, e / 2, e / 4, e * 0.005, e * 0.004, e * 0.003, 1000])
    manifest = {
        "experiment": {"name": name, "config_file": f"experiments/configs/{name}.json",
                       "quick": False, "sets": [], "repetitions": 1},
        "hrad": {"version": "0.1.0", "git_revision": "synthetic"},
        "machine": {"hostname": "synthetic-host", "cpu": "a made-up 64-core machine",
                    "pus_online": 64},
        "status": "complete",
    }
    with open(os.path.join(folder, "manifest.json"), "w") as f:
        json.dump(manifest, f, indent=2)
        f.write("\n")


write_accuracy()
