#!/usr/bin/env python3
"""Where a long mission's memory goes (issue 49): the kernel's resident set (VmRSS) and its peak
(VmHWM) after each stage of one process, as JSON lines.

    PYTHONPATH=build/python python3 tools/mission_memory.py WORLD.yaml world
    PYTHONPATH=build/python python3 tools/mission_memory.py WORLD.yaml render          # + simulator and renderer
    PYTHONPATH=build/python python3 tools/mission_memory.py WORLD.yaml mission STOPS   # + an ours mission, a line per stop

Stages: `import` (the module), `world` (the world generated: plants, triangles, ground-truth
points), `sim+renderer` (the MuJoCo models and the OSMesa context of one render), `progress` (the
mission's resident set as each stop starts: simulator, renderer, truth voxels, evaluator, map,
index) and `mission end`. `canopy bench mission` prints the mission's own holders beside it.
"""
import json
import sys
import time

import numpy as np

import canopy


def status():
    out = {}
    with open('/proc/self/status') as f:
        for line in f:
            key, value = line.split(':', 1)
            if key in ('VmRSS', 'VmHWM'):
                out[key] = int(value.split()[0]) / 1024.0
    return out


def main(argv):
    if len(argv) < 3 or argv[2] not in ('world', 'render', 'mission'):
        print(__doc__, file=sys.stderr)
        return 2
    t0 = time.time()

    def say(stage, **fields):
        s = status()
        print(json.dumps(dict(stage=stage, t=round(time.time() - t0, 1), rss_mb=round(s['VmRSS']),
                              hwm_mb=round(s['VmHWM']), **fields)), flush=True)

    say('import')
    world = canopy.World(argv[1])
    say('world', plants=len(world.plants), triangles=int(world.triangles),
        truth_points=int(np.sum(world.fruits['surface_points'])))
    if argv[2] == 'render':
        world.render(np.eye(4))
        say('sim+renderer')
    elif argv[2] == 'mission':
        settings = canopy.Settings()
        settings.set('mission.stops.count', int(argv[3]) if len(argv) > 3 else 5)

        def progress(line):
            if ': driving' in line:
                say('progress', line=line[:60])

        canopy.run_mission(world, settings, method='ours', seed=1, progress=progress, report=False)
        say('mission end')
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
