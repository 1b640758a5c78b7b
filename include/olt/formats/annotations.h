#pragma once
// The native annotation format (schemas/annotations.schema.json), boxes in the scene frame, metres:
//   {"version": 1, "boxes": [{"id": "b1", "label": "monitor", "instance": "monitor_1",
//     "center": [x, y, z], "size": [sx, sy, sz], "rotation": [qx, qy, qz, qw]}]}
// `size` holds the full extents along the box's own x, y, z. Instead of `rotation` a box may give
// "yaw_pitch_roll_deg": [y, p, r] (intrinsic Z-Y'-X'', the original toolkit's convention).
// `instance` is optional and defaults to the box id.
#include <string>
#include <vector>

#include "olt/core/box.h"
#include "olt/core/error.h"

namespace olt {

/// Largest distance of a quaternion's norm from 1 that is accepted (and then normalised).
constexpr double kQuaternionNormTolerance = 1e-3;

/// Parses and validates; throws InputError listing every problem, each naming the box.
/// `warnings`, where given, gets what looks wrong without being wrong: yaw_pitch_roll_deg values
/// that all look like radians.
std::vector<Box> parse_native_annotations(const std::string& file, const std::string& text,
                                          std::vector<Diagnostic>* warnings = nullptr);

/// Native JSON of boxes (rotation as a unit quaternion, qw >= 0), deterministic.
std::string format_native_annotations(const std::vector<Box>& boxes);

/// Reads back what format_native_annotations wrote (an artifact OLT made: trusted, not validated again;
/// the same boxes, bit for bit, as parse_native_annotations gives).
std::vector<Box> read_native_annotations(const std::string& text);

}  // namespace olt
