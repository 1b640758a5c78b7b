// The `poses` stage's params tables: every key, its range and its one-line doc, declared once per
// settings struct and nested in YAML as the structs are (registration.solver.method,
// laser.matching.huber_m, consistency.distance_m). The flat keys of earlier versions are accepted as
// old spellings.
#include "poses_config.h"

namespace olt {
namespace {

std::shared_ptr<const Params<RegistrationSetting>> solver_params() {
  static auto p = [] {
    auto t = std::make_shared<Params<RegistrationSetting>>();
    t->choice("method", &RegistrationSetting::method,
              Names<RegistrationMethod>{{"gicp", RegistrationMethod::gicp}, {"icp", RegistrationMethod::icp}},
              "gicp or point-to-plane icp")
        .number("max_correspondence_m", &RegistrationSetting::max_correspondence_m, positive(),
                "farthest correspondence, metres")
        .integer("max_iterations", &RegistrationSetting::max_iterations, between(1, 1000),
                 "Gauss-Newton iterations at most")
        .number("translation_eps_m", &RegistrationSetting::translation_eps_m, positive(),
                "convergence threshold, metres")
        .number("rotation_eps_rad", &RegistrationSetting::rotation_eps_rad, positive(),
                "convergence threshold, radians");
    return t;
  }();
  return p;
}

std::shared_ptr<const Params<RegistrationPosesConfig>> registration_params() {
  static auto p = [] {
    auto t = std::make_shared<Params<RegistrationPosesConfig>>();
    t->nested("solver", &RegistrationPosesConfig::solver, solver_params(), "the ICP / GICP solver")
        .number("voxel_size_m", &RegistrationPosesConfig::voxel_size_m, between(0.001, 1), "registration voxel, metres")
        .integer("pixel_stride", &RegistrationPosesConfig::pixel_stride, between(1, 32),
                 "every n-th pixel per direction")
        .number("min_depth_m", &RegistrationPosesConfig::min_depth_m, non_negative(),
                "registration depth range, metres")
        .number("max_depth_m", &RegistrationPosesConfig::max_depth_m, positive(), "registration depth range, metres")
        .integer("covariance_neighbors", &RegistrationPosesConfig::covariance_neighbors, between(5, 100),
                 "k for covariances")
        .number("photometric_weight", &RegistrationPosesConfig::photometric_weight, non_negative(),
                "colour term weight (0 = depth only)")
        .integer("photometric_halvings", &RegistrationPosesConfig::photometric_halvings, between(0, 2),
                 "colour term on images halved this many times")
        .number("photometric_min_gradient", &RegistrationPosesConfig::photometric_min_gradient, non_negative(),
                "colour term: least intensity gradient per reduced pixel")
        .number("photometric_huber", &RegistrationPosesConfig::photometric_huber, positive(),
                "colour term: Huber threshold, intensity in [0, 1]")
        .boolean("smoothing", &RegistrationPosesConfig::smoothing, "bilateral depth smoothing before registration")
        .number("sigma_s_px", &RegistrationPosesConfig::sigma_s_px, between(0.5, 20), "smoothing spatial sigma, pixels")
        .number("sigma_r_m", &RegistrationPosesConfig::sigma_r_m, positive(), "smoothing range sigma, metres")
        .choice("memory", &RegistrationPosesConfig::memory,
                Names<RegistrationMemory>{{"keyframes", RegistrationMemory::keyframes},
                                          {"previous", RegistrationMemory::previous},
                                          {"local_map", RegistrationMemory::local_map}},
                "registration target: keyframes with loop closures, the previous observation, or a local map")
        .number("keyframe_distance_m", &RegistrationPosesConfig::keyframe_distance_m, positive(),
                "keyframes: a new one after moving this far from the last, metres")
        .number("keyframe_angle_deg", &RegistrationPosesConfig::keyframe_angle_deg, positive(),
                "keyframes: ... or turning this much, degrees")
        .integer("loop_candidates", &RegistrationPosesConfig::loop_candidates, between(0, 100),
                 "keyframes: earlier keyframes each new one is registered against (0 = no loop closure)")
        .number("loop_max_distance_m", &RegistrationPosesConfig::loop_max_distance_m, positive(),
                "keyframes: loop candidates' camera centres at most this far apart, metres")
        .number("loop_max_angle_deg", &RegistrationPosesConfig::loop_max_angle_deg, between(0, 180),
                "keyframes: ... and optical axes at most this far apart, degrees")
        .number("loop_min_inlier_ratio", &RegistrationPosesConfig::loop_min_inlier_ratio, between(0, 1),
                "keyframes: a loop closure matches at least this fraction of points")
        .number("loop_max_correction_m", &RegistrationPosesConfig::loop_max_correction_m, positive(),
                "keyframes: ... and moves a keyframe at most this far from its estimate, metres")
        .number("loop_max_correction_deg", &RegistrationPosesConfig::loop_max_correction_deg, positive(),
                "keyframes: ... and turns it at most this much, degrees")
        .integer("memory_size", &RegistrationPosesConfig::memory_size, between(1, 1000), "local_map size, observations")
        .number("key_distance_m", &RegistrationPosesConfig::key_distance_m, non_negative(),
                "key pose distance, metres (0 = off)")
        .number("key_angle_deg", &RegistrationPosesConfig::key_angle_deg, non_negative(),
                "key pose angle, degrees (0 = off)")
        .number("key_max_interval_s", &RegistrationPosesConfig::key_max_interval_s, positive(),
                "key pose at least this often, s")
        .choice("initial_guess", &RegistrationPosesConfig::initial_guess,
                Names<InitialGuess>{{"constant_velocity", InitialGuess::constant_velocity},
                                    {"previous_pose", InitialGuess::previous_pose},
                                    {"trajectory", InitialGuess::trajectory}},
                "registration guess")
        .number("max_rmse_m", &RegistrationPosesConfig::max_rmse_m, positive(), "flag above this inlier RMSE, metres")
        .number("min_inlier_ratio", &RegistrationPosesConfig::min_inlier_ratio, between(0, 1),
                "flag below this inlier fraction")
        .number("max_correction_m", &RegistrationPosesConfig::max_correction_m, positive(),
                "refine: keep the laser pose where registration moves it farther, m")
        .number("max_correction_deg", &RegistrationPosesConfig::max_correction_deg, positive(),
                "refine: ... or turns it more, degrees");
    return t;
  }();
  return p;
}

std::shared_ptr<const Params<ConsistencySetting>> consistency_params() {
  static auto p = [] {
    auto t = std::make_shared<Params<ConsistencySetting>>();
    t->number("distance_m", &ConsistencySetting::distance_m, positive(),
              "memory keyframes: a depth point within this distance of the keyframes' scene agrees with it, metres")
        .number("min_fraction", &ConsistencySetting::min_fraction, between(0, 1),
                "memory keyframes: flag observations with a smaller fraction of agreeing points");
    return t;
  }();
  return p;
}

}  // namespace

std::shared_ptr<const Params<PosesConfig>> poses_params() {
  static auto p = [] {
    auto t = std::make_shared<Params<PosesConfig>>();
    t->choice("method", &PosesConfig::method,
              Names<PosesMethod>{{"trajectory", PosesMethod::trajectory},
                                 {"registration", PosesMethod::registration},
                                 {"laser", PosesMethod::laser}},
              "how poses are found")
        .path("trajectory", &PosesConfig::trajectory, true,
              "TUM trajectory file; default: the recording's ground truth")
        .choice("frame", &PosesConfig::frame,
                Names<TrajectoryFrame>{{"sensor", TrajectoryFrame::sensor}, {"robot", TrajectoryFrame::robot}},
                "frame whose pose the trajectory gives")
        .number("max_gap_s", &PosesConfig::max_gap_s, positive(), "largest time to the nearest sample, seconds")
        .path("guess_trajectory", &PosesConfig::guess_trajectory, true,
              "initial_guess trajectory: TUM file of robot poses (e.g. odometry)")
        .path("anchor", &PosesConfig::anchor, true,
              "TUM trajectory of the first observation's sensor pose (e.g. a ground truth)")
        .choice("anchor_fit", &PosesConfig::anchor_fit,
                Names<AnchorFit>{{"first", AnchorFit::first}, {"all", AnchorFit::all}},
                "registration: place the trajectory by the anchor's first pose, or fit it to all of them")
        .boolean("anchor_to_groundtruth", &PosesConfig::anchor_to_groundtruth,
                 "take the first observation's pose from the recording's ground truth")
        .path("map", &PosesConfig::map, true, "laser: map.txt of a laser_map run; default: the laser_map stage")
        .numbers("initial_pose", &PosesConfig::initial_pose, 3,
                 "laser: x y (m) yaw (deg) of the robot at the first scan")
        .number("max_scan_gap_s", &PosesConfig::max_scan_gap_s, positive(),
                "laser: flag observations between scans farther apart, s")
        .choice("refine", &PosesConfig::refine,
                Names<LaserRefine>{{"none", LaserRefine::none}, {"registration", LaserRefine::registration}},
                "laser: refine by registration")
        .nested("registration", &PosesConfig::registration, registration_params(), "method registration: its settings")
        .nested("consistency", &PosesConfig::consistency, consistency_params(),
                "method registration, memory keyframes: each observation scored against the keyframes' scene")
        .nested("laser", &PosesConfig::laser, laser_localization_params(), "method laser: scan matching and ranges")
        .renamed("algorithm", "registration/solver/method")
        .renamed("consistency_distance_m", "consistency/distance_m")
        .renamed("min_consistency", "consistency/min_fraction")
        .renamed_flat("", "registration")
        .renamed_flat("laser_", "laser");
    return t;
  }();
  return p;
}

}  // namespace olt
