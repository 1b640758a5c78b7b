#!/usr/bin/env python3
"""One kind of edit, many `olt watch` cycles in one daemon: steadier than edit_bench.py's five
cycles a case where a change moves a cycle by a few milliseconds. The synthetic robot (320
observations at 640x480 unless --observations, a multiple of 4, or --size say otherwise) in a fresh
folder; the daemon settles with 3 cycles of the edit, then N more are timed: medians of the cycle's
seconds (/status), the daemon's CPU seconds a cycle (its threads' schedstat, from the edit to the
cycle's end) and each stage's seconds.
Cases: `one` moves bin_1 (49 of 320 frames see it) 1 cm up and back; `unseen` moves a 10 cm box no
frame sees by 10 um (a cycle's cost besides its frames); `full` nudges a labeling parameter, so
every frame is labeled afresh (a full relabel, the divisor of the issue's one-box share: `one`'s
cycle over `full`'s); `share` takes the two in turn, N pairs (two one-box cycles after one that
settles, then a full relabel), and gives each pair's share: the two figures of a pair meet the
machine in the same seconds, where separate runs of `one` and `full` met it minutes apart (a busy
virtual machine moved the full relabel by a quarter between them). Run two builds in turn with ab.sh.

    TMPDIR=/dev/shm /usr/bin/python3 tests/bench/cycle_bench.py OLT one|unseen|full|share [--cycles N] [--size WxH] [--observations N]

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
observations = int(option("--observations", 320))
if case not in ("one", "unseen", "full", "share"):
    sys.exit("the case is `one`, `unseen`, `full` or `share`")

exit_on_sigterm()
work = tempfile.mkdtemp(prefix="olt-cycle-bench-")
daemon = None
try:
    job = os.path.join(work, "job.yaml")
    JOB = robot_job(observations, width, height)
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
    nudges = iter(range(1, 1 << 30))
    nudge = parameter_nudger(job)
    edits = {"one": lambda: move(["bin_1"]), "unseen": lambda: move(["unseen"]), "full": lambda: nudge(next(nudges))}
    # (edit, timed) in order: 3 cycles that settle, then those timed
    if case == "share":
        steps = [("one", False)] * 3 + [("full", False)] + [("one", False), ("one", True), ("one", True),
                                                           ("full", True)] * cycles
    else:
        steps = [(case, False)] * 3 + [(case, True)] * cycles
    daemon, _, wait_runs = start_watch(olt, job, 120)
    wait_runs(1)
    runs = 1
    walls, cpus, stages, frames = [], [], {}, set()
    pair, pairs = {"one": [], "full": []}, []  # share: each pair's cycles (s, CPU s)
    for edit, timed in steps:
        before = thread_cpu(daemon.pid)
        edits[edit]()
        runs += 1
        status = wait_runs(runs)
        last = status["last_run"]
        if not timed:
            settled = status["image_memory"]
            continue
        if case == "share":
            pair[edit].append((last["seconds"], cpu_since(daemon.pid, before)))
            frames.add((edit, last["frames_relabeled"]))
            if edit == "full":
                pairs.append(pair)
                pair = {"one": [], "full": []}
            continue
        walls.append(last["seconds"])
        cpus.append(cpu_since(daemon.pid, before))
        frames.add(last["frames_relabeled"])
        for stage in last["stages"]:
            if stage["status"] == "ran":
                stages.setdefault(stage["kind"], []).append(stage["seconds"])
    ms = lambda values: f"{1000 * statistics.median(values):.1f}"
    if case == "share":
        def shares(k):  # each pair's one-box cycles' median over its full relabel, k: 0 wall, 1 CPU
            return [100 * statistics.median(c[k] for c in p["one"]) / p["full"][0][k] for p in pairs]
        wall, cpu = shares(0), shares(1)
        relabeled = ", ".join(f"{e}: {n} frames relabeled" for e, n in sorted(frames))
        one_box = ms([c[0] for p in pairs for c in p["one"]])
        full = ms([p["full"][0][0] for p in pairs])
        print(f"olt watch, synthetic robot {observations} x {width}x{height}, {cycles} pairs of one-box cycles and "
              f"full relabels in turn ({relabeled}), medians: one box {one_box} ms, full relabel {full} ms; share "
              f"{statistics.median(wall):.1f} % (pairs {min(wall):.1f}-{max(wall):.1f} %), in CPU "
              f"{statistics.median(cpu):.1f} %")
    else:
        print(f"olt watch, synthetic robot {observations} x {width}x{height}, {cycles} cycles of `{case}` "
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
