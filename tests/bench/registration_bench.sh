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
ours olt_gicp
ours olt_icp algorithm=icp
ours olt_gicp_local_map memory=local_map memory_size=5
ours olt_gicp_smoothing smoothing=true
ours olt_gicp_key_poses key_distance_m=0.02 key_angle_deg=1

if /usr/bin/python3 -c "import open3d" 2>/dev/null; then
  for method in gicp icp_point_to_plane rgbd_hybrid; do
    line=$(/usr/bin/python3 "$(dirname "$0")/open3d_peer.py" "$data" "$method" "$work/$method.txt")
    errors=$("$olt" eval poses "$work/$method.txt" "$data/groundtruth.txt" --json)
    /usr/bin/python3 - "$line" "$errors" >> "$rows" <<'PY'
import json, sys
row, e = json.loads(sys.argv[1]), json.loads(sys.argv[2])
row.update(ate_m=e["ate_m"]["rmse"], rpe_frame_deg=e["rpe_frame_deg"]["rmse"], rpe_frame_m=e["rpe_frame_m"]["rmse"],
           rpe_second_deg=e["rpe_second_deg"]["rmse"], rpe_second_m=e["rpe_second_m"]["rmse"])
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
print("%-22s %9s %10s %10s %10s %9s %8s" % ("method", "ATE m", "RPE deg", "RPE m", "drift deg", "ms/frame", "peak MB"))
for r in rows:
    print("%-22s %9.4f %10.3f %10.4f %10.2f %9.1f %8.0f" % (r["name"], r["ate_m"], r["rpe_frame_deg"], r["rpe_frame_m"],
                                                          r["rpe_second_deg"], r["median_ms"], r["peak_mb"]))
print("\nratios, peer / %s (above 1: OLT is better or faster)" % base["name"])
for r in rows:
    if r["name"].startswith("open3d"):
        print("%-22s %9.2f %10.2f %10.2f %10.2f %9.2f %8.2f" % (r["name"], r["ate_m"] / base["ate_m"],
              r["rpe_frame_deg"] / base["rpe_frame_deg"], r["rpe_frame_m"] / base["rpe_frame_m"],
              r["rpe_second_deg"] / base["rpe_second_deg"], r["median_ms"] / base["median_ms"],
              r["peak_mb"] / base["peak_mb"]))
print("\nATE m: after SE(3) alignment; RPE: per frame pair (RMSE); drift: rotational RPE over 1 s (RMSE);")
print("ms/frame: median, image decoding excluded; %d frames." % base["frames"])
PY
