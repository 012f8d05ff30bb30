#!/usr/bin/env python3
"""Tracks each frame of a finished run again, alone, from that run's previous frame.

A change to one frame moves where later frames re-sample, so two whole runs of a change to the
tracker differ by a point or two of carried share whatever the change does. Started from the same
tracked frame j - 1, two builds differ on frame j by the change alone. The means over many frames
say what a change does (docs/performance.md, "Whole runs cannot judge a graft change").

usage: frame_by_frame.py SURFTRACK RUN INPUT SCRATCH FIRST LAST

SURFTRACK  the surftrack binary to measure
RUN        a finished `surftrack track` output folder (the fixed states)
INPUT      the input the run was made from, as the run was given it (its track.json lists it)
SCRATCH    a folder for the resumed runs (created; each frame's is removed once read)
FIRST LAST the frames to track again (1 <= FIRST <= LAST < the run's frame count)

Prints, per frame, the share carried over, the vertices the sub-grid match lost, and the frame's
and the sub-grid match's milliseconds; then their means.
"""
import json
import os
import shutil
import subprocess
import sys


def main():
    if len(sys.argv) != 7:
        sys.exit(__doc__)
    binary, run, source, scratch = sys.argv[1:5]
    first, last = int(sys.argv[5]), int(sys.argv[6])
    state = json.load(open(os.path.join(run, 'track.json')))
    if not 1 <= first <= last < state['completed']:
        sys.exit(f'frames {first}..{last} are not within 1..{state["completed"] - 1}')
    rows = []
    for j in range(first, last + 1):
        out = os.path.join(scratch, f'frame_{j:04d}')
        shutil.rmtree(out, ignore_errors=True)
        for part in ('frames', 'events'):
            os.makedirs(os.path.join(out, part))
        for i in range(j):
            shutil.copy(os.path.join(run, 'frames', f'frame_{i:04d}.ply'), os.path.join(out, 'frames'))
            shutil.copy(os.path.join(run, 'events', f'{i:04d}.events'), os.path.join(out, 'events'))
        resumed = dict(state)
        resumed.update(
            completed=j,
            frames=state['frames'][:j],
            written=state['written'][:j],
            next_id=state['written'][j - 1]['next_id'],
            input=state['input'][:j + 1],
        )
        with open(os.path.join(out, 'track.json'), 'w') as f:
            json.dump(resumed, f)
        done = subprocess.run(
            [binary, 'track', source, '-o', out, '--resume', '--backend', 'cpu', '-q',
             '--frames', str(j + 1)],
            capture_output=True, text=True)
        if done.returncode != 0:
            sys.exit(f'frame {j}: {done.stderr.strip()}')
        frame = json.load(open(os.path.join(out, 'summary.json')))['per_frame'][-1]
        row = (frame['carried'], frame['churn']['subgrid']['lost'],
               frame['times']['total'], frame['times']['reconcile'])
        rows.append(row)
        print(j, f'{100 * row[0]:.2f}%', row[1], f'{row[2]:.0f} ms', f'{row[3]:.0f} ms', flush=True)
        shutil.rmtree(out)
    n = len(rows)
    print(f'mean carried {100 * sum(r[0] for r in rows) / n:.2f}%, lost to the sub-grid match '
          f'{sum(r[1] for r in rows)}, {sum(r[2] for r in rows) / n:.0f} ms per frame, sub-grid '
          f'{sum(r[3] for r in rows) / n:.0f} ms')


if __name__ == '__main__':
    main()
