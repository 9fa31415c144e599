#!/usr/bin/env python3
"""MPI experiment sweeps (experiments/harness/mpi_sweep.h), end to end with mpirun.

usage: mpi_experiment_test.py CASE HRAD MPIEXEC MPI_BUILT CONFIG WORKDIR

CASE is one of
  rows     `mpirun -np 3` gives the serial run's rows (timing columns apart) in the
           serial order, and a manifest that lists every rank;
  survive  with `mpirun --enable-recovery`, a worker SIGKILLed in the middle of a run is
           reported, its run re-queued, and the experiment completes on the others;
  resume   without it, killing a worker ends the whole job; `--resume` on 2 ranks then
           finishes it with no row duplicated or missing.
Exits 77 (ctest's SKIP_RETURN_CODE) when hrad was built without MPI or there is no
mpirun. Needs only the Python standard library.
"""
import csv
import json
import os
import shutil
import signal
import subprocess
import sys
import time

SKIP = 77
# Columns that measure time, the process or the machine's load rather than the
# solution. scheduler_ops counts take attempts too, which differ between two serial
# runs of one point.
VOLATILE = {"started_at", "peak_rss_bytes", "scheduler_ops", "load_avg"}


def volatile(column):
    return column in VOLATILE or column.endswith("_s") or column.endswith("_ns")


def fail(message):
    print(f"FAIL: {message}", file=sys.stderr)
    sys.exit(1)


