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
    did what (per-refiner counters, local/remote task counts, and at more than one
    thread the last sweep's max_change, whose last bits follow the order in which
    refiners appended links: these differ between two runs of one binary too).
It prints one line per case and exits 1 when any case differs. Defaults: scenes
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

# Keys (or parts of keys) of stats.json that are not the computation's result.
NOT_RESULTS = ('_s', 'wall', 'time', 'rss', 'lock', 'idle', 'busy', 'steal', 'peak', 'wait',
               'revision', 'build', 'host', 'date', 'started_at', 'command', 'version', 'cpu',
               'parallel', 'placement', 'numa', 'per_node', 'pin', 'git', 'flags', 'compiler',
               'scheduler_ops', 'visits', 'handoff', 'refiners', 'tasks_local', 'tasks_remote')


def figures(d, path=''):
    """Flattens stats.json into {dotted.path: value}, leaving out NOT_RESULTS."""
    out = {}
    if isinstance(d, dict):
        for k, v in d.items():
            if not any(t in k for t in NOT_RESULTS):
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
                    folder = os.path.join(out, tag, f'{re.sub(r"[^A-Za-z0-9]+", "_", scene)}-{sched}-{threads}')
                    os.makedirs(folder, exist_ok=True)
                    subprocess.run([binary, 'solve', scene, '--out', folder, '--scheduler', sched,
                                    '--threads', threads, '--quiet'] + extra, check=True,
                                   stdout=subprocess.DEVNULL)
                    runs.append(folder)
                old = figures(json.load(open(os.path.join(runs[0], 'stats.json'))))
                new = figures(json.load(open(os.path.join(runs[1], 'stats.json'))))
                diff = sorted(k for k in set(old) | set(new) if old.get(k) != new.get(k)
                              and not (int(threads) > 1 and k.endswith('max_change')))
                same_mesh = filecmp.cmp(os.path.join(runs[0], 'solution.ply'),
                                        os.path.join(runs[1], 'solution.ply'), shallow=False)
                cases += 1
                bad = bool(diff) or not same_mesh
                differing += bad
                print(f'{scene} {sched} {threads} thread(s): links {new.get("totals.links")}, '
                      f'elements {new.get("totals.elements")}, {len(new)} figures '
                      f'{"same" if not diff else "differ: " + ", ".join(diff[:8])}; solution.ply '
                      f'{"identical" if same_mesh else "DIFFERS"}', flush=True)
    print(f'identity-check: {cases} cases, {differing} with differences (runs in {out})')
    return 1 if differing else 0


if __name__ == '__main__':
    sys.exit(main())
