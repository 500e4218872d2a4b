#!/usr/bin/env python3
"""A coverage-greedy view planner written in Python, in canopy's closed loop.

At each request it takes the fruit clusters of the map inside the stop's region, samples the
candidate views around each, keeps those the arm can reach and that were neither taken nor
failed before, scores them by how many unknown voxels their rays would see (the "uvc" gain)
and returns the best view of each cluster, best first, up to the stop's budget. Driving, IK and motion
planning, rendering, mapping and the metrics are canopy's.

    PYTHONPATH=build/python python3 examples/python/coverage_greedy.py --world worlds/small.yaml

(after `cmake --install`, PYTHONPATH=<prefix>/lib/python3/dist-packages instead).
"""

import argparse

import numpy as np

import canopy


def coverage_greedy(request):
    """The planner: a canopy.PlannerRequest in, a list of views (dicts with a pose) out."""
    clusters = request.clusters()
    views = []
    for i, centroid in enumerate(clusters["centroid"]):
        reachable = []
        for pose in request.candidates(centroid, cluster=i)["pose"]:
            if request.is_taken(pose):
                continue
            reached = request.reach(pose)  # None, or the pose moved into the workspace and its IK
            # not taken yet, and not a view that failed before (request.outcomes says why)
            if reached is not None and not request.is_taken(reached["pose"]) and not request.is_failed(reached["pose"]):
                reachable.append(reached)
        if not reachable:
            continue
        poses = np.array([r["pose"] for r in reachable])
        unknown = request.gains(poses, np.repeat(centroid[None, :], len(poses), axis=0), gain="uvc")["gain"]
        best = int(np.argmax(unknown))
        if unknown[best] <= 0:
            continue  # nothing left to see of this cluster
        views.append({"pose": reachable[best]["pose"], "joints": reachable[best]["joints"], "target": centroid,
                      "gain": float(unknown[best]), "cluster": i})
    views.sort(key=lambda v: -v["gain"])
    return views[: request.budget]  # an empty list ends the stop


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--world", default="worlds/small.yaml", help="world file (default: %(default)s)")
    parser.add_argument("--views-per-stop", type=int, default=2, help="successful views wanted per stop")
    parser.add_argument("--seed", type=int, default=1, help="mission seed")
    parser.add_argument("--out", help="also write the run folder (views.csv, summary.json, map.csm, ...)")
    args = parser.parse_args()

    world = canopy.World(args.world)
    settings = canopy.Settings().set("mission.loop.views_per_stop", args.views_per_stop)
    result = canopy.run_mission(world, settings, planner=coverage_greedy, seed=args.seed, out=args.out)
    curve = result.sc_curve()
    for views, coverage in zip(curve["views"], curve["coverage"]):
        print(f"view {views}: fruit SC {coverage:.3f}")
    final = result.summary["final"]
    print(f"coverage_greedy: {result.successful_views} of {len(result.views['attempt'])} views successful, "
          f"fruit SC {final['fruit_coverage']:.3f}, entropy {final['fruit_entropy']:.1f} nats")


if __name__ == "__main__":
    main()
