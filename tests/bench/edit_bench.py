#!/usr/bin/env python3
"""An edit of one box that few frames see, on a synthetic robot (4 RGB-D cameras, 320 observations
of 320x240 unless told otherwise, ground-truth poses, every default output): the whole `olt run`
after every box moved, after the box seen by the fewest frames moved, and with nothing changed;
medians of N runs in one fresh cache, and each case's share of the full relabel; then `olt watch`'s
cycles after every box and that one box moved, in turn, and after a box no frame sees moved (a 10 cm
box above the room's middle, under the report's overview region's top, nudged 10 um and back: what a
cycle costs besides relabeling frames; the benchmark stops if a frame sees it), and after a labeling
parameter nudged (every frame labeled afresh: a full relabel, literally); and how soon SIGTERM
ends a daemon whose cycle after every box moved is labeling frames. `--observations 10000
--size 64x48`: the same on a long recording (what an annotator waits for there).

    /usr/bin/python3 tests/bench/edit_bench.py OLT [--repeats N] [--observations N] [--size WxH]
"""
import copy, json, os, shutil, sys, tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from edit_cases import box_mover, exit_on_sigterm, parameter_nudger, robot_job, stop_times, time_cases, timed_run, watch_cycles

olt = os.path.abspath(sys.argv[1])
option = lambda name, default: sys.argv[sys.argv.index(name) + 1] if name in sys.argv else default
repeats = int(option("--repeats", 3))
observations = int(option("--observations", 320))
width, height = (int(v) for v in option("--size", "320x240").split("x"))

JOB = robot_job(observations, width, height)

exit_on_sigterm()
work = tempfile.mkdtemp(prefix="olt-edit-bench-")
try:
    job = os.path.join(work, "job.yaml")

    run = lambda: timed_run(olt, job)

    # The recording's own boxes, written to a file the benchmark then edits (the world frame).
    open(job, "w").write(JOB % "")
    run()
    boxes = json.load(open(os.path.join(work, "out", "annotations", "boxes.json")))
    far = copy.deepcopy(boxes["boxes"][0])
    far.update(id="unseen", instance="unseen", center=[0.0, 0.0, 2.85], size=[0.1, 0.1, 0.1])
    seeing = {k: v["frames_seeing"] for k, v in json.load(open(os.path.join(work, "out", "labels.json")))["boxes"].items()}
    boxes_file = os.path.join(work, "boxes.json")
    json.dump(boxes, open(boxes_file, "w"))
    open(job, "w").write(JOB % ", params: {file: boxes.json, frame: world}")
    run()

    move = box_mover(boxes, boxes_file, {"unseen": 0.00001})
    few = min(seeing, key=lambda k: (seeing[k], k))
    rows = time_cases((("every box moved", [b["id"] for b in boxes["boxes"]]),
                       (f"one box moved ({few}, seen by {seeing[few]} of {observations})", [few]),
                       ("nothing changed", [])), repeats, run, move)
    boxes["boxes"].append(far)  # for the watch only: the runs above time the recording's own boxes
    move([])
    cycle_s = 60 + 0.05 * observations  # a cycle's limit: 560 s at 10,000 observations, on a busy disk
    watch = watch_cycles(olt, job, move, [b["id"] for b in boxes["boxes"]], [few], repeats, ["unseen"],
                         parameter_nudger(job), cycle_s)
    stopped, mid_cycle = stop_times(olt, job, move, [b["id"] for b in boxes["boxes"]], repeats, cycle_s)

    print(f"olt run of a synthetic robot ({observations} observations, {width}x{height}, 4 cameras) after an edit, "
          f"{repeats} runs each (medians), {os.cpu_count()} cores\n")
    print(f"{'case':44s}{'wall s':>8s}{'frames':>8s}{'of full':>9s}")
    full = rows[0][1]
    for name, seconds, frames in rows:
        print(f"{name:44s}{seconds:8.3f}{frames:8d}{100 * seconds / full:8.0f}%")
    print(f"\nolt watch cycles: every box moved {watch['every']:.3f} s, one box moved ({few}, {watch['frames']} "
          f"frames relabeled) {watch['one']:.3f} s = {watch['one'] / watch['every']:.0%} of it, a box no frame sees "
          f"moved {watch['unseen']:.3f} s = {watch['unseen'] / watch['every']:.0%}")
    print(f"  a full relabel (every frame labeled afresh: a labeling parameter nudged in the job, read again) "
          f"{watch['full']:.3f} s, {watch['full_frames']} frames: the one-box cycle is "
          f"{watch['one'] / watch['full']:.0%} of it")
    cpu = watch["cpu"]
    print(f"  the daemon's CPU a cycle, median s: every box {cpu['every']:.3f}, one box {cpu['one']:.3f} "
          f"({cpu['one'] / cpu['full']:.0%} of a full relabel's {cpu['full']:.3f}), a box no frame sees "
          f"{cpu['unseen']:.3f}")
    stages = watch["unseen_stages"]
    print("  the stages that ran in the cycle no frame sees, median s: " +
          ", ".join(f"{kind} {seconds:.3f}" for kind, seconds in stages.items()) +
          f"; the rest (finding the cached stages, publishing) {watch['unseen'] - sum(stages.values()):.3f}")
    print(f"  SIGTERM while a fresh daemon's first cycle after every box moved labels its frames: it exited "
          f"{stopped:.3f} s later (median of {repeats} daemons; {mid_cycle} stopped mid-cycle), against "
          f"{watch['every']:.3f} s for a whole such cycle of a daemon that kept its frames")
finally:
    shutil.rmtree(work, ignore_errors=True)
