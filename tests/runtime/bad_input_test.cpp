// The bad-input matrix: each case is a broken job, annotation, recording or environment. Each
// asserts the exit code, that the message names the file and the line or field, and that the
// output and the cache are as they were (nothing half-written, no damaged entry).
#include <sys/resource.h>
#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <fstream>
#include <functional>
#include <opencv2/core.hpp>

#include "olt/core/image.h"
#include "olt/core/image_strips.h"
#include "support/temp_dir.h"
#include "support/tiny_recording.h"

using namespace olt::test;
namespace fs = std::filesystem;

namespace {

const std::string kJob = kTinyTumJob;
const std::string kBoxes = kTinyTumBoxes;

void write_bytes(const fs::path& file, const std::string& bytes) { write_text(file, bytes); }

struct Case {
  const char* name;
  std::function<void(const fs::path&)> spoil;  ///< breaks the valid set-up in `dir`
  int exit_code;
  std::vector<std::string> message;  ///< all must appear in stderr (file, line or field, what)
  const char* ulimit = nullptr;      ///< a shell `ulimit` prefix, for environment cases
};

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

void edit(const fs::path& file, const std::string& from, const std::string& to) {
  write_text(file, replace(read_text(file), from, to));
}

std::string many_boxes(int n) {
  std::string text = R"({"version": 1, "boxes": [)";
  for (int i = 0; i < n; ++i)
    text += std::string(i ? "," : "") + R"({"id": "b)" + std::to_string(i) +
            R"(", "label": "x", "center": [0, 0, 1], "size": [0.1, 0.1, 0.1], "rotation": [0, 0, 0, 1]})";
  return text + "]}";
}

// A PNG whose header claims width x height (and nothing else): a decoder trusting it would
// allocate width * height * 2 bytes.
std::string png_header_claiming(uint32_t width, uint32_t height) {
  const std::string real = olt::encode_label_png(cv::Mat(1, 1, CV_16UC1, cv::Scalar(0)));
  std::string bytes = real;
  auto put = [&](size_t at, uint32_t v) {
    for (int k = 0; k < 4; ++k) bytes[at + k] = static_cast<char>((v >> (24 - 8 * k)) & 0xff);
  };
  put(16, width);  // IHDR data starts at byte 16 (8 signature + 4 length + 4 type)
  put(20, height);
  return bytes;
}

