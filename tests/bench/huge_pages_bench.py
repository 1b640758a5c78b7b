#!/usr/bin/env python3
"""Huge pages, side by side with the same `olt` binary, in turn (each round in another order, after
one untimed run of each case), medians of N rounds: transparent huge pages turned off for the
process (prctl PR_SET_THP_DISABLE: olt's advice ignored, every page 4 KB: what olt did before it
asked for them, where the kernel's setting is `madvise`; where it is `always` the old olt had huge
pages already, and "off" is slower than it was), olt's defaults (its large buffers advised: files
read whole, the scene's points, large lists), and the defaults with glibc's heap in huge pages too
(GLIBC_TUNABLES=glibc.malloc.hugetlb=1, what the container image and the Slurm templates set).
Cases: the TUM job from nothing (when ../shared/data has it), the synthetic robot (320 observations
of 640x480) from nothing, and the robot's `olt run` after one box moved (its report draws the box's
picture from the scene's 1.2 M points). Wall seconds and page faults of each run.

    /usr/bin/python3 tests/bench/huge_pages_bench.py OLT [SHARED_DATA] [--rounds N]
"""
import ctypes, json, os, shutil, statistics, subprocess, sys, tempfile, time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from edit_cases import box_mover, robot_job

olt = os.path.abspath(sys.argv[1])
data = sys.argv[2] if len(sys.argv) > 2 and not sys.argv[2].startswith("--") else None
rounds = int(sys.argv[sys.argv.index("--rounds") + 1]) if "--rounds" in sys.argv else 3
repo = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

if not os.path.exists("/sys/kernel/mm/transparent_hugepage/enabled"):
    print("huge pages: skipped, this kernel has no transparent huge pages")
    sys.exit(0)
setting = open("/sys/kernel/mm/transparent_hugepage/enabled").read().strip()


def no_huge_pages():
    PR_SET_THP_DISABLE = 41
    if ctypes.CDLL(None, use_errno=True).prctl(PR_SET_THP_DISABLE, 1, 0, 0, 0) != 0:
        raise OSError(ctypes.get_errno(), "prctl(PR_SET_THP_DISABLE)")


MODES = {"off": ({}, no_huge_pages), "advised": ({}, None),
         "advised + glibc heap": ({"GLIBC_TUNABLES": "glibc.malloc.hugetlb=1"}, None)}


def run(job, mode, cache):
    """Seconds and minor page faults of `olt run JOB` in that mode."""
    extra, before = MODES[mode]
    env = {k: v for k, v in os.environ.items() if k != "GLIBC_TUNABLES"}
    env.update(extra, OLT_CACHE_DIR=cache)
    with tempfile.TemporaryFile() as err:
        start = time.perf_counter()
        child = subprocess.Popen([olt, "run", job], stdout=subprocess.DEVNULL, stderr=err, env=env, preexec_fn=before)
        _, status, usage = os.wait4(child.pid, 0)
        seconds = time.perf_counter() - start
        child.returncode = os.waitstatus_to_exitcode(status)  # reaped here, by wait4
        if status != 0:
            err.seek(0)
            sys.exit(f"olt run {job} failed ({mode}):\n{err.read().decode()}")
    return seconds, usage.ru_minflt


def from_nothing(cache):
    shutil.rmtree(cache, ignore_errors=True)


work = tempfile.mkdtemp(prefix="olt-huge-pages-")
try:
    cases = []  # (name, job, its cache, prepare(cache) before each timed run)
    if data and os.path.isdir(os.path.join(data, "tum_fr1_rpy")):
        jobs = os.path.join(work, "olt", "jobs")  # the job's ../../shared/data is SHARED_DATA
        os.makedirs(jobs)
        for name in ("tum_fr1_rpy.yaml", "tum_fr1_rpy.boxes.json"):
            shutil.copy(os.path.join(repo, "jobs", name), jobs)
        os.makedirs(os.path.join(work, "shared"))
        os.symlink(os.path.abspath(data), os.path.join(work, "shared", "data"))
        cases.append(("TUM job from nothing", os.path.join(jobs, "tum_fr1_rpy.yaml"), os.path.join(work, "cache"),
                      from_nothing))
    else:
        print("TUM job: skipped, SHARED_DATA/tum_fr1_rpy is absent")
    # The robot's own boxes, written to a file the benchmark then edits (the world frame).
    robot = os.path.join(work, "robot", "job.yaml")
    os.makedirs(os.path.dirname(robot))
    open(robot, "w").write(robot_job(320, 640, 480) % "")
    subprocess.run([olt, "run", robot], capture_output=True, check=True)
    boxes_file = os.path.join(work, "robot", "boxes.json")
    boxes = json.load(open(os.path.join(work, "robot", "out", "annotations", "boxes.json")))
    json.dump(boxes, open(boxes_file, "w"))
    open(robot, "w").write(robot_job(320, 640, 480) % ", params: {file: boxes.json, frame: world}")
    robot_cache = os.path.join(work, "robot", "cache")  # the job's own `cache: cache`
    cases.append(("robot 640x480 from nothing", robot, robot_cache, from_nothing))
    move = box_mover(boxes, boxes_file)

    def move_one(cache):
        """bin_1 (seen by 49 of 320 frames) 1 cm up, then down, a micrometre higher each time."""
        move(["bin_1"])

    cases.append(("robot 640x480, one box moved", robot, robot_cache, move_one))

    print(f"huge pages: the same olt with them off, advised, and glibc's heap too; medians of {rounds} rounds "
          f"in turn, {os.cpu_count()} cores, transparent huge pages here: {setting}\n")
    if "[always]" in setting:
        print("(the kernel gives huge pages to every process here: olt before its advice had them too)\n")
    print(f"{'case':32s}" + "".join(f"{m + ' s':>24s}{'faults':>9s}" for m in MODES) + f"{'advised/off':>13s}"
          f"{'+heap/off':>11s}")
    modes = list(MODES)
    for name, job, cache, prepare in cases:
        results = {m: [] for m in MODES}
        if prepare is move_one:  # the edit's run finds the rest in the cache
            subprocess.run([olt, "run", job], capture_output=True, check=True)
        # The edit twice a round in each mode: the box up, then down (each relabels the same frames).
        runs = 2 if prepare is move_one else 1
        for mode in modes:  # untimed: the recording's files read, the binary loaded
            for _ in range(runs):
                prepare(cache)
                run(job, mode, cache)
        for r in range(rounds):
            for mode in modes[r % 3:] + modes[:r % 3]:
                for _ in range(runs):
                    prepare(cache)
                    results[mode].append(run(job, mode, cache))
        med = {m: (statistics.median(r[0] for r in v), statistics.median(r[1] for r in v)) for m, v in results.items()}
        print(f"{name:32s}" + "".join(f"{med[m][0]:24.3f}{med[m][1]:9.0f}" for m in MODES) +
              f"{med['advised'][0] / med['off'][0]:13.2f}{med['advised + glibc heap'][0] / med['off'][0]:11.2f}")
finally:
    shutil.rmtree(work, ignore_errors=True)
