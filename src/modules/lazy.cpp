// The modules' tables for the `olt` binary: each module (a shared library holding one heavy
// dependency) is loaded with dlopen the first time its table is asked for. OpenCV's image codecs,
// PCL's cloud writers and MRPT bring ~185 shared libraries; loaded at start they cost every `olt`
// command 0.2-0.4 s before it does anything (`olt plan`, `olt validate`, each shard and test).
// Modules are found next to the executable (the build tree) or in ../lib/olt/ (an installation).
#include <dlfcn.h>
#include <unistd.h>

#include <climits>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "entry_points.h"
#include "olt/core/error.h"
#include "olt/core/fs.h"
#include "olt/core/image_codec.h"
#include "olt/core/undistort.h"
#include "olt/formats/cloud_writer.h"

namespace olt {
namespace {

fs::path executable_folder() {
  char path[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", path, sizeof path - 1);
  if (n <= 0) return {};
  path[n] = '\0';
  return fs::path(path).parent_path();
}

// The module's handle, or null with why in `error` (the places looked in, and dlerror's words).
void* open_module(const std::string& name, std::string& error) {
  const std::string file = "libolt_" + name + ".so";
  const fs::path here = executable_folder();
  std::vector<fs::path> candidates = {here / file, here / ".." / "lib" / "olt" / file};
#ifdef OLT_MODULES_BUILD_DIR  // the test binaries, in a folder of the build tree
  candidates.push_back(fs::path(OLT_MODULES_BUILD_DIR) / file);
#endif
  for (const fs::path& candidate : candidates) {
    if (void* handle = ::dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL)) return handle;
    const char* why = ::dlerror();
    error += (error.empty() ? "" : "; ") + candidate.lexically_normal().string() + ": " + (why ? why : "not loadable");
  }
  return nullptr;
}

struct Module {
  std::once_flag once;
  void* handle = nullptr;
  std::string error;
};

// Opens the module once per process; null (with `error`) where it cannot be loaded.
void* module(const std::string& name, Module& m, std::string* error = nullptr) {
  std::call_once(m.once, [&] { m.handle = open_module(name, m.error); });
  if (error) *error = m.error;
  return m.handle;
}

template <class F>
F* function(void* handle, const std::string& name, const char* symbol) {
  void* address = handle ? ::dlsym(handle, symbol) : nullptr;
  if (!address) throw std::runtime_error("module libolt_" + name + ".so has no function " + symbol);
  return reinterpret_cast<F*>(address);
}

template <class F>
F* load(const std::string& name, Module& m, const char* symbol) {
  std::string error;
  void* handle = module(name, m, &error);
  if (!handle) throw std::runtime_error("cannot load OLT's module libolt_" + name + ".so: " + error);
  return function<F>(handle, name, symbol);
}

Module images, undistort, clouds, rawlog;

}  // namespace

const ImageCodec& image_codec() {
  static const ImageCodec codec{load<decltype(olt_image_encode)>("images", images, "olt_image_encode"),
                                load<decltype(olt_image_decode)>("images", images, "olt_image_decode")};
  return codec;
}

const Undistorter& undistorter() {
  static const Undistorter table{load<decltype(olt_undistort_points)>("undistort", undistort, "olt_undistort_points")};
  return table;
}

const CloudWriter& cloud_writer() {
  static const CloudWriter writer{load<decltype(olt_cloud_write)>("clouds", clouds, "olt_cloud_write"),
                                  load<decltype(olt_labeled_cloud_write)>("clouds", clouds, "olt_labeled_cloud_write")};
  return writer;
}

const PlaneFinder& plane_finder() {
  static const PlaneFinder finder{load<decltype(olt_find_planes)>("clouds", clouds, "olt_find_planes")};
  return finder;
}

// libolt_rawlog.so is built only where libmrpt is installed: without it, rawlogs are refused with
// what to install.
bool rawlog_supported() { return module("rawlog", rawlog) != nullptr; }

void read_rawlog(const std::string& file, const RawlogVisitor& visit) {
  if (!rawlog_supported()) throw InputError(file, kRawlogNeedsMrpt);
  load<decltype(olt_rawlog_read)>("rawlog", rawlog, "olt_rawlog_read")(file, visit);
}

}  // namespace olt
