#!/usr/bin/env python3
"""Identity check for a change meant to keep behaviour (a redesign, a refactor): solves
the same scenes with two hrad binaries and compares what a run computes.

usage: tools/identity-check.py OLD_HRAD NEW_HRAD [--scenes S,S] [--threads 1,2]
                               [--schedulers all|A,B] [--out DIR] [-- SOLVE OPTIONS...]
  e.g. git worktree add /tmp/base HEAD~1 && cmake -S /tmp/base -B /tmp/base/build -G Ninja \\
         && cmake --build /tmp/base/build --target hrad
       tools/identity-check.py /tmp/base/build/hrad build/hrad

For every scene, scheduler and thread count it solves with both binaries (one after
the other) and compares:
  - solution.ply byte for byte (every leaf's radiosity; the same at 1 and 2 threads
    from run to run),
  - every figure of stats.json that does not measure time or depend on which thread
    did what (per-refiner counters, local/remote task counts), exactly; at more than
    one thread float figures within 1e-9 relative (sums over links, whose order
    follows the refiners: they differ between two runs of one binary too).
Figures only NEW has (a key added to stats.json) are listed apart ("added in NEW") and
are no difference. It prints one line per case and exits 1 when any case differs. Defaults: scenes
builtin:cornell and builtin:office, every registered scheduler (from `hrad solve
--help`), 1 and 2 threads.
"""
import argparse
import filecmp
import json
import os
import re
import subprocess
import sys
import tempfile

# What in stats.json is not the computation's result: times (keys ending in _s or _ns),
# the run's provenance and placement, and what depends on which thread did what.
NOT_RESULTS = {'started_at', 'build', 'host', 'version', 'git_revision', 'command_line',
               'numa', 'placement', 'placement_check', 'pin', 'bytes_per_node', 'refiners',
               'lock_wait_s', 'tasks_local', 'tasks_remote', 'steals', 'scheduler_ops',
               'peak_parallelism', 'peak_rss_bytes', 'local_access_ratio'}

# With more than one thread the refiners append a receiver's links in the order they
# come to them, so sums over links (max_change, row-sum statistics) can differ in their
# last bits from run to run of one binary: such a float figure counts as the same
# within this relative difference. Integers, strings and every figure at one thread
# must be equal.
PARALLEL_ROUND_OFF = 1e-9


def same(a, b, threads):
    if a == b:
        return True
    if threads > 1 and isinstance(a, float) and isinstance(b, float):
        return abs(a - b) <= PARALLEL_ROUND_OFF * max(abs(a), abs(b))
    return False


def is_result(key):
    return key not in NOT_RESULTS and not key.endswith(('_s', '_ns'))


def figures(d, path=''):
    """Flattens stats.json into {dotted.path: value}, leaving out what is not a result."""
    out = {}
    if isinstance(d, dict):
        for k, v in d.items():
            if is_result(k):
                out.update(figures(v, f'{path}{k}.'))
    elif isinstance(d, list):
        for i, v in enumerate(d):
            out.update(figures(v, f'{path}{i}.'))
    else:
        out[path.rstrip('.')] = d
    return out


def registered_schedulers(hrad):
    text = subprocess.run([hrad, 'solve', '--help'], capture_output=True, text=True).stdout
    m = re.search(r'--scheduler NAME\s+.*?by name: ([a-z_, ]+)', text)
    if not m:
        sys.exit('identity-check: cannot read the scheduler names from `hrad solve --help`')
    return [s.strip() for s in m.group(1).split(',')]


def main():
    argv = sys.argv[1:]
    extra = []
    if '--' in argv:
        extra = argv[argv.index('--') + 1:]
        argv = argv[:argv.index('--')]
    ap = argparse.ArgumentParser(description='Compare two hrad binaries run for run.')
    ap.add_argument('old')
    ap.add_argument('new')
    ap.add_argument('--scenes', default='builtin:cornell,builtin:office')
    ap.add_argument('--threads', default='1,2')
    ap.add_argument('--schedulers', default='all')
    ap.add_argument('--out', default=None, help='scratch folder (default: a fresh temporary one)')
    a = ap.parse_args(argv)
    schedulers = (registered_schedulers(a.new) if a.schedulers == 'all'
                  else a.schedulers.split(','))
    out = a.out or tempfile.mkdtemp(prefix='hrad-identity-')
    differing = 0
    cases = 0
    for scene in a.scenes.split(','):
        for sched in schedulers:
            for threads in a.threads.split(','):
                runs = []
                for tag, binary in (('old', a.old), ('new', a.new)):
                    name = re.sub(r'[^A-Za-z0-9]+', '_', scene)
                    folder = os.path.join(out, tag, f'{name}-{sched}-{threads}')
                    os.makedirs(folder, exist_ok=True)
                    subprocess.run([binary, 'solve', scene, '--out', folder, '--scheduler', sched,
                                    '--threads', threads, '--quiet'] + extra, check=True,
                                   stdout=subprocess.DEVNULL)
                    runs.append(folder)
                old = figures(json.load(open(os.path.join(runs[0], 'stats.json'))))
                new = figures(json.load(open(os.path.join(runs[1], 'stats.json'))))
                # Keys only NEW has (a configuration key or statistic added) are listed
                # apart: they are new records, not changed ones.
                added = sorted(set(new) - set(old))
                diff = sorted(k for k in set(old) | set(new)
                              if k not in added and not same(old.get(k), new.get(k), int(threads)))
                same_mesh = filecmp.cmp(os.path.join(runs[0], 'solution.ply'),
                                        os.path.join(runs[1], 'solution.ply'), shallow=False)
                cases += 1
                bad = bool(diff) or not same_mesh
                differing += bad
                print(f'{scene} {sched} {threads} thread(s): links {new.get("totals.links")}, '
                      f'elements {new.get("totals.elements")}, {len(old)} figures '
                      f'{"same" if not diff else "differ: " + ", ".join(diff[:8])}'
                      f'{"; added in NEW: " + ", ".join(added) if added else ""}; solution.ply '
                      f'{"identical" if same_mesh else "DIFFERS"}', flush=True)
    print(f'identity-check: {cases} cases, {differing} with differences (runs in {out})')
    return 1 if differing else 0


if __name__ == '__main__':
    sys.exit(main())
