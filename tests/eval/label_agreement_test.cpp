// Label agreement (IoU, mean IoU, pixel agreement) against values counted by hand on 4x4 images,
// and `olt eval labels` on folders written here.
#include "olt/eval/label_agreement.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "olt/core/fs.h"
#include "olt/core/image_strips.h"
#include "support/temp_dir.h"

using namespace olt;
using namespace olt::test;

namespace {

constexpr uint16_t N = 65535;  // no depth

cv::Mat image(std::initializer_list<uint16_t> values) {
  cv::Mat m(4, 4, CV_16UC1);
  std::copy(values.begin(), values.end(), m.begin<uint16_t>());
  return m;
}

// A numbers box 1 and cup 2; B numbers box 9 and cup 5. Pixel by pixel (A, B) in class names:
//   (box,box) (box,box) (cup,box) (cup,cup)
//   (box,box) (box, - ) (cup,cup) (cup,cup)
//   ( - , - ) ( - , - ) ( - ,cup) ( - , - )
//   ( N , N ) ( - ,box) (box, N ) (cup,cup)
// With depth on both sides: 14 pixels ((3,2) has depth in A only, (3,0) in neither).
// box: A 4, B 5, both 3 -> union 6, IoU 1/2; cup: A 5, B 5, both 4 -> union 6, IoU 2/3.
// Labeled in A or B: 11 pixels, of which 7 agree.
const ClassCoding kCodingA{{{1, "box"}, {2, "cup"}}, 0, N};
const ClassCoding kCodingB{{{9, "box"}, {5, "cup"}}, 0, N};
const cv::Mat kFrameA = image({1, 1, 2, 2, 1, 1, 2, 2, 0, 0, 0, 0, N, 0, 1, 2});
const cv::Mat kFrameB = image({9, 9, 9, 5, 9, 0, 5, 5, 0, 0, 5, 0, N, 9, N, 5});

}  // namespace

TEST_CASE("one frame: IoU per class, agreement, no-depth pixels left out, classes matched by name", "[eval]") {
  const FrameComparison f = compare_labels(kFrameA, kFrameB, kCodingA, kCodingB);
  REQUIRE(f.classes.size() == 2);
  const ClassPixels& box = f.classes.at("box");
  const ClassPixels& cup = f.classes.at("cup");
  CHECK(box.in_a == 4);
  CHECK(box.in_b == 5);
  CHECK(box.both == 3);
  CHECK(box.iou() == Approx(0.5));
  CHECK(cup.in_a == 5);
  CHECK(cup.in_b == 5);
  CHECK(cup.both == 4);
  CHECK(cup.iou() == Approx(2.0 / 3));
  CHECK(f.labeled == 11);
  CHECK(f.agreeing == 7);
  CHECK(f.agreement() == Approx(7.0 / 11));
  CHECK(f.depth_differs == 1);
}

TEST_CASE("frames summed: IoU over all pixels, mean IoU, per-frame agreement, worst frames", "[eval]") {
  // Frame 1 is all box on both sides (16 more pixels of box in A, B and both); frame 2 labels
  // nothing (agreement 1: the two sides agree that nothing is there).
  const cv::Mat all_box_a(4, 4, CV_16UC1, cv::Scalar(1)), all_box_b(4, 4, CV_16UC1, cv::Scalar(9));
  const cv::Mat nothing(4, 4, CV_16UC1, cv::Scalar(0));
  const LabelAgreement s = summarize_agreement({compare_labels(kFrameA, kFrameB, kCodingA, kCodingB),
                                                compare_labels(all_box_a, all_box_b, kCodingA, kCodingB),
                                                compare_labels(nothing, nothing, kCodingA, kCodingB)});
  REQUIRE(s.classes.size() == 2);
  CHECK(s.classes[0].name == "box");
  CHECK(s.classes[0].pixels.union_pixels() == 22);  // A 20, B 21, both 19
  CHECK(s.classes[0].iou == Approx(19.0 / 22));
  CHECK(s.classes[1].name == "cup");
  CHECK(s.classes[1].iou == Approx(2.0 / 3));
  CHECK(s.mean_iou == Approx((19.0 / 22 + 2.0 / 3) / 2));
  CHECK(s.labeled == 27);
  CHECK(s.agreeing == 23);
  CHECK(s.agreement == Approx(23.0 / 27));
  CHECK(s.depth_differs == 1);
  REQUIRE(s.frame_agreement.size() == 3);
  CHECK(s.frame_agreement[0] == Approx(7.0 / 11));
  CHECK(s.frame_agreement[1] == 1);
  CHECK(s.frame_agreement[2] == 1);
  CHECK(s.min_frame_agreement == Approx(7.0 / 11));
  CHECK(s.median_frame_agreement == 1);
  CHECK(worst_frames(s, 1) == std::vector<size_t>{0});
  CHECK(worst_frames(s, 5) == std::vector<size_t>{0, 1, 2});  // equal ones in the order given
  CHECK(worst_frames(s, 0).empty());
}