def read_rows(folder, name):
    with open(os.path.join(folder, name), newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        fail(f"{folder}/{name} is empty")
    header, body = rows[0], rows[1:]
    keep = [i for i, c in enumerate(header) if not volatile(c)]
    return [header[i] for i in keep], [[r[i] for i in keep] for r in body]


def run_ids(folder):
    header, rows = read_rows(folder, "runs.csv")
    p, r = header.index("point"), header.index("repetition")
    return [(int(row[p]), int(row[r])) for row in rows]


def same_rows(reference, folder, what):
    for name in ("runs.csv", "iterations.csv"):
        h1, a = read_rows(reference, name)
        h2, b = read_rows(folder, name)
        if h1 != h2:
            fail(f"{what}: {name} headers differ")
        if len(a) != len(b):
            fail(f"{what}: {name} has {len(b)} rows, the serial run {len(a)}")
        for i, (x, y) in enumerate(zip(a, b)):
            if x != y:
                cols = [h1[j] for j in range(len(x)) if x[j] != y[j]]
                fail(f"{what}: {name} row {i + 1} differs from the serial run in {cols}")
    ids = run_ids(folder)
    if len(set(ids)) != len(ids):
        fail(f"{what}: a run appears twice in runs.csv: {ids}")


def manifest(folder):
    with open(os.path.join(folder, "manifest.json")) as f:
        return json.load(f)


class Job:
    """mpirun in its own process group, so that the test can end what is left of it."""

    def __init__(self, argv, env):
        self.log = open(os.path.join(WORK, f"mpirun-{int(time.time() * 1000)}.log"), "w+")
        self.proc = subprocess.Popen(argv, env=env, stdout=self.log, stderr=subprocess.STDOUT,
                                     start_new_session=True)

    def wait(self, timeout):
        try:
            return self.proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(self.proc.pid, signal.SIGKILL)
            self.proc.wait()
            fail(f"mpirun did not end within {timeout} s:\n{self.output()}")

    def output(self):
        self.log.flush()
        self.log.seek(0)
        return self.log.read()

    def rank_pid(self, rank):
        """The pid of MPI rank `rank` among mpirun's children, or None."""
        for entry in os.listdir("/proc"):
            if not entry.isdigit():
                continue
            try:
                with open(f"/proc/{entry}/stat") as f:
                    ppid = int(f.read().rsplit(")", 1)[1].split()[1])
                if ppid != self.proc.pid:
                    continue
                with open(f"/proc/{entry}/environ", "rb") as f:
                    env = f.read().split(b"\0")
            except (OSError, IndexError, ValueError):
                continue
            if f"OMPI_COMM_WORLD_RANK={rank}".encode() in env:
                return int(entry)
        return None


def mpirun(np, args, extra=()):
    return [MPIEXEC, "--oversubscribe", "--bind-to", "none", *extra, "-np", str(np), HRAD,
            "experiment", CONFIG, "--no-plot", *args]


def serial_reference():
    out = os.path.join(WORK, "serial")
    shutil.rmtree(out, ignore_errors=True)
    subprocess.run([HRAD, "experiment", CONFIG, "--no-plot", "--quiet", "--out", out], check=True)
    return out


def wait_for_rows(job, folder, n, timeout):
    """Waits until runs.csv holds at least `n` rows while the job still runs."""
    end = time.time() + timeout
    while time.time() < end:
        if job.proc.poll() is not None:
            fail(f"mpirun ended before {n} rows were written:\n{job.output()}")
        try:
            if len(run_ids(folder)) >= n:
                return
        except (OSError, SystemExit):
            pass
        time.sleep(0.02)
    fail(f"no {n} rows in {folder} after {timeout} s")


def kill_worker_mid_run(job, folder):
    wait_for_rows(job, folder, 1, 60)
    pid = job.rank_pid(1)
    if pid is None:
        fail("rank 1 not found among mpirun's children")
    os.kill(pid, signal.SIGKILL)
    return len(run_ids(folder))


def case_rows(env):
    reference = serial_reference()
    out = os.path.join(WORK, "np3")
    shutil.rmtree(out, ignore_errors=True)
    job = Job(mpirun(3, ["--out", out]), env)
    if job.wait(120) != 0:
        fail(f"mpirun -np 3 failed:\n{job.output()}")
    same_rows(reference, out, "mpirun -np 3")
    m = manifest(out)
    if m["status"] != "complete" or len(m.get("mpi", [])) != 1:
        fail(f"manifest: status {m['status']}, mpi sessions {len(m.get('mpi', []))}")
    s = m["mpi"][0]
    ranks = sorted(r["rank"] for r in s["ranks_info"])
    if ranks != [0, 1, 2] or s["workers"] != 2:
        fail(f"manifest lists ranks {ranks}, {s['workers']} workers")
    workers = [r for r in s["ranks_info"] if r["role"] == "worker"]
    if any(not r["host"] or not r["cpus"] or "omp_max_threads" not in r for r in workers):
        fail(f"a worker's host, CPUs or threads are missing: {workers}")
    cpus = [r["cpus"] for r in workers]
    if os.cpu_count() and os.cpu_count() >= 2 and len(set(cpus)) != 2:
        fail(f"the two workers on this host do not have their own cores: {cpus}")
    if sorted({r["rank"] for r in s["runs"]}) != [1, 2]:
        fail(f"not both workers ran runs: {s['runs']}")
    if len(s["runs"]) != len(run_ids(out)):
        fail("manifest's runs and runs.csv disagree")
    print(f"rows: {len(run_ids(out))} runs identical to serial; hand-off "
          f"{1000 * s['overhead']['handoff_wait_mean_s']:.2f} ms mean")


def case_survive(env):
    reference = serial_reference()
    out = os.path.join(WORK, "survive")
    shutil.rmtree(out, ignore_errors=True)
    job = Job(mpirun(3, ["--out", out, "--worker-timeout", "2"], ["--enable-recovery"]), env)
    before = kill_worker_mid_run(job, out)
    rc = job.wait(120)
    log = job.output()
    if rc != 0:
        fail(f"mpirun --enable-recovery exited {rc} after a worker was killed:\n{log}")
    same_rows(reference, out, "after a worker was killed")
    m = manifest(out)
    lost = m["mpi"][0]["lost_ranks"]
    if m["status"] != "complete" or [l["rank"] for l in lost] != [1]:
        fail(f"manifest: status {m['status']}, lost ranks {lost}")
    if not lost[0]["requeued"] or lost[0]["run"] is None:
        fail(f"rank 1's run was not re-queued: {lost}")
    if "taken for dead" not in log:
        fail(f"the lost rank is not reported:\n{log}")
    print(f"survive: rank 1 killed after {before} rows; run {lost[0]['run']} re-queued; "
          f"{len(run_ids(out))} runs, identical to serial")


def case_resume(env):
    reference = serial_reference()
    out = os.path.join(WORK, "resume")
    shutil.rmtree(out, ignore_errors=True)
    job = Job(mpirun(3, ["--out", out]), env)
    before = kill_worker_mid_run(job, out)
    rc = job.wait(120)
    if rc == 0:
        fail("killing a rank did not end the job (OpenMPI without --enable-recovery)")
    done = run_ids(out)
    if len(done) >= len(run_ids(reference)):
        fail("the killed job finished every run: the kill came too late to test resume")
    if len(set(done)) != len(done):
        fail(f"a run appears twice after the kill: {done}")
    job = Job(mpirun(2, ["--resume", out]), env)
    if job.wait(120) != 0:
        fail(f"--resume on 2 ranks failed:\n{job.output()}")
    same_rows(reference, out, "after --resume")
    m = manifest(out)
    if m["status"] != "complete" or len(m["mpi"]) != 2 or m["mpi"][1]["ranks"] != 2:
        fail(f"manifest after resume: status {m['status']}, sessions "
             f"{[s['ranks'] for s in m.get('mpi', [])]}")
    print(f"resume: job ended (rc {rc}) with {len(done)} rows (rank 1 killed after {before}); "
          f"--resume on 2 ranks completed {len(run_ids(out))}, identical to serial")


def main():
    global HRAD, MPIEXEC, CONFIG, WORK
    if len(sys.argv) != 7:
        print(__doc__, file=sys.stderr)
        return 2
    case, HRAD, MPIEXEC, built, CONFIG, WORK = sys.argv[1:]
    if built.upper() not in ("ON", "TRUE", "1", "YES"):
        print("SKIP: hrad was built without MPI (HRAD_MPI)")
        return SKIP
    if not MPIEXEC or not shutil.which(MPIEXEC):
        print(f"SKIP: no mpirun ({MPIEXEC!r})")
        return SKIP
    os.makedirs(WORK, exist_ok=True)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    {"rows": case_rows, "survive": case_survive, "resume": case_resume}[case](env)
    return 0


if __name__ == "__main__":
    sys.exit(main())
