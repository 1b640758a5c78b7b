"""The peer a user would pick in Python: Open3D's oriented boxes (Debian python3-open3d).

Labels the frames of the exchange file that olt_bench_propagation writes: per frame, the depth
image as a world-frame point cloud (create_from_depth_image with the pose as extrinsic, depth_trunc
at the far limit; points nearer than the near limit are dropped with a numpy mask), then every box's
OrientedBoundingBox.get_point_indices_within_bounding_box. Prints one JSON line: median ms per frame
for the box tests alone and with the cloud's creation (PNG decoding excluded), and the number of
points inside each box per frame.
    /usr/bin/python3 propagation_open3d_peer.py EXCHANGE.json [--frames N]
"""
import json
import sys
import time

import numpy as np
import open3d as o3d


def main():
    x = json.load(open(sys.argv[1]))
    frames = x["frames"]
    if len(sys.argv) > 3 and sys.argv[2] == "--frames":
        frames = frames[: int(sys.argv[3])]
    k = x["intrinsics"]
    intrinsic = o3d.camera.PinholeCameraIntrinsic(k["width"], k["height"], k["fx"], k["fy"], k["cx"], k["cy"])
    boxes = []
    for b in x["boxes"]:
        R = np.array(b["rotation"], dtype=float).reshape(3, 3)
        boxes.append(o3d.geometry.OrientedBoundingBox(np.array(b["center"], float), R, np.array(b["size"], float)))
    box_ms, all_ms, inside = [], [], []
    for f in frames:
        depth = o3d.io.read_image(f["depth"])
        T = np.array(f["T_world_sensor"], dtype=float).reshape(4, 4)
        start = time.perf_counter()
        cloud = o3d.geometry.PointCloud.create_from_depth_image(
            depth, intrinsic, np.linalg.inv(T), depth_scale=x["depth_scale"], depth_trunc=x["max_depth_m"], stride=1)
        # Nearer than the near limit: depth along the camera's z, i.e. the point's z in the sensor frame.
        points = np.asarray(cloud.points)
        z = (points - T[:3, 3]) @ T[:3, 2]
        cloud = cloud.select_by_index(np.nonzero(z >= x["min_depth_m"])[0])
        tests_start = time.perf_counter()
        counts = [len(box.get_point_indices_within_bounding_box(cloud.points)) for box in boxes]
        end = time.perf_counter()
        box_ms.append((end - tests_start) * 1000)
        all_ms.append((end - start) * 1000)
        inside.append(counts)
    print(json.dumps({"name": "open3d_obb", "frames": len(frames), "median_ms": float(np.median(box_ms)),
                      "median_ms_with_cloud": float(np.median(all_ms)), "inside": inside}))


if __name__ == "__main__":
    main()
