// The modules' tables bound to their code linked into the executable: for tests, fuzzers and
// benchmarks, which load everything anyway (the `olt` binary uses lazy.cpp instead).
#include "entry_points.h"
#include "olt/core/error.h"
#include "olt/core/image_codec.h"
#include "olt/core/undistort.h"
#include "olt/formats/cloud_writer.h"

namespace olt {

const ImageCodec& image_codec() {
  static const ImageCodec codec{&olt_image_encode, &olt_image_decode};
  return codec;
}

const Undistorter& undistorter() {
  static const Undistorter table{&olt_undistort_points};
  return table;
}

const CloudWriter& cloud_writer() {
  static const CloudWriter writer{&olt_cloud_write, &olt_labeled_cloud_write};
  return writer;
}

const PlaneFinder& plane_finder() {
  static const PlaneFinder finder{&olt_find_planes};
  return finder;
}

#ifdef OLT_WITH_MRPT
bool rawlog_supported() { return true; }
void read_rawlog(const std::string& file, const RawlogVisitor& visit) { olt_rawlog_read(file, visit); }
#else
bool rawlog_supported() { return false; }
void read_rawlog(const std::string& file, const RawlogVisitor&) { throw InputError(file, kRawlogNeedsMrpt); }
#endif

}  // namespace olt
