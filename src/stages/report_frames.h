#pragma once
// The report's per-frame views: which frames look wrong (a labeled share well under their
// neighbours'), a plot of every frame's labeled share and pose consistency with the flagged and the
// worst marked, and the sensor's path from above with the flagged observations on it. Plots are
// inline SVG, so each point names its frame and links to its overlay.
#include <string>
#include <vector>

#include "olt/stages/report.h"

namespace olt {

/// A frame's labeled share over the median share of the labeled frames of its sensor within
/// `radius` frames before and after it (itself left out); 1 where there is nothing to compare with.
double share_against_neighbours(const std::vector<ReportFrame>& frames, size_t i, size_t radius = 5);

/// The `count` labeled frames with the lowest share against their neighbours, lowest first; only
/// frames under 0.9 of their neighbours' share (a frame as good as its neighbours is not "worst").
std::vector<size_t> worst_frames(const std::vector<ReportFrame>& frames, int count);

/// Labeled share (and consistency, where poses carry it) per frame in the recording's order; flagged
/// frames red, `worst` circled; every point (up to 2000 frames) titled with its frame and linked to
/// its overlay.
std::string frames_plot_svg(const ReportInputs& in, const std::vector<size_t>& worst);

/// The valid poses' positions from above (world x right, y up, equal scale, metre grid); flagged
/// observations drawn red at the nearest valid pose of their sensor in time. Empty when no pose is valid.
std::string trajectory_svg(const std::vector<ObservationPose>& poses);

}  // namespace olt
