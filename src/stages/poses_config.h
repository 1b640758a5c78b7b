#pragma once
// The `poses` stage's params table and its methods' bodies (config: olt/stages/poses.h), shared by
// the files of the stage: poses_params.cpp, poses_registration.cpp, poses_laser.cpp, poses_stage.cpp.
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "olt/config/params.h"
#include "olt/stages/laser.h"
#include "olt/stages/poses.h"

namespace olt {

std::shared_ptr<const Params<PosesConfig>> poses_params();

/// Reads the observation's colour image when the registration asks for it.
RegistrationOdometry::ColorLoader color_of(const Observation& o);

/// method registration: every observation registered (RegistrationOdometry), with memory keyframes
/// scored against the keyframes' scene; the graph's figures go into `summary`.
std::vector<ObservationPose> registered_poses(const PosesConfig& c, const Recording& recording,
                                              const Calibration& calibration, nlohmann::json& summary);

/// anchor_fit all: the registered trajectory moved as one rigid body onto the anchor trajectory.
void fit_to_anchor(const PosesConfig& c, const Recording& recording, const Calibration& calibration,
                   std::vector<ObservationPose>& poses);

/// method laser: the scans localized in the map, the robot pose interpolated at each observation,
/// refined by registration where asked.
PosesResult laser_poses(const PosesInputs& in, const PosesConfig& c);

}  // namespace olt
