// What the source formats share.
#include <algorithm>
#include <cctype>

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

bool safe_id(const std::string& id) {
  return !id.empty() && id.size() <= 64 && (std::isalnum(static_cast<unsigned char>(id[0])) || id[0] == '_') &&
         std::all_of(id.begin(), id.end(), [](char ch) {
           return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '.' || ch == '-';
         });
}

void image_size(const fs::path& file, int* width, int* height) {
  const PngHeader header = read_png_header(file);
  *width = header.width;
  *height = header.height;
}

void sort_by_time(std::vector<Observation>& observations) {
  std::stable_sort(observations.begin(), observations.end(), [](const Observation& a, const Observation& b) {
    return a.timestamp < b.timestamp || (a.timestamp == b.timestamp && a.sensor < b.sensor);
  });
}

}  // namespace olt::source
