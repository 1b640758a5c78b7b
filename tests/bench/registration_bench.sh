#!/usr/bin/env bash
# Registration benchmark: OLT's option sets and the Open3D peer on the same TUM frames, one table.
#   bash tests/bench/registration_bench.sh BENCH_BINARY DATASET_DIR      (or: cmake --build build --target bench)
# Needs python3-open3d (Debian) for the peer rows; they are left out, with a note, without it.
set -euo pipefail
bench=$1
data=$2
olt="$(dirname "$bench")/../olt"
if [ ! -f "$data/depth.txt" ]; then
  echo "skipped: $data is absent"
  exit 0
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

rows="$work/rows.jsonl"
ours() {  # name, options...
  "$bench" "$data" "$@" >> "$rows"
}
ours olt_gicp_colour                             # the default: GICP with the colour term, keyframes
ours olt_gicp_colour_no_loops loop_candidates=0  # keyframes without loop closures
ours olt_gicp_colour_previous memory=previous     # frame to frame (the default before keyframes)
ours olt_gicp_colour_full_res photometric_halvings=0
ours olt_icp_colour algorithm=icp
ours olt_gicp_colour_local_map memory=local_map memory_size=5
ours olt_gicp_colour_smoothing smoothing=true
ours olt_gicp_colour_key_poses key_distance_m=0.02 key_angle_deg=1
ours olt_gicp photometric_weight=0                 # depth only
ours olt_gicp_2cm photometric_weight=0 voxel_size_m=0.02
ours olt_icp algorithm=icp photometric_weight=0

if /usr/bin/python3 -c "import open3d" 2>/dev/null; then
  for peer in "gicp" "gicp 0.03" "icp_point_to_plane" "colored_icp" "rgbd_hybrid" "posegraph"; do
    set -- $peer
    line=$(/usr/bin/python3 "$(dirname "$0")/open3d_peer.py" "$data" "$1" "$work/$1.txt" ${2:-})
    errors=$("$olt" eval poses "$work/$1.txt" "$data/groundtruth.txt" --json)
    # The corrected figures, as ours: timestamps moved by the depth clock's lag, ground truth interpolated.
    awk '{ $1 = sprintf("%.6f", $1 - 0.02); print }' "$work/$1.txt" > "$work/$1.shifted.txt"
    corrected=$("$olt" eval poses "$work/$1.shifted.txt" "$data/groundtruth.txt" --json --interpolate)
    /usr/bin/python3 - "$line" "$errors" "$corrected" >> "$rows" <<'PY'
import json, sys
row, e, c = (json.loads(a) for a in sys.argv[1:4])
row.update(ate_m=e["ate_m"]["rmse"], rpe_frame_deg=e["rpe_frame_deg"]["rmse"], rpe_frame_m=e["rpe_frame_m"]["rmse"],
           rpe_second_deg=e["rpe_second_deg"]["rmse"], rpe_second_m=e["rpe_second_m"]["rmse"],
           corrected={"ate_m": c["ate_m"]["rmse"], "rpe_frame_deg": c["rpe_frame_deg"]["rmse"],
                      "rpe_second_deg": c["rpe_second_deg"]["rmse"]})
print(json.dumps(row))
PY
  done
else
  echo "note: python3-open3d is not installed; peer rows left out"
fi

/usr/bin/python3 - "$rows" <<'PY'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
base = rows[0]
print("%-26s %7s %8s %7s %9s %8s %7s %10s %10s" % ("method", "ATE m", "RPE deg", "RPE m", "drift deg", "ms/frame",
                                                 "peak MB", "RPE deg *", "drift deg *"))
for r in rows:
    c = r["corrected"]
    print("%-26s %7.4f %8.3f %7.4f %9.2f %8.1f %7.0f %10.3f %10.2f" % (
        r["name"], r["ate_m"], r["rpe_frame_deg"], r["rpe_frame_m"], r["rpe_second_deg"], r["median_ms"], r["peak_mb"],
        c["rpe_frame_deg"], c["rpe_second_deg"]))
print("\nratios, peer / %s (above 1: OLT is better or faster)" % base["name"])
for r in rows:
    if r["name"].startswith("open3d"):
        c, b = r["corrected"], base["corrected"]
        print("%-26s %7.2f %8.2f %7.2f %9.2f %8.2f %7.2f %10.2f %10.2f" % (
            r["name"], r["ate_m"] / base["ate_m"], r["rpe_frame_deg"] / base["rpe_frame_deg"],
            r["rpe_frame_m"] / base["rpe_frame_m"], r["rpe_second_deg"] / base["rpe_second_deg"],
            r["median_ms"] / base["median_ms"], r["peak_mb"] / base["peak_mb"],
            c["rpe_frame_deg"] / b["rpe_frame_deg"], c["rpe_second_deg"] / b["rpe_second_deg"]))
print("\nATE m: after SE(3) alignment; RPE: per frame pair (RMSE); drift: rotational RPE over 1 s (RMSE);")
print("ms/frame: median, image decoding excluded; %d frames." % base["frames"])
print("open3d_posegraph: GICP odometry, loop closures between keyframes, Open3D's global_optimization (multiway")
print("   registration); its ms/frame spreads the loop closures' and the optimisation's time over the frames.")
print("*: corrected: timestamps moved by the depth clock's -20 ms lag (calibrate time_offset_s) and the")
print("   ground truth interpolated at them (olt eval --interpolate); the other columns are TUM's definition.")
PY
