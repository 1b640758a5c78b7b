#!/usr/bin/env bash
# Laser benchmark, one table per part:
#  1. the real SENA loop (224 SICK scans): our map's robot poses and MRPT icp-slam's (the tool the
#     paper used, with its demo config for this very log) against the 99 reference keyframe poses,
#     after a least-squares rigid alignment (olt eval poses: ATE translation and rotation), and the
#     time to map (ours: median of 5 builds; icp-slam: its own "total time", median of 5 runs);
#  2. the synthetic 4-camera robot: camera pose errors and label agreement with laser poses, with
#     and without refinement by registration.
#   bash tests/bench/laser_bench.sh OLT MAP_BENCH POSES_BENCH SHARED_DATA_DIR ROBOT_JOB
# icp-slam comes from Debian's mrpt-apps and mrpt-common; its row is left out, with a note, without it.
set -euo pipefail
olt=$1
map_bench=$2
poses_bench=$3
data=$4
robot_job=$5
text="$data/mrpt_laser/text"
rawlog="$data/mrpt_laser/original_mrpt/sena_telecom_one_loop.rawlog"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

if [ ! -f "$text/sena_scans.txt" ]; then
  echo "skipped the SENA loop: $text is absent"
else
  # The reference: each keyframe's pose at its scan's timestamp, as a TUM trajectory.
  awk 'NR == FNR { if ($1 !~ /^#/) t[$1] = $2; next }
       $1 !~ /^#/ { printf "%.6f %.6f %.6f 0 0 0 %.9f %.9f\n", t[$1], $2, $3, sin($5 / 2), cos($5 / 2) }' \
    "$text/malaga_cs_fac_map_scans.txt" "$text/malaga_cs_fac_map_keyframes.txt" > "$work/reference.tum"
  ours=$("$map_bench" "$text/sena_scans.txt" "$text/sena_odometry.txt" "$work")
  rows="$work/rows.txt"
  judge() {  # name, trajectory, seconds
    echo "$1 $3 $("$olt" eval poses "$2" "$work/reference.tum" --json | tr -d '\n ')" >> "$rows"
  }
  judge olt_laser_map "$work/olt_laser_map.tum" "$(echo "$ours" | sed 's/.*"seconds":\([0-9.e-]*\).*/\1/')"
  ini=/usr/share/mrpt/config_files/icp-slam/icp-slam_demo_classic.ini
  if command -v icp-slam > /dev/null && [ -f "$ini" ] && [ -f "$rawlog" ]; then
    sed -e "s|^rawlog_file=.*|rawlog_file=$rawlog|" -e "s|^logOutput_dir=.*|logOutput_dir=$work/icp|" \
        -e "s|^SHOW_PROGRESS_3D_REAL_TIME=.*|SHOW_PROGRESS_3D_REAL_TIME=0|" -e "s|^SAVE_3D_SCENE=.*|SAVE_3D_SCENE=0|" \
        -e "s|^LOG_FREQUENCY=.*|LOG_FREQUENCY=0|" "$ini" > "$work/icp.ini"
    times=()
    for _ in 1 2 3 4 5; do
      rm -rf "$work/icp"
      times+=("$(icp-slam "$work/icp.ini" 2>&1 | sed -n 's/.*total time: \([0-9.]*\) sec.*/\1/p')")
    done
    median=$(printf '%s\n' "${times[@]}" | sort -g | sed -n 3p)
    # Its path (step x y phi, one line per scan) at the scans' timestamps.
    awk 'NR == FNR { if ($1 !~ /^#/) t[$1] = $2; next }
         { printf "%.6f %.6f %.6f 0 0 0 %.9f %.9f\n", t[$1], $2, $3, sin($4 / 2), cos($4 / 2) }' \
      "$text/sena_scans.txt" "$work/icp/log_estimated_path.txt" > "$work/icp_slam.tum"
    judge mrpt_icp_slam "$work/icp_slam.tum" "$median"
  else
    echo "(MRPT icp-slam not installed: apt-get install mrpt-apps mrpt-common; its row is left out)"
  fi
  judge raw_odometry "$work/raw_odometry.tum" nan
  echo "SENA loop, 224 real scans: robot poses against the 99 reference keyframes (rigid 2D alignment)"
  echo "map: $ours"
  /usr/bin/python3 - "$rows" <<'PY'
import json, sys
rows = []
for line in open(sys.argv[1]):
    name, seconds, j = line.split(" ", 2)
    e = json.loads(j)
    rows.append((name, e["ate_m"]["rmse"], e["ate_m"]["max"], e["ate_deg"]["rmse"], e["ate_deg"]["max"], float(seconds)))
print("%-16s %9s %9s %10s %10s %9s" % ("method", "t RMSE m", "t max m", "yaw RMSE", "yaw max", "seconds"))
for r in rows:
    print("%-16s %9.4f %9.3f %10.3f %10.3f %9.3f" % r)
peer = [r for r in rows if r[0] == "mrpt_icp_slam"]
if peer:
    p, o = peer[0], rows[0]
    print("ratios icp-slam / ours (above 1: OLT better or faster): translation %.2f, yaw %.2f, time %.2f"
          % (p[1] / o[1], p[3] / o[3], p[5] / o[5]))
PY
fi
echo
if [ -f "$robot_job" ]; then
  "$poses_bench" "$olt" "$robot_job"
fi
