"""python3 -m canopy: the Python package's commands (docs/commands.md#python-commands).

  map-bag BAG --out DIR      map a ROS 1 bag's RGB-D camera into the run folder `canopy map
                             --frames` writes (canopy.bag.map_bag)
  export-bag RUN_DIR OUT.bag write a `canopy mission` run folder as a ROS 1 bag, for RViz and
                             Foxglove (canopy.bag.export_bag)

Bad input prints one line naming the problem and exits with code 2, as the canopy CLI does;
Ctrl-C and SIGTERM exit with 130 and 143 after keeping what the command promises (map-bag: the
frames mapped so far, marked incomplete; export-bag: no bag).
"""

import argparse
import signal
import sys

from . import interrupts


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit code 2 (argparse's code, without the usage block)
        sys.stderr.write(f"canopy: error: {self.prog}: {message}\n")
        sys.exit(2)


def _parser():
    from . import _canopy, bag

    p = _Parser(prog="python3 -m canopy", description="canopy's Python commands: ROS 1 bags in and out.")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)

    m = sub.add_parser("map-bag", help="map a ROS 1 bag into the run folder `canopy map --frames` writes",
                       description="Maps a bag's RGB-D camera (poses from /tf and /tf_static) into map.csm, map.ply, "
                                   "map.bt, frames.json, run.yaml and settings.yaml (docs/real_robot.md#ros-bags). "
                                   "The bag is streamed: memory does not grow with its length.")
    m.add_argument("bag", help="the ROS 1 bag (.bag) (required)")
    m.add_argument("--out", required=True, help="output folder (required)")
    m.add_argument("--config", default=None, help="settings bundle (default: configs/canopy.yaml)")
    m.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="a setting of the bundle, e.g. mapping.map.resolution_m=0.005; repeatable (default: none)")
    m.add_argument("--seg", choices=["color", "truth"], default=None,
                   help="labels: color (HSV segmentation of --rgb) or truth (the --labels topic) (default: the "
                        "bundle's mapping.extractor.source)")
    m.add_argument("--pgt", type=float, default=None,
                   help="simulated mask noise: the probability a mask keeps its class (default: 1, no noise: a "
                        "recording's labels are taken as they are, whatever the bundle says)")
    m.add_argument("--rgb", default=bag.TOPICS["rgb"], help="RGB topic, Image or CompressedImage (default: %(default)s)")
    m.add_argument("--depth", default=bag.TOPICS["depth"],
                   help="depth topic: 16UC1 mm, 32FC1 m or compressedDepth (default: %(default)s)")
    m.add_argument("--camera-info", default=bag.TOPICS["camera_info"], help="CameraInfo topic (default: %(default)s)")
    m.add_argument("--labels", default=bag.TOPICS["labels"],
                   help="label topic with --seg truth: mono8 class indices or rgb8 class colours (default: %(default)s)")
    m.add_argument("--classes", default=None,
                   help="label classes, comma-separated (default: " + ",".join(bag.DEFAULT_CLASSES) + ")")
    m.add_argument("--frame", default=None,
                   help="the camera's optical frame; must be the depth images' header frame_id (default: that "
                        "frame_id)")
    m.add_argument("--override-frame", action="store_true",
                   help="take --frame although the depth images name another frame (their frame_id is wrong); "
                        "warns (default: off)")
    m.add_argument("--world-frame", default=bag.WORLD_FRAME, help="the fixed frame the map is built in (default: "
                   "%(default)s)")
    m.add_argument("--max-dt", type=float, default=bag.DEFAULT_MAX_DT,
                   help="largest stamp difference of a depth image and its partners, and tf extrapolation [s] "
                        "(default: %(default)s)")
    K = _canopy.Intrinsics()
    m.add_argument("--min-range", type=float, default=None,
                   help=f"valid depth from [m] (default: {K.min_range_m:g}, the D405's)")
    m.add_argument("--max-range", type=float, default=None,
                   help=f"valid depth to [m] (default: {K.max_range_m:g}, the D405's)")

    e = sub.add_parser("export-bag", help="write a `canopy mission` run folder as a ROS 1 bag",
                       description="Replays the run from its own records (settings.yaml, the world's spec and the "
                                   "seed in summary.json), checks that the replay's views.csv equals the run's, and "
                                   "writes the bag: wrist images, /tf, the map per view, the views and the true "
                                   "fruits (docs/real_robot.md#ros-bags). An existing OUT.bag is replaced only when "
                                   "canopy wrote it; OUT.bag is never inside a canopy output folder.")
    e.add_argument("run_dir", help="the run folder of `canopy mission --out` (required)")
    e.add_argument("bag", help="the bag to write, NAME.bag (required)")
    return p


def _map_bag(args, progress):
    from . import _canopy, bag

    settings = _canopy.Settings(args.config)
    p_gt = args.pgt
    for item in args.set:
        key, sep, value = item.partition("=")
        if not sep or not key:
            raise ValueError(f"--set: '{item}' is not KEY=VALUE")
        settings.set(key, value)
        if key == "mapping.extractor.p_gt" and args.pgt is None:
            p_gt = float(settings.get(key))
    if args.seg is not None:
        settings.set("mapping.extractor.source", args.seg)
    classes = args.classes.split(",") if args.classes else None
    r = bag.map_bag(args.bag, args.out, settings, rgb=args.rgb, depth=args.depth, camera_info=args.camera_info,
                    labels=args.labels, frame=args.frame, world_frame=args.world_frame, classes=classes,
                    max_dt=args.max_dt, min_range=args.min_range, max_range=args.max_range, p_gt=p_gt,
                    override_frame=args.override_frame, progress=progress)
    print(f"mapped {r['mapped']} frames ({r['skipped']} skipped): {r['occupied_voxels']} occupied voxels; "
          f"wrote {args.out}")


def main(argv=None):
    # First: SIGTERM takes Ctrl-C's path (the work so far kept as promised, exit 143), and a write
    # past `ulimit -f` fails like a full disk instead of killing the process (as the canopy CLI).
    interrupts.stop_on_sigterm()
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    if interrupts.received():  # while the package imported
        sys.stderr.write("canopy: interrupted; nothing was written\n")
        return interrupts.exit_code()
    args = None
    try:
        args = _parser().parse_args(argv)

        def progress(line):  # never fatal: stderr piped into `head` that has ended loses the lines only
            try:
                sys.stderr.write(line + "\n")
                sys.stderr.flush()
            except OSError:
                pass

        if args.command == "map-bag":
            _map_bag(args, progress)
        else:
            from . import bag

            result = bag.export_bag(args.run_dir, args.bag, progress=progress)
            print(f"wrote {args.bag}: {result.successful_views} views of {args.run_dir}")
    except (ValueError, OSError, ImportError) as err:  # BagError and canopy's ValueError name the input
        sys.stderr.write(f"canopy: error: {' '.join(str(err).split())}\n")
        return 2
    except KeyboardInterrupt as err:
        text = " ".join(str(err).split())
        if not text.startswith(("interrupted after", "interrupted before")):  # map_frames' own account
            text = "interrupted; no bag written" if args is not None and args.command == "export-bag" else \
                "interrupted; nothing was written"
        sys.stderr.write(f"canopy: {text}\n")
        return interrupts.exit_code()
    return 0


if __name__ == "__main__":
    sys.exit(main())
