#!/usr/bin/env python3
"""End-to-end relabel benchmark: the whole `olt run` of the TUM job (start-up, change detection,
every default output) after every box moved, after one box moved, and with nothing changed; and
`olt watch`'s cycle after one box moved (edit saved -> labels published, as an annotator waits),
and its cycles after every box and one box moved, in turn (the ratio an annotator sees), and after a
labeling parameter nudged (every frame labeled afresh: a full relabel, literally).

    /usr/bin/python3 tests/bench/relabel_bench.py OLT JOB_YAML [--repeats N]

Each case moves boxes to positions never seen before (so nothing comes from the cache by luck)
and reports the median of N runs (default 3) in one fresh cache.
"""
import json, os, re, shutil, sys, tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from edit_cases import box_mover, parameter_nudger, time_cases, timed_run, watch_cycles

olt, job = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
repeats = int(sys.argv[sys.argv.index("--repeats") + 1]) if "--repeats" in sys.argv else 3
job_dir = os.path.dirname(job)
text = open(job).read()
data = re.search(r"path: (\S+)", text).group(1)
if not os.path.isfile(os.path.join(job_dir, data, "depth.txt")):
    print(f"skipped: {os.path.normpath(os.path.join(job_dir, data))} is absent")
    sys.exit(0)
boxes_name = re.search(r"file: (\S+\.json)", text).group(1)

work = tempfile.mkdtemp(prefix="olt-relabel-bench-")
try:
    # The job, with its relative paths made absolute, an output and a cache of its own.
    local = re.sub(r"(path|trajectory): (\.\.?/\S+)",
                   lambda m: f"{m.group(1)}: {os.path.normpath(os.path.join(job_dir, m.group(2)))}", text)
    local = re.sub(r"output: \S+", "output: out\ncache: cache", local)
    open(os.path.join(work, "job.yaml"), "w").write(local)
    boxes_file = os.path.join(work, boxes_name)
    boxes = json.load(open(os.path.join(job_dir, boxes_name)))
    json.dump(boxes, open(boxes_file, "w"))

    run = lambda: timed_run(olt, os.path.join(work, "job.yaml"))
    move = box_mover(boxes, boxes_file)

    run()  # everything, once: the scene, poses and labels are then cached
    all_ids = [b["id"] for b in boxes["boxes"]]
    one = "b11" if "b11" in all_ids else all_ids[0]
    rows = time_cases((("every box moved", all_ids), (f"one box moved ({one})", [one]), ("nothing changed", [])),
                      repeats, run, move)

    # olt watch: every box moved, then one box, in turn: the cycles an annotator waits for.
    watch = watch_cycles(olt, os.path.join(work, "job.yaml"), move, all_ids, [one], repeats,
                         relabel_all=parameter_nudger(os.path.join(work, "job.yaml")))

    full = rows[0][1]
    print(f"olt run of {os.path.basename(job)} after an edit, {repeats} runs each (medians), 2 cores\n")
    print(f"{'case':34} {'wall s':>7} {'frames':>7} {'frames/s':>9} {'of full':>8}")
    for name, seconds, frames in rows:
        fps = f"{frames / seconds:.0f}" if frames else "-"
        print(f"{name:34} {seconds:7.3f} {frames:7d} {fps:>9} {seconds / full:7.0%}")
    print(f"\nolt watch, one box moved: edit saved -> labels published {watch['saved_to_done']:.3f} s "
          f"(the cycle itself {watch['one']:.3f} s, {watch['frames']} frames relabeled; the rest is noticing the "
          f"save: at the default --poll 0.2 s and --settle 0.3 s, 30 ms where the system reports it finished)")
    print(f"olt watch cycles: every box moved {watch['every']:.3f} s, one box moved {watch['one']:.3f} s "
          f"= {watch['one'] / watch['every']:.0%} of it; a full relabel (every frame labeled afresh: a labeling "
          f"parameter nudged in the job, read again) {watch['full']:.3f} s, {watch['full_frames']} frames: the "
          f"one-box cycle is {watch['one'] / watch['full']:.0%} of it")
finally:
    shutil.rmtree(work, ignore_errors=True)
