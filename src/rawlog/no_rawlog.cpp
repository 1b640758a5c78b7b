// Built without libmrpt: rawlogs are refused with what to install.
#include "olt/core/error.h"
#include "olt/formats/rawlog.h"

namespace olt {

bool rawlog_supported() { return false; }

void read_rawlog(const std::string& file, const RawlogVisitor&) {
  throw InputError(file,
                   "reading MRPT rawlogs needs libmrpt: install libmrpt-obs-dev (docker/install-deps.sh) "
                   "and rebuild");
}

}  // namespace olt