TEST_CASE("without names ids are compared as they are - an unnamed id is matched by its number", "[eval]") {
  const ClassCoding plain;
  const FrameComparison f = compare_labels(image({3, 3, 3, 3, 0, 0, 0, 0, 7, 7, 0, 0, 0, 0, 0, 0}),
                                           image({3, 3, 0, 0, 0, 0, 0, 0, 7, 7, 7, 7, 0, 0, 0, 0}), plain, plain);
  REQUIRE(f.classes.size() == 2);
  CHECK(f.classes.at("id 3").iou() == Approx(0.5));
  CHECK(f.classes.at("id 7").iou() == Approx(0.5));
  CHECK(f.agreement() == Approx(4.0 / 8));
  // A names 3 "mug" but not 7; B names neither: 7 still matches 7, 3 does not match "mug".
  const ClassCoding named{{{3, "mug"}}, 0, N};
  const FrameComparison g = compare_labels(image({3, 7, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}),
                                           image({3, 7, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}), named, plain);
  CHECK(g.classes.at("id 7").iou() == 1);
  CHECK(g.classes.at("mug").iou() == 0);
  CHECK(g.classes.at("id 3").iou() == 0);
  // Other unlabeled and no-depth values.
  const ClassCoding shifted{{}, 100, 200};
  const FrameComparison h = compare_labels(
      image({100, 200, 5, 5, 100, 100, 100, 100, 100, 100, 100, 100, 100, 100, 100, 100}),
      image({5, 5, 5, 100, 100, 100, 100, 100, 100, 100, 100, 100, 100, 100, 100, 100}), shifted, shifted);
  CHECK(h.depth_differs == 1);  // (0,1): no depth in A only
  CHECK(h.labeled == 3);        // (0,0) B only, (0,2) both, (0,3) A only
  CHECK(h.agreeing == 1);
}

TEST_CASE("images of another type or size are refused", "[eval]") {
  const ClassCoding plain;
  CHECK_THROWS_AS(compare_labels(cv::Mat(4, 4, CV_16UC1), cv::Mat(4, 5, CV_16UC1), plain, plain),
                  std::invalid_argument);
  CHECK_THROWS_AS(compare_labels(cv::Mat(4, 4, CV_8UC1), cv::Mat(4, 4, CV_8UC1), plain, plain), std::invalid_argument);
}

namespace {

// An output folder of olt run with the class_label images of `frames` (observation ids) and a
// labels.json naming `classes` (id -> name).
void write_output(const std::filesystem::path& dir, const std::vector<std::pair<std::string, cv::Mat>>& frames,
                  const std::map<int, std::string>& classes) {
  nlohmann::json files = nlohmann::json::array();
  for (const auto& [id, labels] : frames) {
    const std::string path = "labels/cam/class/" + id + ".png";
    write_file_atomic(dir / path, encode_label_png(labels));
    files.push_back({{"kind", "class_label"},
                     {"path", path},
                     {"sensor", "cam"},
                     {"observation", {{"id", id}, {"timestamp", std::stod(id)}}}});
    files.push_back({{"kind", "overlay"}, {"path", "labels/cam/overlay/" + id + ".jpg"}});
  }
  write_text(dir / "manifest.json", nlohmann::json{{"files", files}}.dump(1));
  nlohmann::json list = nlohmann::json::array();
  for (const auto& [id, name] : classes) list.push_back({{"id", id}, {"name", name}, {"color", {0, 0, 0}}});
  write_text(dir / "labels.json", nlohmann::json{{"classes", list}, {"unlabeled", 0}, {"no_depth", N}}.dump(1));
}

}  // namespace

