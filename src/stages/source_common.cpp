// What the source formats share.
#include <algorithm>
#include <cctype>
#include <map>

#include "olt/core/image.h"
#include "source_formats.h"

namespace olt::source {

const Names<SourceFormat>& source_format_names() {
  static const Names<SourceFormat> names = {{"tum", SourceFormat::tum},
                                            {"synthetic", SourceFormat::synthetic},
                                            {"laser_text", SourceFormat::laser_text},
                                            {"rawlog", SourceFormat::rawlog},
                                            {"plain_text", SourceFormat::plain_text}};
  return names;
}

std::string name_of(SourceFormat format) { return name_in(source_format_names(), format); }

void write_recording(ArtifactWriter& out, const Recording& r) {
  out.write_pieces("recording.json", [&](const PieceSink& sink) { recording_text(r, sink); });
}

bool safe_id(const std::string& id) {
  return !id.empty() && id.size() <= 64 && (std::isalnum(static_cast<unsigned char>(id[0])) || id[0] == '_') &&
         std::all_of(id.begin(), id.end(), [](char ch) {
           return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '.' || ch == '-';
         });
}

void image_size(const fs::path& file, int* width, int* height) {
  const ImageHeader header = read_image_header(file);
  *width = header.width;
  *height = header.height;
}

void add_folded(const std::string& list, const std::vector<LineProblem>& problems, const std::string& plural,
                std::vector<Diagnostic>& errors) {
  constexpr size_t kShown = 3;
  struct Repeats {
    size_t count = 0;
    int first_folded = 0, last = 0;
  };
  std::map<std::string, Repeats> repeats;  // by problem
  for (const auto& p : problems) {
    Repeats& r = repeats[p.problem];
    if (++r.count <= kShown) {
      errors.push_back({list, p.line, 1, p.subject + ": " + p.problem});
    } else {
      if (r.count == kShown + 1) r.first_folded = p.line;
      r.last = p.line;
    }
  }
  for (const auto& [problem, r] : repeats)
    if (r.count > kShown)
      errors.push_back({list, r.first_folded, 1,
                        "... and " + std::to_string(r.count - kShown) + " more " + plural +
                            " with this problem (lines " + std::to_string(r.first_folded) + " to " +
                            std::to_string(r.last) + "): " + problem});
}

void sort_by_time(std::vector<Observation>& observations) {
  std::stable_sort(observations.begin(), observations.end(), [](const Observation& a, const Observation& b) {
    return a.timestamp < b.timestamp || (a.timestamp == b.timestamp && a.sensor < b.sensor);
  });
}

}  // namespace olt::source
