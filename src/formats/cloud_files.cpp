#include "olt/formats/cloud_files.h"

#include "olt/formats/cloud_writer.h"

namespace olt {
namespace {

// PCL writes in place; we write to a temporary sibling and rename, like every other output.
template <class Write>
void write_atomic_with(const fs::path& file, Write write) {
  fs::create_directories(file.parent_path());
  const fs::path temp = temp_sibling(file);
  if (write(temp.string()) != 0) {
    fs::remove(temp);
    throw std::runtime_error(file.string() + ": cannot write point cloud");
  }
  fs::rename(temp, file);
}

}  // namespace

void write_labeled_pcd(const fs::path& file, const LabeledCloud& cloud) {
  write_atomic_with(file, [&](const std::string& path) { return cloud_writer().labeled(path, cloud, true); });
}

void write_labeled_ply(const fs::path& file, const LabeledCloud& cloud) {
  write_atomic_with(file, [&](const std::string& path) { return cloud_writer().labeled(path, cloud, false); });
}

void write_ply(const fs::path& file, const ColoredCloud& cloud) {
  write_atomic_with(file, [&](const std::string& path) { return cloud_writer().colored(path, cloud, false); });
}

void write_pcd(const fs::path& file, const ColoredCloud& cloud) {
  write_atomic_with(file, [&](const std::string& path) { return cloud_writer().colored(path, cloud, true); });
}

}  // namespace olt
