// libFuzzer target: a job file, loaded and validated as `olt validate` does.
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>

#include "fuzz_input.h"
#include "olt/job/job.h"
#include "olt/stages/stage.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("olt-fuzz-job-" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(file, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  olt::fuzz::expect_input_errors_only("job", [&] { olt::load_job(file, olt::kind_specs()); });
  return 0;
}