const std::vector<Case>& cases() {
  static const std::vector<Case> all = {
      {"malformed YAML", [](const fs::path& d) { edit(d / "job.yaml", "stages:\n", "stages: [\n"); }, 2, {"job.yaml:"}},
      {"malformed JSON",
       [](const fs::path& d) { write_text(d / "boxes.json", "{\"version\": 1, \"boxes\": [}"); },
       2,
       {"boxes.json:1:"}},
      {"wrong type",
       [](const fs::path& d) { edit(d / "job.yaml", "needs: [poses]}", "needs: [poses], params: {every: many}}"); },
       2,
       {"job.yaml:8:", "every"}},
      {"unknown key",
       [](const fs::path& d) { edit(d / "job.yaml", "needs: [poses]}", "needs: [poses], params: {evrey: 3}}"); },
       2,
       {"job.yaml:8:", "evrey", "every"}},
      {"NaN in the job",
       [](const fs::path& d) {
         edit(d / "job.yaml", "needs: [poses]}", "needs: [poses], params: {voxel_size_m: .nan}}");
       },
       2,
       {"job.yaml:8:", "voxel_size_m"}},
      {"Inf in a box",
       [](const fs::path& d) { edit(d / "boxes.json", "[0, 0, 1]", "[0, 0, 1e999]"); },
       2,
       {"boxes.json:1:"}},
      {"box of zero size",
       [](const fs::path& d) { edit(d / "boxes.json", "[0.5, 0.5, 0.5]", "[0.5, 0, 0.5]"); },
       2,
       {"boxes.json:1:", "size"}},
      {"box of negative size",
       [](const fs::path& d) { edit(d / "boxes.json", "[0.5, 0.5, 0.5]", "[0.5, -1, 0.5]"); },
       2,
       {"boxes.json:1:", "size"}},
      {"non-unit quaternion",
       [](const fs::path& d) { edit(d / "boxes.json", "[0, 0, 0, 1]", "[0, 0, 0, 2]"); },
       2,
       {"boxes.json:1:", "rotation"}},
      {"missing image",
       [](const fs::path& d) { fs::remove(d / "data/depth/1.png"); },
       2,
       {"depth.txt:3:", "depth/1.png"}},
      {"empty image",
       [](const fs::path& d) { write_text(d / "data/depth/1.png", ""); },
       2,
       {"depth.txt:3:", "depth/1.png", "empty file"}},
      {"truncated image",
       [](const fs::path& d) {
         const std::string png = read_text(d / "data/depth/1.png");
         write_bytes(d / "data/depth/1.png", png.substr(0, png.size() / 2));
       },
       2,
       {"depth/1.png"}},
      {"not an image",
       [](const fs::path& d) { write_text(d / "data/depth/1.png", "GIF89a not a png at all"); },
       2,
       {"depth.txt:3:", "depth/1.png", "not an image OpenCV reads"}},
      {"depth of the wrong type",
       [](const fs::path& d) {
         write_bytes(d / "data/depth/1.png", olt::encode_png(cv::Mat(48, 64, CV_8UC3, cv::Scalar(1, 2, 3))));
       },
       2,
       {"depth.txt:3:", "depth/1.png", "16-bit"}},
      {"depth of the wrong size",
       [](const fs::path& d) {
         write_bytes(d / "data/depth/2.png", olt::encode_png(cv::Mat(40, 64, CV_16UC1, cv::Scalar(5000))));
       },
       2,
       {"depth.txt:4:", "depth/2.png", "64x40", "64x48"}},
      {"timestamps out of order",
       [](const fs::path& d) { edit(d / "data/depth.txt", "1.200000", "1.050000"); },
       2,
       {"depth.txt:4:", "does not increase"}},
      {"duplicated timestamp",
       [](const fs::path& d) { edit(d / "data/depth.txt", "1.200000", "1.100000"); },
       2,
       {"depth.txt:4:", "does not increase"}},
      {"trajectory that covers no observation",
       [](const fs::path& d) { write_text(d / "data/groundtruth.txt", "5.0 0 0 0 0 0 0 1\n5.1 0 0 0 0 0 0 1\n"); },
       2,
       {"groundtruth.txt", "none of the 3 observations"}},
      {"empty recording",
       [](const fs::path& d) { write_text(d / "data/depth.txt", "# nothing\n"); },
       2,
       {"depth.txt", "no depth images"}},
      {"sensor id escaping the output folder",
       [](const fs::path& d) { edit(d / "job.yaml", "path: data}", "path: data, sensor: ../../escape}"); },
       2,
       {"job.yaml:5:", "sensor"}},
      {"symlink loop",
       [](const fs::path& d) {
         fs::remove(d / "data/depth/1.png");
         fs::create_symlink("loop_b.png", d / "data/depth/loop_a.png");
         fs::create_symlink("loop_a.png", d / "data/depth/loop_b.png");
         fs::create_symlink("loop_a.png", d / "data/depth/1.png");
       },
       2,
       {"depth.txt:3:", "depth/1.png"}},
      {"unreadable image (a folder)",
       [](const fs::path& d) {
         fs::remove(d / "data/depth/1.png");
         fs::create_directory(d / "data/depth/1.png");
       },
       2,
       {"depth.txt:3:", "depth/1.png"}},
      {"image header claiming 50000x50000",
       [](const fs::path& d) { write_bytes(d / "data/depth/1.png", png_header_claiming(50000, 50000)); },
       2,
       {"depth.txt:3:", "depth/1.png", "50000x50000"}},
      {"100k boxes",
       [](const fs::path& d) { write_text(d / "boxes.json", many_boxes(100000)); },
       2,
       {"boxes.json", "100000 boxes", "at most"}},
      {"a JSON file too large to read",
       [](const fs::path& d) {
         std::ofstream out(d / "boxes.json", std::ios::binary);
         out << kBoxes;
         out << std::string(300u << 20, ' ');
       },
       2,
       {"boxes.json", "MB", "at most"}},
      {"two depth images of one name (one listed twice)",
       [](const fs::path& d) { edit(d / "data/depth.txt", "1.200000 depth/2.png", "1.200000 depth/1.png"); },
       2,
       {"depth.txt:4:", "observation id '1'", "line 3's too"}},
      {"an output folder that holds the job (output: .)",
       [](const fs::path& d) { edit(d / "job.yaml", "output: out", "output: ."); },
       2,
       {"job.yaml:2:", "holds the job file"}},
      {"an output that is a file",
       [](const fs::path& d) {
         write_text(d / "notes.txt", "mine\n");
         edit(d / "job.yaml", "output: out", "output: notes.txt");
       },
       2,
       {"job.yaml:2:", "is a file, not a folder"}},
      {"an output inside the cache",
       [](const fs::path& d) { edit(d / "job.yaml", "output: out", "output: cache/out"); },
       2,
       {"job.yaml:2:", "is inside the cache"}},
      {"the whole file system as the output (output: /)",
       [](const fs::path& d) { edit(d / "job.yaml", "output: out", "output: /"); },
       2,
       {"job.yaml:2:", "holds the job file"}},
      {"an output folder that holds an input",
       [](const fs::path& d) { edit(d / "job.yaml", "output: out", "output: data"); },
       2,
       {"job.yaml:2:", "holds an input of stage 'source'"}},
      {"a named pipe as the boxes file",
       [](const fs::path& d) {
         fs::remove(d / "boxes.json");
         REQUIRE(::mkfifo((d / "boxes.json").c_str(), 0644) == 0);
       },
       2,
       {"boxes.json", "named pipe"}},
      {"a named pipe as an image",
       [](const fs::path& d) {
         fs::remove(d / "data/depth/1.png");
         REQUIRE(::mkfifo((d / "data/depth/1.png").c_str(), 0644) == 0);
       },
       2,
       {"depth.txt:3:", "depth/1.png", "named pipe"}},
      {"a full disk (file size limit)", [](const fs::path&) {}, 1, {"write failed: File too large"}, "ulimit -f 2;"},
  };
  return all;
}

