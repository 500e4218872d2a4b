#!/usr/bin/env python3
"""The views that saw each fruit, counted from a mission's dataset export (`canopy mission
--export DIR`): for each successful view (transforms.json's frames, in the order they were
taken), the fruit instances of its instance image (uint16, id + 1, 0 = none) whose pixels have
a depth (depth/*.npy, 0 = invalid: outside the camera's range). Prints {"fruit id": views}.

An independent computation of report.html's fruit-table column "views" (jobs::set_fruit_views
counts MapReplay::instances_seen, recorded from the same frames in the mission's memory):
run_report_browser_test.sh hands it to report_browser.py --fruit-views.

  fruit_views.py EXPORT_DIR > views.json     (Debian's python3: numpy and PIL)
"""
import json
import os
import sys

import numpy as np
from PIL import Image


def fruit_views(folder):
    frames = json.load(open(os.path.join(folder, "transforms.json")))["frames"]
    views = {}
    for f in frames:
        ids = np.asarray(Image.open(os.path.join(folder, f["instance_path"])), dtype=np.int64)
        depth = np.load(os.path.join(folder, f["depth_npy_path"]))
        if ids.shape != depth.shape:
            raise SystemExit(f"{f['instance_path']}: {ids.shape} pixels against a depth of {depth.shape}")
        for i in np.unique(ids[depth > 0]):
            if i:
                views[int(i) - 1] = views.get(int(i) - 1, 0) + 1
    return views, len(frames)


def main(argv):
    if len(argv) != 2:
        print(__doc__)
        return 2
    views, n = fruit_views(argv[1])
    print(json.dumps({"frames": n, "views": {str(k): v for k, v in sorted(views.items())}}))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
