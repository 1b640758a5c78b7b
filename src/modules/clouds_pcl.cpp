// libolt_clouds.so: PCL's binary PCD and PLY writers.
#include <pcl/PCLPointCloud2.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>

#include <cstring>
#include <fstream>

#include "entry_points.h"

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

// A PCLPointCloud2 (PCL's cloud with arbitrary fields) of a labeled cloud: x y z, colour, class and
// instance, packed per point.
pcl::PCLPointCloud2 to_pcl2(const LabeledCloud& cloud, bool packed_rgb) {
  pcl::PCLPointCloud2 out;
  auto field = [&](const std::string& name, uint8_t type, uint32_t size) {
    pcl::PCLPointField f;
    f.name = name;
    f.offset = out.point_step;
    f.datatype = type;
    f.count = 1;
    out.fields.push_back(f);
    out.point_step += size;
  };
  out.point_step = 0;
  for (const char* axis : {"x", "y", "z"}) field(axis, pcl::PCLPointField::FLOAT32, 4);
  if (packed_rgb) {
    field("rgb", pcl::PCLPointField::FLOAT32, 4);
  } else {
    for (const char* c : {"red", "green", "blue"}) field(c, pcl::PCLPointField::UINT8, 1);
  }
  field("class", pcl::PCLPointField::UINT16, 2);
  field("instance", pcl::PCLPointField::UINT16, 2);
  out.height = 1;
  out.width = static_cast<uint32_t>(cloud.size());
  out.is_dense = true;
  out.is_bigendian = false;
  out.row_step = out.point_step * out.width;
  out.data.resize(static_cast<size_t>(out.row_step));
  uint8_t* at = out.data.data();
  for (const auto& p : cloud) {
    uint8_t* q = at;
    auto put = [&q](const void* value, size_t size) {
      std::memcpy(q, value, size);
      q += size;
    };
    put(&p.x, 4), put(&p.y, 4), put(&p.z, 4);
    if (packed_rgb) {
      const uint32_t rgb = (uint32_t{p.r} << 16) | (uint32_t{p.g} << 8) | p.b;
      put(&rgb, 4);
    } else {
      put(&p.r, 1), put(&p.g, 1), put(&p.b, 1);
    }
    put(&p.class_id, 2), put(&p.instance_id, 2);
    at += out.point_step;
  }
  return out;
}

}  // namespace
}  // namespace olt

int olt_cloud_write(const std::string& path, const olt::ColoredCloud& cloud, bool pcd) {
  const auto pcl_cloud = olt::to_pcl(cloud);
  if (pcd) return pcl::io::savePCDFileBinary(path, pcl_cloud);
  pcl::PLYWriter writer;
  return writer.write(path, pcl_cloud, /*binary=*/true, /*use_camera=*/false);
}

int olt_labeled_cloud_write(const std::string& path, const olt::LabeledCloud& cloud, bool pcd) {
  const auto pcl_cloud = olt::to_pcl2(cloud, /*packed_rgb=*/pcd);
  if (cloud.empty() && !pcd) {
    // PCL's binary PLY writer refuses a cloud without points (a frame whose depth is all out of
    // range): its file is then PCL's header for no points, without the camera element PCL writes
    // after the points (its PCD writer writes such a file itself).
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << pcl::PLYWriter().generateHeaderBinary(pcl_cloud, Eigen::Vector4f::Zero(), Eigen::Quaternionf::Identity(), 0,
                                                 /*use_camera=*/false);
    out.close();
    return out ? 0 : -1;
  }
  if (pcd) {
    pcl::PCDWriter writer;
    return writer.writeBinary(path, pcl_cloud);
  }
  pcl::PLYWriter writer;
  return writer.writeBinary(path, pcl_cloud);
}