// The good inputs back in `work` (the output and the cache stay as the good run left them).
void restore_inputs(const fs::path& pristine, const fs::path& work) {
  fs::remove_all(work / "data");
  fs::create_directories(work);
  fs::copy(pristine / "data", work / "data", fs::copy_options::recursive);
  for (const char* file : {"job.yaml", "verify.yaml", "boxes.json"}) {
    fs::remove(work / file);  // not written through: it may be a named pipe now
    fs::copy_file(pristine / file, work / file);
  }
}

void good_run(const fs::path& work) {
  const auto good = run_olt("run " + (work / "job.yaml").string());
  INFO(good.err);
  REQUIRE(good.exit_code == 0);
}

}  // namespace

// One good run, then each case in turn on the same folder: its inputs spoiled, the bad run, the
// checks, the inputs restored (the output and cache must be as the good run left them anyway).
TEST_CASE("bad input matrix: exit code, a message naming file and line or field, nothing changed") {
  TempDir dir;
  const fs::path pristine = dir / "pristine", work = dir / "work";
  write_tiny_tum_recording(pristine / "data");
  write_text(pristine / "job.yaml", kJob);
  // The same cache, for `olt cache verify` once job.yaml or the recording is spoiled.
  write_text(pristine / "verify.yaml",
             "version: 1\noutput: out\ncache: cache\nstages:\n  a: {kind: annotations, params: {file: boxes.json}}\n");
  write_text(pristine / "boxes.json", kBoxes);
  restore_inputs(pristine, work);
  good_run(work);
  for (const Case& c : cases()) {
    INFO("case: " << c.name);
    restore_inputs(pristine, work);
    if (c.ulimit) {  // the environment case: a fresh output, so that something must be written
      fs::remove_all(work / "out");
      fs::remove_all(work / "cache");
    }
    const std::string output_before = snapshot(work / "out");
    const std::string objects_before = snapshot(work / "cache/objects");
    c.spoil(work);

    const std::string command = std::string(c.ulimit ? c.ulimit : "") + " " + OLT_BINARY + " run " +
                                (work / "job.yaml").string() + " 2>" + (work / "stderr").string();
    const int status = std::system(("bash -c '" + command + "'").c_str());
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    const std::string err = read_text(work / "stderr");
    INFO(err);
    CHECK(code == c.exit_code);
    for (const auto& part : c.message) CHECK_THAT(err, Catch::Contains(part));
    CHECK(snapshot(work / "out") == output_before);
    if (c.exit_code == 2 && !c.ulimit && std::string(c.name) != "truncated image")
      CHECK(snapshot(work / "cache/objects") == objects_before);  // found before anything ran
    if (fs::exists(work / "cache")) {
      fs::remove(work / "boxes.json");
      write_text(work / "boxes.json", kBoxes);
      const auto verify = run_olt("cache verify " + (work / "verify.yaml").string());
      INFO(verify.out);
      CHECK(verify.exit_code == 0);
    }
    if (c.ulimit) {  // the good output and cache back for the cases after it
      restore_inputs(pristine, work);
      good_run(work);
    }
  }
}

// Paths go into JSON, which holds UTF-8 only: a job in a folder whose name is not UTF-8 is refused
// up front, naming the job and the fix, instead of failing mid-run with a raw JSON error.
TEST_CASE("a job in a folder whose name is not UTF-8 is refused by validate and run, saying why") {
  TempDir dir;
  const fs::path folder = dir / "job\xff";
  write_tiny_tum_recording(folder / "data");
  write_text(folder / "job.yaml", kJob);
  write_text(folder / "boxes.json", kBoxes);
  for (const char* command : {"validate ", "run "}) {
    const auto result = run_olt(command + ("'" + (folder / "job.yaml").string() + "'"));
    INFO(command << result.err);
    CHECK(result.exit_code == 2);
    CHECK_THAT(result.err, Catch::Contains("job.yaml") && Catch::Contains("is not UTF-8 (byte 0xFF") &&
                               Catch::Contains("rename the folder"));
    CHECK_FALSE(fs::exists(folder / "out"));
  }
}
