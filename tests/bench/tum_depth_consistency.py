#!/usr/bin/python3
"""How well a trajectory makes a TUM recording's depth images agree with each other.

Every depth image (every 4th pixel, 0.4-3 m, the tum_fr1 calibration) is placed by the trajectory;
for each, the share of its points within 1 cm of the points of the images at least 3 frames away.
A pose error or a wrong camera model shows as a lower share. The motion-capture ground truth is
scored as it is and with a rolling shutter modelled (each pixel row placed at its own capture time,
READOUT seconds from the first row to the last, centred on the stamp), then each trajectory given.

  /usr/bin/python3 tests/bench/tum_depth_consistency.py ../shared/data/tum_fr1_rpy [TRAJECTORY ...]

Needs Debian's python3-numpy, python3-scipy and python3-opencv.
"""
import sys

import cv2
import numpy as np
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation, Slerp

FX, FY, CX, CY = 517.3, 516.5, 318.6, 255.3
DISTORTION = np.array([0.2624, -0.9531, -0.0054, 0.0026, 1.1633])
STRIDE, NEAR_M, FAR_M, AGREE_M, TIME_OFFSET_S = 4, 0.4, 3.0, 0.01, -0.02


def read_trajectory(path):
    rows = np.array([[float(x) for x in line.split()] for line in open(path)
                     if line.strip() and not line.startswith("#")])
    return rows[:, 0], rows[:, 1:4], Slerp(rows[:, 0], Rotation.from_quat(rows[:, 4:8]))


def depth_points(data):
    """Per depth image: its stamp, points in the camera frame and the pixel row of each."""
    u, v = np.meshgrid(np.arange(0, 640, STRIDE), np.arange(0, 480, STRIDE))
    pixels = np.stack([u.ravel(), v.ravel()], 1).astype(np.float64).reshape(-1, 1, 2)
    K = np.array([[FX, 0, CX], [0, FY, CY], [0, 0, 1]])
    rays = cv2.undistortPoints(pixels, K, DISTORTION).reshape(-1, 2)
    frames = []
    for line in open(data + "/depth.txt"):
        if line.startswith("#") or not line.strip():
            continue
        stamp, name = line.split()
        z = cv2.imread(data + "/" + name, cv2.IMREAD_UNCHANGED)[::STRIDE, ::STRIDE].ravel() / 5000.0
        ok = (z > NEAR_M) & (z < FAR_M)
        frames.append((float(stamp), np.stack([rays[ok, 0] * z[ok], rays[ok, 1] * z[ok], z[ok]], 1), v.ravel()[ok]))
    return frames


def placed(frames, trajectory, time_offset_s, readout_s):
    t, positions, rotations = trajectory
    world = []
    for stamp, points, rows in frames:
        times = np.clip(stamp + time_offset_s + (rows / 480.0 - 0.5) * readout_s, t[0], t[-1])
        R = rotations(times).as_matrix()
        p = np.stack([np.interp(times, t, positions[:, k]) for k in range(3)], 1)
        world.append(np.einsum("nij,nj->ni", R, points) + p)
    return world


def agreement(world):
    shares = []
    for i in range(len(world)):
        others = np.concatenate([world[j][::3] for j in range(len(world)) if abs(i - j) >= 3])
        distances, _ = cKDTree(others).query(world[i][::2])
        shares.append(np.mean(distances < AGREE_M))
    return np.array(shares)


def main():
    data = sys.argv[1]
    frames = depth_points(data)
    truth = read_trajectory(data + "/groundtruth.txt")
    print("%-58s %8s %8s" % ("poses", "mean", "min"))
    cases = [("motion capture, global shutter", truth, TIME_OFFSET_S, 0.0)]
    for readout in (0.02, 0.033, -0.02):
        cases.append(("motion capture, rolling shutter %+.0f ms" % (readout * 1000), truth, TIME_OFFSET_S, readout))
    for path in sys.argv[2:]:  # OLT trajectories are stamped at capture time already
        cases.append((path[-58:], read_trajectory(path), 0.0, 0.0))
    for name, trajectory, offset, readout in cases:
        shares = agreement(placed(frames, trajectory, offset, readout))
        print("%-58s %8.3f %8.3f" % (name, shares.mean(), shares.min()), flush=True)
    print("share of each depth image's points within %.0f cm of the other images' (3+ frames away)" % (AGREE_M * 100))


if __name__ == "__main__":
    main()
