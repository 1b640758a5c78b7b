// `olt boxes convert` and `olt boxes corners`: box files between annotation tools, and the quickest
// check of a convention: every box's eight corners.
#include <cstdio>

#include "args.h"
#include "olt/core/error.h"
#include "olt/core/fs.h"
#include "olt/formats/box_formats.h"

namespace olt {
namespace {

std::string format_arg(const Args& args, const std::string& flag, const std::string& fallback) {
  const std::string format = args.value(flag, fallback);
  for (const auto& f : box_formats())
    if (f == format) return format;
  std::string known;
  for (const auto& f : box_formats()) known += (known.empty() ? "" : ", ") + f;
  throw InputError(flag, "unknown box format '" + format + "' (expected one of: " + known + ")");
}

// The boxes of `file`, its warnings (angles that look like the other unit) printed to stderr.
std::vector<Box> read_reporting_warnings(const std::string& format, const std::string& file) {
  const BoxFile read = read_box_file(format, file, read_file(file));
  for (const auto& w : read.warnings) std::fprintf(stderr, "warning: %s\n", w.str().c_str());
  return read.boxes;
}

}  // namespace

int cmd_boxes(const Args& args) {
  const std::string action = args.positional.empty() ? "" : args.positional[0];
  if (action == "convert" && args.positional.size() == 3) {
    if (!args.has("--from") || !args.has("--to")) throw InputError("olt boxes convert", "needs --from and --to");
    const std::string from = format_arg(args, "--from", ""), to = format_arg(args, "--to", "");
    const std::string in = args.positional[1];
    write_file_atomic(args.positional[2], write_boxes(to, read_reporting_warnings(from, in)));
    return kExitOk;
  }
  if (action == "corners" && args.positional.size() == 2) {
    const std::string file = args.positional[1];
    for (const Box& box : read_reporting_warnings(format_arg(args, "--format", "native"), file)) {
      std::printf("%s %s %s\n", box.id.c_str(), box.label.c_str(), box.instance.c_str());
      int i = 0;
      for (const auto& c : box_corners(box))
        std::printf("  %d (%c%c%c) %10.4f %10.4f %10.4f\n", i, (i & 1) ? '+' : '-', (i & 2) ? '+' : '-',
                    (i & 4) ? '+' : '-', c.x(), c.y(), c.z()),
            ++i;
    }
    return kExitOk;
  }
  throw InputError("olt boxes", "expected 'convert IN OUT' or 'corners FILE'");
}

}  // namespace olt
