#!/usr/bin/python3
# Usage: python3 docs/ablation/repeats.py ABLATION_OUT_DIR (reads its jobs/): prints the table of docs/ablation/README.md.
# Share of NBV views within 0.1 m of an earlier view of the same plant run, per configuration.
import json, pathlib, sys, collections, math
root = pathlib.Path(sys.argv[1]) / 'jobs'
out = collections.OrderedDict()
for cfg in sorted(root.iterdir()):
    near = tot = empty = 0
    for f in cfg.glob('*.json'):
        j = json.loads(f.read_text())
        prev = []
        for s in j['steps']:
            if s.get('source') == 'empty': empty += 1
            if 'pose' not in s: continue
            p = s['pose']['position']
            if s.get('source') == 'nbv':
                tot += 1
                if any(math.dist(p, q) < 0.1 for q in prev): near += 1
            prev.append(p)
    if tot: out[cfg.name] = (near / tot, tot, empty)
print('| configuration | NBV views within 0.1 m of an earlier view | NBV views | empty rounds |')
print('|---|---|---|---|')
for k, (r, t, e) in out.items(): print(f'| {k} | {100*r:.1f} % | {t} | {e} |')
