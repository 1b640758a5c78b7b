#pragma once
// The functions each module exports by name (C linkage, found with dlsym): the tables of
// olt/core/image_codec.h, olt/core/undistort.h, olt/formats/cloud_writer.h and olt/reconstruct/plane_finder.h, and
// formats/rawlog.h's reader.
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "olt/formats/rawlog.h"
#include "olt/model/cloud.h"
#include "olt/reconstruct/plane_finder.h"

#define OLT_MODULE_EXPORT extern "C" __attribute__((visibility("default")))

// libolt_images.so (OpenCV imgcodecs)
OLT_MODULE_EXPORT bool olt_image_encode(const cv::Mat& image, const std::string& extension,
                                        const std::vector<int>& params, std::vector<unsigned char>& out);
OLT_MODULE_EXPORT void olt_image_decode(const std::string& bytes, int flags, cv::Mat& image, std::string& error);

// libolt_undistort.so (OpenCV calib3d)
OLT_MODULE_EXPORT void olt_undistort_points(const std::vector<cv::Point2f>& pixels, const cv::Matx33d& K,
                                            const std::vector<double>& distortion,
                                            std::vector<cv::Point2f>& normalised);

// libolt_clouds.so (PCL io and sample consensus)
OLT_MODULE_EXPORT int olt_cloud_write(const std::string& path, const olt::ColoredCloud& cloud, bool pcd);
OLT_MODULE_EXPORT int olt_labeled_cloud_write(const std::string& path, const olt::LabeledCloud& cloud, bool pcd);
OLT_MODULE_EXPORT void olt_find_planes(const std::vector<Eigen::Vector3f>& points, const olt::PlaneQuery& query,
                                       std::vector<olt::Plane>& planes);

// libolt_rawlog.so (MRPT), built where libmrpt is installed
OLT_MODULE_EXPORT void olt_rawlog_read(const std::string& file, const olt::RawlogVisitor& visit);
