#!/usr/bin/env python3
"""One kind of edit, many `olt watch` cycles in one daemon: steadier than edit_bench.py's five
cycles a case where a change moves a cycle by a few milliseconds. The synthetic robot (320
observations, 640x480 unless told otherwise) in a fresh folder; the daemon settles with 3 cycles
of the edit, then N more are timed: medians of the cycle's seconds (/status), the daemon's CPU
seconds a cycle (its threads' schedstat, from the edit to the cycle's end) and each stage's seconds.
Cases: `one` moves bin_1 (49 of 320 frames see it) 1 cm up and back; `unseen` moves a 10 cm box no
frame sees by 10 um (a cycle's cost besides its frames); `full` nudges a labeling parameter, so
every frame is labeled afresh (a full relabel, the divisor of the issue's one-box share: `one`'s
cycle over `full`'s). Run two builds in turn with ab.sh.

    TMPDIR=/dev/shm /usr/bin/python3 tests/bench/cycle_bench.py OLT one|unseen|full [--cycles N] [--size WxH]

(its folder is made in TMPDIR: on a disk, a cycle's time is mostly its flushes)
"""
import copy, json, os, shutil, statistics, subprocess, sys, tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from edit_cases import (box_mover, cpu_since, exit_on_sigterm, parameter_nudger, robot_job, start_watch, thread_cpu,
                        timed_run)

olt = os.path.abspath(sys.argv[1])
case = sys.argv[2]
def option(name, default):
    if name not in sys.argv:
        return default
    if sys.argv.index(name) + 1 >= len(sys.argv):
        sys.exit(f"{name} needs a value")
    return sys.argv[sys.argv.index(name) + 1]


cycles = int(option("--cycles", 30))
width, height = (int(v) for v in option("--size", "640x480").split("x"))
if case not in ("one", "unseen", "full"):
    sys.exit("the case is `one`, `unseen` or `full`")

exit_on_sigterm()
work = tempfile.mkdtemp(prefix="olt-cycle-bench-")
daemon = None
try:
    job = os.path.join(work, "job.yaml")
    JOB = robot_job(320, width, height)
    open(job, "w").write(JOB % "")
    timed_run(olt, job)
    boxes = json.load(open(os.path.join(work, "out", "annotations", "boxes.json")))
    far = copy.deepcopy(boxes["boxes"][0])
    far.update(id="unseen", instance="unseen", center=[0.0, 0.0, 2.85], size=[0.1, 0.1, 0.1])
    boxes["boxes"].append(far)
    boxes_file = os.path.join(work, "boxes.json")
    json.dump(boxes, open(boxes_file, "w"))
    open(job, "w").write(JOB % ", params: {file: boxes.json, frame: world}")
    timed_run(olt, job)
    move = box_mover(boxes, boxes_file, {"unseen": 0.00001})
    ids = ["bin_1"] if case == "one" else ["unseen"]
    if case == "full":
        nudge = parameter_nudger(job)
        edit = lambda i: nudge(i + 1)
    else:
        edit = lambda i: move(ids)
    daemon, _, wait_runs = start_watch(olt, job, 120)
    wait_runs(1)
    runs = 1
    walls, cpus, stages, frames = [], [], {}, set()
    for i in range(3 + cycles):
        before = thread_cpu(daemon.pid)
        edit(i)
        runs += 1
        status = wait_runs(runs)
        last = status["last_run"]
        if i < 3:
            settled = status["image_memory"]
            continue
        walls.append(last["seconds"])
        cpus.append(cpu_since(daemon.pid, before))
        frames.add(last["frames_relabeled"])
        for stage in last["stages"]:
            if stage["status"] == "ran":
                stages.setdefault(stage["kind"], []).append(stage["seconds"])
    ms = lambda values: f"{1000 * statistics.median(values):.1f}"
    print(f"olt watch, synthetic robot {width}x{height}, {cycles} cycles of `{case}` "
          f"({'/'.join(str(f) for f in sorted(frames))} frames relabeled), medians: cycle {ms(walls)} ms, "
          f"the daemon's CPU {ms(cpus)} ms; stages " + ", ".join(f"{k} {ms(v)} ms" for k, v in stages.items()))
    held = status["image_memory"]
    print(f"what the daemon keeps over the {cycles} cycles: {settled['values']} -> {held['values']} values, "
          f"{settled['held_mb']:.1f} -> {held['held_mb']:.1f} MB ({held['dropped']} dropped for its budget)")
finally:
    if daemon:
        daemon.terminate()
        try:
            daemon.wait(timeout=60)
        except subprocess.TimeoutExpired:
            daemon.kill()
            daemon.wait()
    shutil.rmtree(work, ignore_errors=True)