TEST_CASE("olt eval labels on two output folders and on two folders of PNGs", "[eval]") {
  TempDir dir;
  const cv::Mat all_box_a(4, 4, CV_16UC1, cv::Scalar(1)), all_box_b(4, 4, CV_16UC1, cv::Scalar(9));
  // Frame 3.0 is in A only (flagged and excluded in B, say).
  write_output(dir / "a", {{"1.0", kFrameA}, {"2.0", all_box_a}, {"3.0", all_box_a}}, {{1, "box"}, {2, "cup"}});
  write_output(dir / "b", {{"1.0", kFrameB}, {"2.0", all_box_b}}, {{5, "cup"}, {9, "box"}});

  SECTION("--json") {
    const auto r = run_olt("eval labels --json --worst=1 " + (dir / "a").string() + " " + (dir / "b").string());
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(j["classes_matched_by"] == "name");
    CHECK(j["frames_compared"] == 2);
    REQUIRE(j["frames_only_in_a"].size() == 1);
    CHECK(j["frames_only_in_a"][0]["observation"] == "3.0");
    CHECK(j["frames_only_in_b"].empty());
    REQUIRE(j["classes"].size() == 2);
    CHECK(j["classes"][0]["name"] == "box");
    CHECK(j["classes"][0]["iou"].get<double>() == Approx(19.0 / 22));
    CHECK(j["classes"][1]["iou"].get<double>() == Approx(2.0 / 3));
    CHECK(j["mean_iou"].get<double>() == Approx((19.0 / 22 + 2.0 / 3) / 2));
    CHECK(j["agreement"].get<double>() == Approx(23.0 / 27));
    CHECK(j["frame_agreement"]["min"].get<double>() == Approx(7.0 / 11));
    CHECK(j["frame_agreement"]["median"].get<double>() == Approx((7.0 / 11 + 1) / 2));
    REQUIRE(j["worst_frames"].size() == 1);
    CHECK(j["worst_frames"][0]["observation"] == "1.0");
    CHECK(j["worst_frames"][0]["sensor"] == "cam");
    REQUIRE(j["frames"].size() == 2);
    CHECK(j["frames"][1]["agreement"] == 1);
  }
  SECTION("text") {
    const auto r = run_olt("eval labels " + (dir / "a").string() + " " + (dir / "b").string());
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    INFO(r.out);
    CHECK(r.out.find("frames compared        2\n") != std::string::npos);
    CHECK(r.out.find("frames only in A       1: cam/3.0\n") != std::string::npos);
    CHECK(r.out.find("  box                    0.8636") != std::string::npos);
    CHECK(r.out.find("  cup                    0.6667") != std::string::npos);
    CHECK(r.out.find("mean IoU               0.7652 over 2 classes") != std::string::npos);
    CHECK(r.out.find("agreement              0.8519 of 27 pixels") != std::string::npos);
    CHECK(r.out.find("min 0.6364, median 0.8182") != std::string::npos);
  }
  SECTION("folders of PNGs: one labels.json in the parent names both sides, whose ids are compared as they are") {
    write_file_atomic(dir / "p/pa/x/f.png", encode_label_png(kFrameA));
    write_file_atomic(dir / "pb/x/f.png", encode_label_png(kFrameA));
    write_file_atomic(dir / "pb/x/g.png", encode_label_png(kFrameA));
    write_text(dir / "p/labels.json", R"({"classes": [{"id": 1, "name": "box"}, {"id": 2, "name": "cup"}]})");
    const auto r = run_olt("eval labels --json " + (dir / "p/pa").string() + " " + (dir / "pb").string());
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(j["classes_matched_by"] == "id");
    CHECK(j["frames_compared"] == 1);
    CHECK(j["frames_only_in_b"][0]["frame"] == "x/g.png");
    CHECK(j["classes"][0]["name"] == "box");
    CHECK(j["agreement"] == 1);
    CHECK(j["mean_iou"] == 1);
  }
  SECTION("bad input: exit 2 naming the file") {
    auto fails = [&](const std::string& args, const std::string& named) {
      const auto r = run_olt("eval labels " + args);
      INFO(r.err);
      CHECK(r.exit_code == 2);
      CHECK(r.err.find(named) != std::string::npos);
    };
    fails((dir / "a").string() + " " + (dir / "missing").string(), (dir / "missing").string() + ": no such folder");
    write_file_atomic(dir / "c/labels/cam/class/1.0.png", encode_label_png(cv::Mat(4, 5, CV_16UC1, cv::Scalar(0))));
    write_text(dir / "c/manifest.json",
               R"({"files": [{"kind": "class_label", "path": "labels/cam/class/1.0.png", "sensor": "cam",
                              "observation": {"id": "1.0", "timestamp": 1}}]})");
    fails((dir / "a").string() + " " + (dir / "c").string(), "1.0.png: 5x4, but the image of this frame in A");
    write_text(dir / "c/labels/cam/class/1.0.png", "not a png");
    fails((dir / "a").string() + " " + (dir / "c").string(), (dir / "c/labels/cam/class/1.0.png").string());
    write_text(dir / "c/manifest.json",
               R"({"files": [{"kind": "class_label", "path": "labels/cam/class/1.0.png", "sensor": "cam",
                              "observation": {"id": "9.0", "timestamp": 9}}]})");
    fails((dir / "a").string() + " " + (dir / "c").string(), "no frame in common");
    write_file_atomic(dir / "pc/f.png", encode_label_png(kFrameA));
    fails((dir / "a").string() + " " + (dir / "pc").string(), "manifest.json");
  }
}
