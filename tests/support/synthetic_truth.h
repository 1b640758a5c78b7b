#pragma once
// Judges a run of the synthetic recording against its exact truth: each observation's published
// pose against the exact camera pose, and each class image against the object every pixel sees.
#include <filesystem>

#include "olt/source/synthetic.h"

namespace olt::test {

struct SyntheticJudgement {
  int observations = 0;  ///< with a published pose
  double translation_rmse_m = 0, translation_max_m = 0;
  double rotation_rmse_deg = 0, rotation_max_deg = 0;
  int64_t depth_pixels = 0;    ///< pixels with depth in the labeled observations
  double label_agreement = 0;  ///< fraction of them whose class is the exact one
};

/// `out`: the job's output folder (poses stage `poses_stage`, labels from a propagate stage);
/// `config`: the source's synthetic settings; `T_world_output`: where the run's world frame is in
/// the synthetic world (identity when the run was anchored to it).
SyntheticJudgement judge_synthetic_run(const std::filesystem::path& out, const std::string& poses_stage,
                                       const SyntheticConfig& config, const Pose& T_world_output = Pose::Identity());

}  // namespace olt::test
