#include "olt/model/pose_quality.h"

namespace olt {
namespace {

using json = nlohmann::json;

json to_json(const RegistrationQuality& r) {
  json q = {{"key", r.key}};
  if (r.first) q["first"] = true;
  if (r.fit) {
    const RegistrationQuality::Fit& f = *r.fit;
    q["converged"] = f.converged;
    q["iterations"] = f.iterations;
    q["inliers"] = f.inliers;
    q["inlier_ratio"] = f.inlier_ratio;
    q["rmse_m"] = f.rmse_m;
    q["source_points"] = f.source_points;
    q["target_points"] = f.target_points;
    if (f.photometric_points) q["photometric_points"] = *f.photometric_points;
    if (f.photometric_rmse) q["photometric_rmse"] = *f.photometric_rmse;
  }
  if (r.refined) q["refined"] = *r.refined;
  if (!r.not_refined.empty()) q["not_refined"] = r.not_refined;
  if (r.keyframe) q["keyframe"] = *r.keyframe;
  if (r.new_keyframe) q["new_keyframe"] = true;
  return q;
}

RegistrationQuality registration_from_json(const json& q) {
  RegistrationQuality r;
  r.key = q.at("key");
  r.first = q.value("first", false);
  if (q.contains("converged")) {
    RegistrationQuality::Fit f;
    f.converged = q.at("converged");
    f.iterations = q.at("iterations");
    f.inliers = q.at("inliers");
    f.inlier_ratio = q.at("inlier_ratio");
    f.rmse_m = q.at("rmse_m");
    f.source_points = q.at("source_points");
    f.target_points = q.at("target_points");
    if (q.contains("photometric_points")) f.photometric_points = q["photometric_points"].get<int>();
    if (q.contains("photometric_rmse")) f.photometric_rmse = q["photometric_rmse"].get<double>();
    r.fit = f;
  }
  if (q.contains("refined")) r.refined = q["refined"].get<bool>();
  r.not_refined = q.value("not_refined", "");
  if (q.contains("keyframe")) r.keyframe = q["keyframe"].get<uint64_t>();
  r.new_keyframe = q.value("new_keyframe", false);
  return r;
}

json to_json(const ScanQuality& s) {
  return {{"scan_before", s.scan_before}, {"scan_after", s.scan_after}, {"scan_gap_s", s.scan_gap_s}};
}

ScanQuality scan_from_json(const json& q) { return {q.at("scan_before"), q.at("scan_after"), q.at("scan_gap_s")}; }

}  // namespace

json to_json(const PoseQuality& q) {
  if (q.empty()) return nullptr;
  json out = json::object();
  if (q.laser && q.registration)
    out = {{"laser", to_json(*q.laser)}, {"registration", to_json(*q.registration)}};
  else if (q.laser)
    out = to_json(*q.laser);
  else if (q.registration)
    out = to_json(*q.registration);
  if (q.consistency) {
    const ConsistencyQuality& c = *q.consistency;
    out["consistency"] = {
        {"fraction", c.fraction}, {"coverage", c.coverage}, {"rmse_m", c.rmse_m}, {"points", c.points}};
  }
  return out;
}

PoseQuality pose_quality_from_json(const json& j) {
  PoseQuality q;
  if (j.is_null()) return q;
  if (j.contains("laser")) {
    q.laser = scan_from_json(j.at("laser"));
    q.registration = registration_from_json(j.at("registration"));
  } else if (j.contains("scan_before")) {
    q.laser = scan_from_json(j);
  } else if (j.contains("key")) {
    q.registration = registration_from_json(j);
  }
  if (j.contains("consistency")) {
    const json& c = j["consistency"];
    q.consistency = ConsistencyQuality{c.at("fraction"), c.at("coverage"), c.at("rmse_m"), c.at("points")};
  }
  return q;
}

}  // namespace olt
