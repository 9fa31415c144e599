#!/usr/bin/env python3
"""Runs per minute against MPI ranks, and the MPI layer's hand-off time per run.

Reads DIR/scaling.csv and DIR/np<N>/ (tools/mpi-scaling.sh) and writes
DIR/mpi_scaling.pdf, .svg, .png and .caption.txt (or --out-dir).
Usage: mpi_scaling.py DIR [--out-dir DIR] [--size page|column] [--caption-in-image]
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402


def main():
    a = common.parse_args(__doc__.splitlines()[0])
    path = os.path.join(a.result_dir, "scaling.csv")
    if not os.path.exists(path):
        sys.exit(f"mpi_scaling.py: {path}: not found (make it with tools/mpi-scaling.sh)")
    rows = sorted(common.load_csv(path), key=lambda r: r["ranks"])
    if not rows:
        sys.exit(f"mpi_scaling.py: {path}: no rows")
    first = os.path.join(a.result_dir, f"np{rows[0]['ranks']}")
    runs, _, manifest = common.load_result(first)
    pus = manifest.get("machine", {}).get("pus_online", "?")

    fig, (ax, bx) = common.figure(1, 2)
    ranks = [r["ranks"] for r in rows]
    rate = [r["runs_per_min"] for r in rows]
    ax.plot(ranks, rate, marker="o", label="measured")
    ideal = [rows[0]["runs_per_min"] * r["workers"] for r in rows]
    ax.plot(ranks, ideal, linestyle="--", color="gray", label="1 rank x workers")
    for r in rows:
        note = f"{r['workers']} worker{'s' if r['workers'] > 1 else ''}"
        if isinstance(pus, int) and r["ranks"] > pus:
            note += f"\n{r['ranks']} ranks on {pus} PUs"
        last = r is rows[-1]  # its note to the left, inside the panel
        ax.annotate(note, (r["ranks"], r["runs_per_min"]), textcoords="offset points",
                    xytext=(-6 if last else 6, -18 if not last or r["workers"] < 2 else 8),
                    ha="right" if last else "left", va="top" if not last else "bottom",
                    fontsize=7.5)
    ax.set_xlabel("MPI ranks (rank 0 coordinates when ranks > 1)")
    ax.set_ylabel("runs per minute")
    ax.set_xticks(ranks)
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
    common.legend_below(ax)

    mpi = [r for r in rows if r["ranks"] > 1 and common.is_finite(r["handoff_wait_mean_s"])]
    if mpi:
        xs = [r["ranks"] for r in mpi]
        bx.bar(xs, [1000 * r["handoff_wait_mean_s"] for r in mpi], width=0.5, label="mean")
        bx.plot(xs, [1000 * r["handoff_wait_max_s"] for r in mpi], "v", color="black",
                label="max")
        # Each mean's share of a run under its rank count (clear of the bars and marks).
        bx.set_xticks(xs)
        bx.set_xticklabels([f"{r['ranks']}\n{100 * r['handoff_wait_mean_s'] / r['mean_run_s']:.2f}%"
                            f" of a {r['mean_run_s']:.2f} s run" for r in mpi])
        common.legend_below(bx)
    bx.set_xlabel("MPI ranks")
    bx.set_ylabel("hand-off per run (ms)")
    bx.set_title("worker idle from sending a result to its next run")
    bx.grid(True, alpha=0.3, axis="y")

    # The data come from tools/mpi-scaling.sh (one hrad experiment per rank count, under
    # mpirun), not from one `hrad experiment`: its command, with this folder and the
    # config and rank counts of these runs.
    config = common.as_given(manifest.get("experiment", {}).get("config_file") or "CONFIG")
    text = common.caption(manifest, runs, "Experiment runs per minute against MPI ranks")
    lines = text.split("\n")
    lines = [line.replace("mean (bars: min-max)",
                          "one sweep per rank count, timed from launch to exit")
             for line in lines if not line.startswith("Regenerate:")]
    lines.insert(-1, f"Regenerate: tools/mpi-scaling.sh build {common.as_given(a.result_dir)} "
                     f"{config} {' '.join(str(r) for r in ranks)}")
    quick = text.quick
    text = common.Caption("\n".join(lines))
    text.quick = quick
    common.save(fig, a.out_dir, "mpi_scaling", text)


if __name__ == "__main__":
    main()
