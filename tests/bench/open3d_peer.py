"""The peer a user would pick instead of OLT's registration: Open3D (Debian python3-open3d).

Runs one method over a TUM RGB-D folder, frame to frame with a constant-velocity initial guess,
writes the estimated trajectory (TUM format) and prints one JSON line with the median
milliseconds per frame (image decoding excluded) and the peak resident memory.
    /usr/bin/python3 open3d_peer.py DATASET_DIR METHOD OUT_TRAJECTORY [VOXEL_M]
METHOD: rgbd_hybrid | icp_point_to_plane | gicp | colored_icp | posegraph; VOXEL_M: downsampling voxel (0.02, the
peers' best). posegraph is not frame to frame: GICP odometry plus loop closures, one pose graph (see pose_graph()).
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


# The pose-graph row's own settings (the registration ones, VOXEL, MAX_CORR, DEPTH_TRUNC, are the GICP row's)
KEY_EVERY = 5            # every 5th frame is a keyframe (Open3D's reconstruction system: n_keyframes_per_n_frame 5)
LOOP_ANGLE_DEG = 30.0    # an earlier keyframe is a loop candidate within this view angle of the later one ...
LOOP_DISTANCE_M = 0.3    # ... and this distance, both from the odometry's estimate
LOOP_MIN_OVERLAP = 0.3   # accepted when correspondences / the smaller cloud's points reach this (as Open3D's
                         # reconstruction system's register_fragments)


def pose_graph(root, intrinsic, depths, criteria):
    """Open3D's multiway registration (its "Multiway registration" tutorial and the reconstruction system's
    make_fragments), on the frames rather than on fragments.

    1. Odometry: each frame's cloud (create_from_depth_image, stride 2, depth up to DEPTH_TRUNC; TUM's Kinect gives
       nothing nearer than 0.7 m, so the 0.3 m lower bound needs no filter, as in the other rows; voxel_down_sample
       VOXEL) registered to the previous one with registration_generalized_icp, MAX_CORR, 30 iterations and the
       constant-velocity guess: the open3d_gicp row exactly (the GICP row's voxel, 2 cm, is the best frame-to-frame
       Open3D row). The normals GICP derives its covariances from (20 neighbours) are computed once per cloud with
       estimate_normals(KDTreeSearchParamKNN(20)), which gives GICP the same covariances as it computes itself,
       since every cloud is registered more than once here. Each pair is a certain PoseGraphEdge.
    2. Loop closures: every KEY_EVERY-th frame is a keyframe; each keyframe is registered (the same GICP, started
       from the odometry's relative pose) to every earlier keyframe within LOOP_ANGLE_DEG and LOOP_DISTANCE_M of it,
       and the pair becomes an uncertain PoseGraphEdge when its overlap is at least LOOP_MIN_OVERLAP.
    3. Information matrices for all edges: get_information_matrix_from_point_clouds at 1.5 voxels (the tutorial's
       max_correspondence_distance_fine; the registration itself uses MAX_CORR).
    4. global_optimization with GlobalOptimizationLevenbergMarquardt, the default convergence criteria and
       GlobalOptimizationOption(max_correspondence_distance=1.5 voxels, edge_prune_threshold=0.25,
       reference_node=0) (preference_loop_closure at its default, 1, as in the tutorial); its line process prunes
       wrong loop closures. The optimised node poses are the trajectory.
    The loop closures and the optimisation run once, after the odometry (as in Open3D's pipeline); their time is
    spread evenly over the frames: a frame's milliseconds are its own cloud, odometry and information matrix plus
    1/N of the loop closures' and the optimisation's, and the row's figure is the median of these (mean_ms: the
    mean). Nothing random: repeated runs give the same trajectory (three runs were identical to the last digit).
    """
    reg = o3d.pipelines.registration
    estimation = reg.TransformationEstimationForGeneralizedICP()
    fine = 1.5 * VOXEL
    graph = reg.PoseGraph()
    clouds, poses, times = [], [], []  # poses: world_T_frame, the first frame the world
    velocity = np.eye(4)
    for index, (stamp, name) in enumerate(depths):
        depth_img = o3d.io.read_image(root + "/" + name)
        start = time.perf_counter()
        cloud = o3d.geometry.PointCloud.create_from_depth_image(
            depth_img, intrinsic, depth_scale=5000.0, depth_trunc=DEPTH_TRUNC, stride=2).voxel_down_sample(VOXEL)
        cloud.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(20))
        if index == 0:
            pose = np.eye(4)
        else:
            # T_previous_current, as the frame-to-frame rows
            relative = reg.registration_generalized_icp(
                cloud, clouds[-1], MAX_CORR, velocity, estimation, criteria).transformation
            velocity = relative
            pose = poses[-1] @ relative
            # An edge's transformation takes its source's points into its target's frame
            forward = np.linalg.inv(relative)
            info = reg.get_information_matrix_from_point_clouds(clouds[-1], cloud, fine, forward)
            graph.edges.append(reg.PoseGraphEdge(index - 1, index, forward, info, uncertain=False))
        graph.nodes.append(reg.PoseGraphNode(pose))
        times.append((time.perf_counter() - start) * 1000)
        clouds.append(cloud)
        poses.append(pose)

    start = time.perf_counter()
    keys = range(0, len(clouds), KEY_EVERY)
    tried = accepted = 0
    for i in keys:
        for j in keys:
            if j >= i:
                break
            guess = np.linalg.inv(poses[i]) @ poses[j]  # T_i_j
            angle = np.degrees(np.arccos(np.clip((np.trace(guess[:3, :3]) - 1) / 2, -1, 1)))
            if angle > LOOP_ANGLE_DEG or np.linalg.norm(guess[:3, 3]) > LOOP_DISTANCE_M:
                continue
            tried += 1
            T = reg.registration_generalized_icp(
                clouds[j], clouds[i], MAX_CORR, guess, estimation, criteria).transformation
            info = reg.get_information_matrix_from_point_clouds(clouds[j], clouds[i], fine, T)
            if info[5, 5] / min(len(clouds[j].points), len(clouds[i].points)) < LOOP_MIN_OVERLAP:
                continue
            accepted += 1
            graph.edges.append(reg.PoseGraphEdge(j, i, T, info, uncertain=True))
    edges = len(graph.edges)
    reg.global_optimization(
        graph, reg.GlobalOptimizationLevenbergMarquardt(), reg.GlobalOptimizationConvergenceCriteria(),
        reg.GlobalOptimizationOption(max_correspondence_distance=fine, edge_prune_threshold=0.25, reference_node=0))
    back_end_ms = (time.perf_counter() - start) * 1000
    times = [t + back_end_ms / len(times) for t in times]
    poses = [(stamp, np.array(node.pose)) for (stamp, _), node in zip(depths, graph.nodes)]
    stats = {"mean_ms": float(np.mean(times)), "back_end_ms": back_end_ms, "loop_candidates": tried,
             "loop_edges": accepted, "loop_edges_kept": accepted - (edges - len(graph.edges))}
    return poses, times, stats


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

    poses, times, stats = [], [], {}
    previous, velocity = None, np.eye(4)
    if method == "posegraph":
        poses, times, stats = pose_graph(root, intrinsic, depths, criteria)
        depths = []
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
                      "peak_mb": peak_mb, **stats}))


if __name__ == "__main__":
    main()
