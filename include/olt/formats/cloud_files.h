#pragma once
// Point-cloud files through PCL's writers: binary little-endian PLY (x y z float, red green blue
// uchar) and binary PCD (x y z rgb), the forms point-cloud annotation tools open.
#include <string>

#include "olt/core/fs.h"
#include "olt/model/cloud.h"

namespace olt {

void write_ply(const fs::path& file, const ColoredCloud& cloud);
void write_pcd(const fs::path& file, const ColoredCloud& cloud);

/// Labeled clouds: fields x y z (float), rgb (PCD: packed float, PCL's convention; PLY: red green
/// blue uchar), class and instance (uint16). Binary.
void write_labeled_pcd(const fs::path& file, const LabeledCloud& cloud);
void write_labeled_ply(const fs::path& file, const LabeledCloud& cloud);

}  // namespace olt
