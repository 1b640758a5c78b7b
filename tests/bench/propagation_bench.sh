#!/usr/bin/env bash
# Propagation benchmark: OLT's per-frame labeling against the original toolkit's method (PCL
# CropHull per box) and Open3D's oriented-box test, on the same TUM frames, poses and 30 boxes.
#   bash tests/bench/propagation_bench.sh OLT_BENCH CROPHULL_PEER DATASET_DIR BOXES_JSON
# (or: cmake --build build --target bench). Open3D rows need python3-open3d (Debian); they are left
# out, with a note, without it.
set -euo pipefail
bench=$1
crophull=$2
data=$3
boxes=$4
if [ ! -f "$data/depth.txt" ]; then
  echo "skipped: $data is absent"
  exit 0
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$bench" "$data" "$boxes" --exchange "$work/exchange.json" > "$work/olt.json"
"$crophull" "$work/exchange.json" --frames 3 > "$work/crophull.json"
if /usr/bin/python3 -c "import open3d" 2>/dev/null; then
  /usr/bin/python3 "$(dirname "$0")/propagation_open3d_peer.py" "$work/exchange.json" > "$work/open3d.json"
else
  echo "note: python3-open3d is not installed; the Open3D row is left out"
fi

/usr/bin/python3 - "$work" <<'PY'
import json, os, sys
work = sys.argv[1]
ours = json.load(open(os.path.join(work, "olt.json")))
peers = [json.load(open(os.path.join(work, f))) for f in ("crophull.json", "open3d.json")
         if os.path.exists(os.path.join(work, f))]

def agreement(peer):
    # Points inside each box on its own, on the frames both counted: largest difference.
    worst, total = 0, 0
    for a, b in zip(ours["inside"], peer["inside"]):
        for x, y in zip(a, b):
            worst = max(worst, abs(x - y))
            total += x
    return worst, total

print("%d frames of %s, %d boxes, 640x480 depth, %d cores" % (ours["frames"], "tum_fr1_rpy", ours["boxes"], ours["cores"]))
print()
print("%-22s %14s %14s" % ("labeling", "ms/frame", "ours faster by"))
print("%-22s %14.2f %14s" % ("olt", ours["median_label_ms"], "1.0x"))
for p in peers:
    print("%-22s %14.2f %13.0fx" % (p["name"], p["median_ms"], p["median_ms"] / ours["median_label_ms"]))
    if "median_ms_with_cloud" in p:
        name = p["name"] + " + cloud"
        print("%-22s %14.2f %13.0fx" % (name, p["median_ms_with_cloud"], p["median_ms_with_cloud"] / ours["median_label_ms"]))
print()
print("olt per frame, one core (medians): read depth PNG %.2f ms, label %.2f ms, write class + instance PNGs %.2f ms,"
      % (ours["median_read_ms"], ours["median_label_ms"], ours["median_write_ms"]))
print("  all together %.2f ms = %.0f frames/s on one core; %.0f frames/s on %d cores"
      % (ours["median_total_ms"], ours["fps_one_core"], ours["fps_all_cores"], ours["cores"]))
e = ours["one_box_edit"]
print("one box (%s) moved, on the %d frames that see it: label afresh %.2f ms; relabel from the previous labels"
      " %.2f ms + decode them %.2f ms = %.2fx" % (e["box"], e["frames_seeing"], e["median_label_afresh_ms"],
      e["median_relabel_ms"], e["median_decode_previous_ms"],
      (e["median_relabel_ms"] + e["median_decode_previous_ms"]) / e["median_label_afresh_ms"]))
print()
for p in peers:
    worst, total = agreement(p)
    print("agreement with %s on %d frames: points inside each box (each alone) differ by at most %d of %d"
          % (p["name"], min(len(ours["inside"]), len(p["inside"])), worst, total))
print("labeling: olt = all boxes with the overlap rule, class and instance images, per-box counts;")
print("peers = the point-in-box tests alone (+ cloud: and building the point cloud). Medians; PNG decoding excluded.")
PY
