#include "olt/formats/cloud_files.h"

#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>

namespace olt {
namespace {

pcl::PointCloud<pcl::PointXYZRGB> to_pcl(const ColoredCloud& cloud) {
  pcl::PointCloud<pcl::PointXYZRGB> out;
  out.reserve(cloud.size());
  for (const auto& p : cloud) {
    pcl::PointXYZRGB q(p.r, p.g, p.b);
    q.x = p.x;
    q.y = p.y;
    q.z = p.z;
    out.push_back(q);
  }
  return out;
}

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

void write_ply(const fs::path& file, const ColoredCloud& cloud) {
  const auto pcl_cloud = to_pcl(cloud);
  write_atomic_with(file, [&](const std::string& path) {
    pcl::PLYWriter writer;
    return writer.write(path, pcl_cloud, /*binary=*/true, /*use_camera=*/false);
  });
}

void write_pcd(const fs::path& file, const ColoredCloud& cloud) {
  const auto pcl_cloud = to_pcl(cloud);
  write_atomic_with(file, [&](const std::string& path) { return pcl::io::savePCDFileBinary(path, pcl_cloud); });
}

}  // namespace olt
