// labelCloud (labelCloud/io/labels/vertices.py), "vertices" label format: the file of the centroid
// formats, each object {"name": "cup", "vertices": [[x, y, z] x 8]}, the box's corners in
// labelCloud's order (model/bbox.py; docs/conventions.md), local signs of length x, width y,
// height z:
//   0 (-,-,-) left back bottom   1 (-,+,-) left front bottom   2 (+,+,-) right front bottom
//   3 (+,-,-) right back bottom  4 (-,-,+) left back top       5 (-,+,+) left front top
//   6 (+,+,+) right front top    7 (+,-,+) right back top
// The box is recovered from all eight corners, not from three edges of corner 0 as labelCloud's
// import does: centre = their mean, each axis = the mean of its four parallel edges, the axes made
// orthonormal (the rotation nearest to them), and the corners must lie within a tolerance of the
// box so found. Each box is its own instance, "<class>_<index>".
#include <Eigen/SVD>
#include <array>

#include "json_fields.h"
#include "tool_formats.h"

namespace olt {
namespace {

/// OLT's corner index (local signs x: bit 0, y: bit 1, z: bit 2) of labelCloud's vertex k.
constexpr std::array<int, 8> kOltCornerOfVertex = {0, 2, 3, 1, 4, 6, 7, 5};
const char* const kVertexOrder =
    "labelCloud's order: 0 left back bottom, 1 left front bottom, 2 right front bottom, 3 right back bottom, then "
    "4-7 the top corners above them";

/// Corners as labelCloud rounds them (export_precision decimals) stay within this of a true box.
double box_tolerance_m(const Eigen::Vector3d& size) { return 1e-3 + 1e-3 * size.norm(); }

struct FittedBox {
  Eigen::Vector3d center, size;
  Eigen::Matrix3d rotation;
  std::string problem;  ///< why the corners are not a box, "" when they are
};

FittedBox fit_box(const std::array<Eigen::Vector3d, 8>& corner) {  // indexed as OLT's corners
  FittedBox fit;
  fit.center = Eigen::Vector3d::Zero();
  for (const auto& c : corner) fit.center += c / 8;
  Eigen::Matrix3d axes;
  for (int a = 0; a < 3; ++a) {
    Eigen::Vector3d edge = Eigen::Vector3d::Zero();  // the mean of the four edges along axis a
    for (int i = 0; i < 8; ++i) edge += ((i >> a) & 1 ? 0.25 : -0.25) * corner[i];
    fit.size[a] = edge.norm();
    if (!(fit.size[a] > 1e-12)) {
      fit.problem = std::string("the corners have no extent along the box's ") + "xyz"[a];
      return fit;
    }
    axes.col(a) = edge / fit.size[a];
  }
  if (!fit.center.allFinite() || !fit.size.allFinite()) {
    fit.problem = "the corners are too far out to add up in double precision";
    return fit;
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(axes, Eigen::ComputeFullU | Eigen::ComputeFullV);
  fit.rotation = svd.matrixU() * svd.matrixV().transpose();
  if (fit.rotation.determinant() < 0) {
    fit.problem = std::string("the corners are mirrored (a left-handed box), not in ") + kVertexOrder;
    return fit;
  }
  double worst = 0;
  int worst_vertex = 0;
  for (int k = 0; k < 8; ++k) {
    const int i = kOltCornerOfVertex[k];
    const Eigen::Vector3d sign((i & 1) ? 0.5 : -0.5, (i & 2) ? 0.5 : -0.5, (i & 4) ? 0.5 : -0.5);
    const double off = (fit.center + fit.rotation * sign.cwiseProduct(fit.size) - corner[i]).norm();
    if (off > worst) worst = off, worst_vertex = k;
  }
  if (!(worst <= box_tolerance_m(fit.size)))
    fit.problem = "the corners do not form a box: vertex " + std::to_string(worst_vertex) + " is " +
                  std::to_string(worst) + " m from the box fitted to all eight (tolerance " +
                  std::to_string(box_tolerance_m(fit.size)) + " m); expected " + kVertexOrder;
  return fit;
}

}  // namespace

BoxFile read_labelcloud_vertices(const std::string& file, const std::string& text) {
  const Document doc = parse_json_document(file, text);
  FieldReader reader(doc);
  std::vector<Box> boxes;
  const nlohmann::json& objects = labelcloud_objects(reader, "vertices");
  for (size_t i = 0; objects.is_array() && i < objects.size(); ++i) {
    const std::string at = "/objects/" + std::to_string(i), name = "objects[" + std::to_string(i) + "]";
    const std::string label = reader.text(at + "/name", name + ".name");
    const nlohmann::json& vertices = reader.at(at + "/vertices", name + ".vertices");
    if (vertices.is_null()) continue;
    if (!vertices.is_array() || vertices.size() != 8) {
      reader.error(at + "/vertices", name + ".vertices: expected 8 corners [x, y, z], got " +
                                         (vertices.is_array() ? std::to_string(vertices.size()) + " items"
                                                              : std::string(vertices.type_name())));
      continue;
    }
    std::array<Eigen::Vector3d, 8> corner;
    bool complete = true;
    for (int k = 0; k < 8; ++k) {
      const std::string v = at + "/vertices/" + std::to_string(k), what = name + ".vertices[" + std::to_string(k) + "]";
      if (!vertices[k].is_array() || vertices[k].size() != 3) {
        reader.error(v, what + ": expected [x, y, z], got " + vertices[k].dump());
        complete = false;
        continue;
      }
      for (int j = 0; j < 3; ++j) corner[kOltCornerOfVertex[k]][j] = reader.number(v + "/" + std::to_string(j), what);
    }
    if (!complete) continue;
    const FittedBox fit = fit_box(corner);
    if (!fit.problem.empty()) {
      reader.error(at + "/vertices", name + " ('" + label + "'): " + fit.problem);
      continue;
    }
    const std::string id = label + "_" + std::to_string(i);
    boxes.push_back(make_checked_box(reader, at, id, label, "", fit.center, fit.size, fit.rotation));
  }
  reader.throw_if_errors();
  return {boxes, reader.warnings()};
}

std::string write_labelcloud_vertices(const std::vector<Box>& boxes) {
  nlohmann::ordered_json objects = nlohmann::ordered_json::array();
  for (const auto& b : boxes) {
    const std::array<Eigen::Vector3d, 8> corners = box_corners(b);
    nlohmann::ordered_json vertices = nlohmann::ordered_json::array();
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector3d& c = corners[kOltCornerOfVertex[k]];
      vertices.push_back({c.x(), c.y(), c.z()});
    }
    nlohmann::ordered_json object;
    object["name"] = b.label;
    object["vertices"] = vertices;
    objects.push_back(object);
  }
  return labelcloud_file_text(objects);
}

}  // namespace olt
