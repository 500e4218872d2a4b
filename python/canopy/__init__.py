"""canopy from Python: worlds, maps, planning and the closed-loop mission of canopy's C++ library.

Quick start (docs/python.md)::

    import canopy
    world = canopy.World("worlds/small.yaml")
    result = canopy.run_mission(world, seed=1)
    curve = result.sc_curve()
    print(curve["views"], curve["coverage"])

- Worlds: World (generate from a world file and a seed; plants, fruits and fruit_points are
  the ground truth; render / render_robot give a Frame with rgb, depth, labels, instances).
- Maps: Map (insert a Frame or labelled points; save / load .csm; occupancy, known, entropy,
  class_probabilities, voxels in bulk as numpy arrays; metrics against a World), read_frames.
- Planning: find_clusters, sample_candidates, gains (by name: gain_names()), next_views (as
  `canopy nbv`), Robot (camera_pose, ik, stop_region).
- Missions: run_mission with a Settings bundle and any planner_names() method, or with a
  planner written in Python (planner=f, where f(request: PlannerRequest) returns views).

- ROS 1 bags (canopy.bag, Debian's python3-rosbag): read_bag (a recording as Frames, poses from
  /tf), map_bag (streamed into the run folder `canopy map --frames` writes), record_bag (a
  mission written as a bag while it runs), export_bag (a run folder's bag); `python3 -m canopy
  map-bag` and `export-bag`.
- stop_on_sigterm(): SIGTERM stops canopy's long calls as Ctrl-C does, so they keep their work
  so far (Python's default ends the process at once, saving nothing).

Bad input raises ValueError naming the value. Long calls release the GIL. Arrays handed back
are copies, or read-only views that keep their owner alive.
"""

from . import interrupts

interrupts.note_while_the_command_imports()  # only as `python3 -m canopy`: before the slow imports

from . import _canopy  # noqa: E402
from ._canopy import *  # noqa: E402,F401,F403
from ._canopy import __version__  # noqa: E402,F401  (the C++ package's version)

for _type in list(vars(_canopy).values()):
    if isinstance(_type, type):
        _type.__module__ = __name__  # canopy.World, not canopy._canopy.World, in help() and reprs
del _type

from .bag import BagError, export_bag, map_bag, read_bag, record_bag  # noqa: E402,F401  (ROS imported on use)
from .interrupts import stop_on_sigterm  # noqa: E402,F401
