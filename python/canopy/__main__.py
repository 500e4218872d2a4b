"""python3 -m canopy: the Python package's commands (docs/commands.md#python-commands).

  map-bag BAG --out DIR      map a ROS 1 bag's RGB-D camera into the run folder `canopy map
                             --frames` writes (canopy.bag.map_bag)
  export-bag RUN_DIR OUT.bag write a `canopy mission` run folder as a ROS 1 bag, for RViz and
                             Foxglove (canopy.bag.export_bag)

Bad input prints one line naming the problem and exits with code 2, as the canopy CLI does.
"""

import argparse
import sys


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit code 2 (argparse's code, without the usage block)
        sys.stderr.write(f"canopy: error: {self.prog}: {message}\n")
        sys.exit(2)


def _parser():
    from . import bag

    p = _Parser(prog="python3 -m canopy", description="canopy's Python commands: ROS 1 bags in and out.")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)

    m = sub.add_parser("map-bag", help="map a ROS 1 bag into the run folder `canopy map --frames` writes",
                       description="Maps a bag's RGB-D camera (poses from /tf and /tf_static) into map.csm, map.ply, "
                                   "map.bt, frames.json, run.yaml and settings.yaml (docs/real_robot.md#ros-bags).")
    m.add_argument("bag")
    m.add_argument("--out", required=True, help="output folder")
    m.add_argument("--config", default=None, help="settings bundle (default configs/canopy.yaml)")
    m.add_argument("--seg", choices=["color", "truth"], default=None,
                   help="labels: color (HSV segmentation of --rgb) or truth (the --labels topic); default from config")
    m.add_argument("--pgt", type=float, default=None, help="probability a mask keeps its class (1 = no noise)")
    m.add_argument("--rgb", default=bag.TOPICS["rgb"], help="RGB topic (Image or CompressedImage)")
    m.add_argument("--depth", default=bag.TOPICS["depth"], help="depth topic (16UC1 mm, 32FC1 m, compressedDepth)")
    m.add_argument("--camera-info", default=bag.TOPICS["camera_info"], help="CameraInfo topic")
    m.add_argument("--labels", default=bag.TOPICS["labels"], help="label topic with --seg truth (mono8 class "
                   "indices or rgb8 class colours)")
    m.add_argument("--classes", default=None, help="label classes, comma-separated (default background,leaf,fruit)")
    m.add_argument("--frame", default=None, help="the camera's optical frame (default: the depth images' frame_id)")
    m.add_argument("--world-frame", default=bag.WORLD_FRAME, help="the fixed frame the map is built in")
    m.add_argument("--max-dt", type=float, default=bag.DEFAULT_MAX_DT,
                   help="largest stamp difference of a depth image and its partners, and tf extrapolation [s]")
    m.add_argument("--min-range", type=float, default=None, help="valid depth from [m] (default: the D405's)")
    m.add_argument("--max-range", type=float, default=None, help="valid depth to [m] (default: the D405's)")

    e = sub.add_parser("export-bag", help="write a `canopy mission` run folder as a ROS 1 bag",
                       description="Replays the run from its own records (settings.yaml, the world's spec and the "
                                   "seed in summary.json), checks that the replay's views.csv equals the run's, and "
                                   "writes the bag: wrist images, /tf, the map per view, the views and the true "
                                   "fruits (docs/real_robot.md#ros-bags).")
    e.add_argument("run_dir")
    e.add_argument("bag")
    return p


def main(argv=None):
    args = _parser().parse_args(argv)
    from . import _canopy, bag

    def progress(line):
        sys.stderr.write(line + "\n")

    try:
        if args.command == "map-bag":
            settings = _canopy.Settings(args.config)
            if args.seg is not None:
                settings.set("mapping.extractor.source", args.seg)
            if args.pgt is not None:
                settings.set("mapping.extractor.p_gt", args.pgt)
            classes = args.classes.split(",") if args.classes else None
            r = bag.map_bag(args.bag, args.out, settings, rgb=args.rgb, depth=args.depth,
                            camera_info=args.camera_info, labels=args.labels, frame=args.frame,
                            world_frame=args.world_frame, classes=classes, max_dt=args.max_dt,
                            min_range=args.min_range, max_range=args.max_range, progress=progress)
            print(f"mapped {r['mapped']} frames ({r['skipped']} skipped): {r['occupied_voxels']} occupied voxels; "
                  f"wrote {args.out}")
        else:
            result = bag.export_bag(args.run_dir, args.bag, progress=progress)
            print(f"wrote {args.bag}: {result.successful_views} views of {args.run_dir}")
    except (ValueError, OSError) as err:  # BagError and canopy's ValueError name the input
        sys.stderr.write(f"canopy: error: {' '.join(str(err).split())}\n")
        return 2
    except ImportError as err:
        sys.stderr.write(f"canopy: error: {' '.join(str(err).split())}\n")
        return 2
    except KeyboardInterrupt as err:  # the map so far is published when a frame was mapped (the message says)
        sys.stderr.write(f"canopy: {' '.join(str(err).split()) or 'interrupted'}\n")
        return 130
    return 0


if __name__ == "__main__":
    sys.exit(main())
