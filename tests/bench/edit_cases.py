"""What the edit benchmarks (relabel_bench.py, edit_bench.py) share: one timed `olt run`, moving
boxes to positions never seen before, and the cases timed as medians."""
import json, re, statistics, subprocess, sys, time


def timed_run(olt, job):
    """Seconds of one `olt run JOB` and how many frames it labeled."""
    start = time.perf_counter()
    result = subprocess.run([olt, "run", job], capture_output=True, text=True)
    seconds = time.perf_counter() - start
    if result.returncode != 0:
        sys.exit(f"olt run failed:\n{result.stderr}")
    # "(propagate): done in 1.05 s: labeled 100 observations (59 relabeled, 41 unchanged)"; without
    # the parenthesis every frame was labeled.
    done = re.findall(r"\(propagate\): done in [0-9.]+ s: labeled (\d+) observations(?: \((\d+) relabeled)?",
                      result.stderr)
    return seconds, int(done[-1][1] or done[-1][0]) if done else 0


def box_mover(boxes, boxes_file):
    """move(ids): raises those boxes 2 mm more each call (never a position seen before) and saves."""
    step = [0]

    def move(ids):
        step[0] += 1
        for b in boxes["boxes"]:
            if b["id"] in ids:
                b["center"][2] += 0.002 * step[0]
        json.dump(boxes, open(boxes_file, "w"))
    return move


def time_cases(cases, repeats, run, move):
    """[(name, median seconds, frames)] of each (name, ids moved) case, `repeats` runs each."""
    rows = []
    for name, ids in cases:
        times, frames = [], 0
        for _ in range(repeats):
            if ids:
                move(ids)
            seconds, frames = run()
            times.append(seconds)
        rows.append((name, statistics.median(times), frames))
    return rows
