"""The peer a user would pick instead of OLT's registration: Open3D (Debian python3-open3d).

Runs one method over a TUM RGB-D folder, frame to frame with a constant-velocity initial guess,
writes the estimated trajectory (TUM format) and prints one JSON line with the median
milliseconds per frame (image decoding excluded) and the peak resident memory.
    /usr/bin/python3 open3d_peer.py DATASET_DIR METHOD OUT_TRAJECTORY [VOXEL_M]
METHOD: rgbd_hybrid | icp_point_to_plane | gicp | colored_icp; VOXEL_M: downsampling voxel (0.02, the peers' best)
"""
import json
import resource
import sys
import time

import numpy as np
import open3d as o3d

VOXEL = 0.02        # metres, the setting at which the peers do best
MAX_CORR = 0.1      # metres, as our default
DEPTH_TRUNC = 4.0   # metres, as our default
FX, FY, CX, CY = 517.3, 516.5, 318.6, 255.3  # TUM fr1 (Open3D's models have no distortion)


def read_list(path):
    entries = []
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        stamp, name = line.split()[:2]
        entries.append((float(stamp), name))
    return entries


def nearest(entries, t):
    return min(entries, key=lambda e: abs(e[0] - t))


def quaternion(R):
    w = np.sqrt(max(0.0, 1 + R[0, 0] + R[1, 1] + R[2, 2])) / 2
    x = np.sqrt(max(0.0, 1 + R[0, 0] - R[1, 1] - R[2, 2])) / 2
    y = np.sqrt(max(0.0, 1 - R[0, 0] + R[1, 1] - R[2, 2])) / 2
    z = np.sqrt(max(0.0, 1 - R[0, 0] - R[1, 1] + R[2, 2])) / 2
    x = np.copysign(x, R[2, 1] - R[1, 2])
    y = np.copysign(y, R[0, 2] - R[2, 0])
    z = np.copysign(z, R[1, 0] - R[0, 1])
    return x, y, z, w


def main():
    global VOXEL
    root, method, out_path = sys.argv[1], sys.argv[2], sys.argv[3]
    row_name = "open3d_" + method
    if len(sys.argv) > 4:
        VOXEL = float(sys.argv[4])
        row_name += "_%gcm" % (VOXEL * 100)
    o3d.utility.set_verbosity_level(o3d.utility.VerbosityLevel.Error)
    intrinsic = o3d.camera.PinholeCameraIntrinsic(640, 480, FX, FY, CX, CY)
    depths = read_list(root + "/depth.txt")
    colors = read_list(root + "/rgb.txt")
    criteria = o3d.pipelines.registration.ICPConvergenceCriteria(max_iteration=30)

    def prepare(depth_img, color_img):
        if method == "rgbd_hybrid":
            return o3d.geometry.RGBDImage.create_from_color_and_depth(
                color_img, depth_img, depth_scale=5000.0, depth_trunc=DEPTH_TRUNC, convert_rgb_to_intensity=True)
        if method == "colored_icp":  # points with their colours (Park et al. 2017)
            rgbd = o3d.geometry.RGBDImage.create_from_color_and_depth(
                color_img, depth_img, depth_scale=5000.0, depth_trunc=DEPTH_TRUNC, convert_rgb_to_intensity=False)
            cloud = o3d.geometry.PointCloud.create_from_rgbd_image(rgbd, intrinsic)
        else:
            cloud = o3d.geometry.PointCloud.create_from_depth_image(
                depth_img, intrinsic, depth_scale=5000.0, depth_trunc=DEPTH_TRUNC, stride=2)
        cloud = cloud.voxel_down_sample(VOXEL)
        if method in ("icp_point_to_plane", "colored_icp"):
            cloud.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(10))
        return cloud

    def register(source, target, init):
        if method == "rgbd_hybrid":
            ok, T, _ = o3d.pipelines.odometry.compute_rgbd_odometry(
                source, target, intrinsic, init, o3d.pipelines.odometry.RGBDOdometryJacobianFromHybridTerm(),
                o3d.pipelines.odometry.OdometryOption())
            return T if ok else init
        if method == "icp_point_to_plane":
            estimation = o3d.pipelines.registration.TransformationEstimationPointToPlane()
            return o3d.pipelines.registration.registration_icp(
                source, target, MAX_CORR, init, estimation, criteria).transformation
        if method == "colored_icp":
            return o3d.pipelines.registration.registration_colored_icp(
                source, target, MAX_CORR, init, o3d.pipelines.registration.TransformationEstimationForColoredICP(),
                criteria).transformation
        estimation = o3d.pipelines.registration.TransformationEstimationForGeneralizedICP()
        return o3d.pipelines.registration.registration_generalized_icp(
            source, target, MAX_CORR, init, estimation, criteria).transformation

    poses, times = [], []
    previous, velocity = None, np.eye(4)
    for stamp, name in depths:
        depth_img = o3d.io.read_image(root + "/" + name)
        color_img = o3d.io.read_image(root + "/" + nearest(colors, stamp)[1])
        start = time.perf_counter()
        current = prepare(depth_img, color_img)
        if previous is None:
            pose = np.eye(4)
        else:
            # T_previous_current; the guess assumes the same motion as between the last two frames
            relative = register(current, previous, velocity)
            velocity = relative
            pose = poses[-1][1] @ relative
        times.append((time.perf_counter() - start) * 1000)
        poses.append((stamp, pose))
        previous = current
    with open(out_path, "w") as out:
        for stamp, T in poses:
            x, y, z, w = quaternion(T[:3, :3])
            out.write("%.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n" % (stamp, *T[:3, 3], x, y, z, w))
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    print(json.dumps({"name": row_name, "frames": len(poses), "median_ms": float(np.median(times)),
                      "peak_mb": peak_mb}))


if __name__ == "__main__":
    main()
