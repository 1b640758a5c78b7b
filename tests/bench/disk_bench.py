#!/usr/bin/env python3
"""What an edit writes to the disk: the synthetic robot of edit_bench.py (320 observations of
320x240) in FOLDER, its output and cache there; the bytes its block device wrote during one `olt
run` after every box moved and after one box moved (bin_1), each the median of N runs, synced
before and after; then the bytes the output and the cache hold, and the room the file system has
used in all (`df`: where the output's files are clones of the cache's, XFS and Btrfs, the output
takes almost none of its own). FOLDER must be on a block device of its own for the figures to mean
anything (a loop-mounted image file, or a disk nothing else writes to meanwhile); `--target bench`
runs it in the build folder, whatever holds that.

    /usr/bin/python3 tests/bench/disk_bench.py OLT FOLDER [--repeats N]
"""
import json, os, shutil, subprocess, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from edit_cases import box_mover, robot_job, timed_run

olt, folder = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
repeats = int(sys.argv[sys.argv.index("--repeats") + 1]) if "--repeats" in sys.argv else 3

# --nofsroot: a Btrfs subvolume's or a bind mount's device without its "[/path]".
source = subprocess.run(["findmnt", "-n", "--nofsroot", "-o", "SOURCE,FSTYPE", "--target", folder],
                        capture_output=True, text=True, check=True).stdout.split()
device, fstype = os.path.basename(os.path.realpath(source[0])), source[1]
stat = f"/sys/class/block/{device}/stat"
if not os.path.exists(stat):
    print(f"skipped: {folder} is on {source[0]}, which has no {stat} (not a block device)")
    sys.exit(0)


def written():
    """Bytes the device wrote so far (sectors of 512 bytes, the stat's seventh field)."""
    return int(open(stat).read().split()[6]) * 512


def size(path):
    return int(subprocess.run(["du", "-sb", path], capture_output=True, text=True, check=True).stdout.split()[0])


def used():
    os.sync()
    line = subprocess.run(["df", "-B1", "--output=used", folder], capture_output=True, text=True, check=True).stdout
    return int(line.split()[-1])


work = os.path.join(folder, f"olt-disk-bench-{os.getpid()}")
os.makedirs(work)
try:
    before = used()
    job = os.path.join(work, "job.yaml")
    open(job, "w").write(robot_job() % "")
    timed_run(olt, job)
    boxes = json.load(open(os.path.join(work, "out", "annotations", "boxes.json")))
    boxes_file = os.path.join(work, "boxes.json")
    json.dump(boxes, open(boxes_file, "w"))
    open(job, "w").write(robot_job() % ", params: {file: boxes.json, frame: world}")
    timed_run(olt, job)
    move = box_mover(boxes, boxes_file)
    rows = []
    for name, ids in (("every box moved", [b["id"] for b in boxes["boxes"]]), ("one box moved (bin_1)", ["bin_1"])):
        bytes_written = []
        for _ in range(repeats):
            move(ids)
            os.sync()
            start = written()
            timed_run(olt, job)
            os.sync()
            bytes_written.append(written() - start)
        rows.append((name, sorted(bytes_written)[len(bytes_written) // 2]))
    print(f"olt run of the synthetic robot (320 observations, 320x240) on {fstype} ({source[0]}), "
          f"{repeats} runs each (medians)\n")
    for name, value in rows:
        print(f"{name:36s}{value / 1e6:8.1f} MB written to the device")
    print(f"{'the output holds':36s}{size(os.path.join(work, 'out')) / 1e6:8.1f} MB")
    print(f"{'the cache holds':36s}{size(os.path.join(work, 'cache')) / 1e6:8.1f} MB")
    print(f"{'the file system used for both':36s}{(used() - before) / 1e6:8.1f} MB")
finally:
    shutil.rmtree(work, ignore_errors=True)
