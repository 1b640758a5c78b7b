"""What the edit benchmarks (relabel_bench.py, edit_bench.py) share: one timed `olt run`, moving
boxes to positions never seen before, the cases timed as medians, and `olt watch`'s cycles."""
import json, os, re, signal, statistics, subprocess, sys, time, urllib.request


def exit_on_sigterm():
    """SIGTERM (a CI timeout, `kill`) leaves through the benchmark's `finally` blocks: its daemons are
    stopped and its folder removed."""
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))


def robot_job(observations=320, width=320, height=240):
    """The synthetic robot's job (4 RGB-D cameras, ground-truth poses, every default output), its
    annotations stage with `%s` where its params go (its own boxes with "", a file's with
    ", params: {file: boxes.json, frame: world}"); output and cache beside the job."""
    job = """version: 1
output: out
cache: cache
stages:
  source: {kind: source, params: {format: synthetic, cameras: 4, frames: FRAMES, rate_hz: 2.5, width: WIDTH, height: HEIGHT}}
  calibrate: {kind: calibrate, needs: [source]}
  poses: {kind: poses, needs: [calibrate], params: {method: trajectory}}
  scene: {kind: reconstruct, needs: [poses], params: {every: EVERY}}
  annotations: {kind: annotations, needs: [source, scene]%s}
  labels: {kind: propagate, needs: [poses, annotations]}
  dataset: {kind: export, needs: [labels]}
  report: {kind: report, needs: [labels, scene]}
"""
    # The scene fuses 40 of the observations at any length.
    return (job.replace("FRAMES", str(observations // 4)).replace("WIDTH", str(width)).replace("HEIGHT", str(height))
            .replace("EVERY", str(max(1, observations // 40))))


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


def box_mover(boxes, boxes_file, metres=None):
    """move(ids): moves each of those boxes 1 cm up, then back down the next time it moves, and so on
    (`metres` {id: m} for other steps): it stays where it was annotated, as an annotator's corrections
    do, and a micrometre higher each time, so no position repeats (nothing comes from the cache by
    luck); saves."""
    moves = {}

    def move(ids):
        for b in boxes["boxes"]:
            if b["id"] in ids:
                moves[b["id"]] = moves.get(b["id"], 0) + 1
                sign = 1 if moves[b["id"]] % 2 else -1
                b["center"][2] += sign * (metres or {}).get(b["id"], 0.01) + 1e-6
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


def parameter_nudger(job):
    """relabel_all(step): JOB's labeling stage given color_fill_tolerance_m 0.05 m + step um, saved:
    every frame's inputs change, so `olt watch` labels every frame afresh, pixel by pixel: a full
    relabel in the literal sense (moving every box relabels only the frames that see a box, and in
    place). The stage must have no params of its own (a flow or a block mapping)."""
    text = open(job).read()
    flow = re.search(r"\{kind: propagate,[^}]*\}", text)
    block = re.search(r"^( *)kind: propagate *(#.*)?$", text, re.M)
    if not flow and not block:
        sys.exit(f"{job}: no labeling stage to nudge")
    siblings = []  # the block mapping's other keys: the lines after it at its indentation
    for line in text[block.end():].split("\n")[1:] if block else []:
        if line.strip() and len(line) - len(line.lstrip(" ")) < len(block.group(1)):
            break
        siblings.append(line)
    if flow and "params:" in flow.group(0) or any(line.startswith(block.group(1) + "params:") for line in siblings):
        sys.exit(f"{job}: the labeling stage has params of its own: nudge them by hand")

    def relabel_all(step):
        param = f"params: {{color_fill_tolerance_m: {0.05 + step * 1e-6:.7f}}}"
        if flow:
            changed = text[:flow.start()] + "{kind: propagate, " + param + "," + text[flow.start() + 17:]
        else:
            changed = text[:block.end()] + "\n" + block.group(1) + param + text[block.end():]
        open(job, "w").write(changed)
    return relabel_all


def start_watch(olt, job, cycle_s, log_name="watch.err"):
    """`olt watch JOB` at its defaults (--poll 0.2, --settle 0.3: what an annotator waits for from
    saving to labels), on loopback at a port of the system's choosing: the process, its stderr's
    file, and wait_runs(n), /status once n cycles ended (each given up to `cycle_s` seconds: a
    long recording's cycles are long, and a busy disk's longer)."""
    err = os.path.join(os.path.dirname(job), log_name)
    daemon = subprocess.Popen([olt, "watch", job, "--listen=127.0.0.1:0"], stderr=open(err, "w"))
    port = None
    for _ in range(600):
        m = re.search(r"listening on http://127\.0\.0\.1:(\d+)", open(err).read())
        if m:
            port = int(m.group(1))
            break
        time.sleep(0.05)
    if port is None:
        daemon.kill()
        daemon.wait()
        sys.exit("olt watch did not listen in 30 s:\n" + open(err).read())

    def wait_runs(n):
        until = time.perf_counter() + cycle_s
        while time.perf_counter() < until:
            s = json.load(urllib.request.urlopen(f"http://127.0.0.1:{port}/status", timeout=5))
            if s["runs"] >= n and s["state"] == "idle":
                if s["last_run"]["outcome"] != "ok":
                    sys.exit(f"olt watch's cycle {n} failed: {s['last_run']['errors']}")
                return s
            time.sleep(0.025)
        sys.exit(f"olt watch did not finish cycle {n} in {cycle_s:.0f} s")
    return daemon, err, wait_runs


def stop_times(olt, job, move, all_ids, repeats, cycle_s=60):
    """Seconds from SIGTERM to `olt watch`'s exit, sent as a cycle after every box moved is labeling
    frames (its log says the labeling stage runs); a fresh daemon each time (medians): what a pod's or
    a Slurm job's grace period must cover. Returns their median, and how many of them the daemon
    logged as a cycle stopped mid-way (an olt before stopping existed ran its cycles to the end; a
    signal that comes late finds the labeling done) and exited 0 after."""
    stops, clean = [], 0
    for i in range(repeats):
        daemon, err, wait_runs = start_watch(olt, job, cycle_s, "stop.err")
        try:
            wait_runs(1)
            labeling = open(err).read().count("(propagate): running")
            move(all_ids)
            until = time.perf_counter() + cycle_s
            while open(err).read().count("(propagate): running") == labeling:
                if time.perf_counter() > until:
                    sys.exit("olt watch did not start labeling after the edit:\n" + open(err).read())
                time.sleep(0.002)
            sent = time.perf_counter()
            daemon.terminate()
            code = daemon.wait(timeout=cycle_s)
            stops.append(time.perf_counter() - sent)
            if code != 0:
                sys.exit(f"olt watch exited {code} after SIGTERM:\n" + open(err).read())
            clean += "stopped in stage 'labels'" in open(err).read()
        finally:
            if daemon.poll() is None:
                daemon.kill()
                daemon.wait()
    return statistics.median(stops), clean


def thread_cpu(pid):
    """{thread id: CPU nanoseconds} of process `pid`'s live threads (their schedstat)."""
    out = {}
    for task in os.listdir(f"/proc/{pid}/task"):
        try:
            with open(f"/proc/{pid}/task/{task}/schedstat") as f:
                out[task] = int(f.read().split()[0])
        except (FileNotFoundError, ProcessLookupError):
            pass  # a thread that ended meanwhile
    return out


def cpu_since(pid, before):
    """CPU seconds process `pid`'s threads used since thread_cpu gave `before`: those alive now (a
    status server's thread that answered a request and ended is not counted; one that ended since
    `before` takes nothing off)."""
    now = thread_cpu(pid)
    return sum(ns - before.get(task, 0) for task, ns in now.items()) / 1e9


def watch_cycles(olt, job, move, all_ids, one_ids, repeats, unseen_ids=None, relabel_all=None, cycle_s=60):
    """`olt watch JOB`'s cycles, every box moved then one box moved, in turn, `repeats` times each:
    {"every": median s, "one": median s, "saved_to_done": median s (one box: the edit saved -> its
    cycle done, as an annotator waits), "frames": frames the last one-box cycle relabeled}, from its
    /status (loopback, a port of the system's choosing). With `unseen_ids` (boxes no frame sees),
    a third cycle moves those each time: "unseen" is its median, what a cycle costs besides its
    frames, and "unseen_stages" the median seconds of each stage that ran in it, by kind. With
    `relabel_all` (parameter_nudger's), a last cycle each time labels every frame afresh: "full" is
    its median, "full_frames" the frames it labeled. "cpu": each case's median CPU seconds a cycle
    (cpu_since, from the edit to the cycle's end: steadier than wall time on a busy machine; it holds
    the daemon's idle polling in the settle time too, a few milliseconds). Each cycle is given up to
    `cycle_s` seconds."""
    daemon, err, wait_runs = start_watch(olt, job, cycle_s)
    try:
        wait_runs(1)
        every, one, unseen, unseen_stages, waited, frames, full, full_frames = [], [], [], {}, [], 0, [], 0
        cpu = {"every": [], "one": [], "unseen": [], "full": []}
        runs = 1

        def cycle(case, edit):
            """edit() saved, then its cycle's /status, and the seconds from the save to the cycle's end;
            its CPU seconds kept under `case`."""
            nonlocal runs
            before = thread_cpu(daemon.pid)
            edit()
            saved = time.perf_counter()
            runs += 1
            s = wait_runs(runs)
            waited = time.perf_counter() - saved
            cpu[case].append(cpu_since(daemon.pid, before))
            return s, waited

        for i in range(repeats):
            every.append(cycle("every", lambda: move(all_ids))[0]["last_run"]["seconds"])
            s, saved_to_done = cycle("one", lambda: move(one_ids))
            waited.append(saved_to_done)
            one.append(s["last_run"]["seconds"])
            frames = s["last_run"]["frames_relabeled"]
            if unseen_ids:
                s = cycle("unseen", lambda: move(unseen_ids))[0]
                if s["last_run"]["frames_relabeled"] != 0:
                    sys.exit(f"moving {unseen_ids} relabeled {s['last_run']['frames_relabeled']} frames: not unseen")
                unseen.append(s["last_run"]["seconds"])
                for stage in s["last_run"]["stages"]:
                    if stage["status"] == "ran":
                        unseen_stages.setdefault(stage["kind"], []).append(stage["seconds"])
            if relabel_all:
                s = cycle("full", lambda: relabel_all(i + 1))[0]
                full.append(s["last_run"]["seconds"])
                full_frames = s["last_run"]["frames_relabeled"]
    finally:
        daemon.terminate()
        daemon.wait(timeout=cycle_s)
    return {"every": statistics.median(every), "one": statistics.median(one),
            "unseen": statistics.median(unseen) if unseen else None,
            "unseen_stages": {kind: statistics.median(v) for kind, v in unseen_stages.items()},
            "saved_to_done": statistics.median(waited), "frames": frames,
            "full": statistics.median(full) if full else None, "full_frames": full_frames,
            "cpu": {case: statistics.median(v) for case, v in cpu.items() if v}}
