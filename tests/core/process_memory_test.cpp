// What `olt watch` keeps between cycles: decoded images found again while the file is the same,
// decoded afresh once it changed, dropped beyond the budget, and not kept at all by default; and
// the values kept by name (a frame's labels) under the same budget.
#include "olt/core/process_memory.h"

#include <catch2/catch.hpp>
#include <numeric>

#include "olt/core/fs.h"
#include "olt/core/image_strips.h"
#include "olt/core/parallel.h"
#include "support/temp_dir.h"

using namespace olt;

namespace {

// A 16-bit image of `value` everywhere, written as PNG to `file`.
void write_grey16(const fs::path& file, uint16_t value, int width = 40) {
  test::write_text(file, encode_label_png(cv::Mat(30, width, CV_16UC1, cv::Scalar(value))));
}

}  // namespace

TEST_CASE("decoded images: kept while the file is the same, decoded again once it changed or was dropped") {
  test::TempDir dir;
  for (const char* name : {"a.png", "b.png", "c.png"}) write_grey16(dir / name, 7);
  // By default nothing is kept: each read decodes.
  CHECK(remembered_grey16(dir / "a.png").data != remembered_grey16(dir / "a.png").data);

  keep_in_memory(2 * 40 * 30 * 2);  // room for two of these images
  const cv::Mat a = remembered_grey16(dir / "a.png");
  CHECK(remembered_grey16(dir / "a.png").data == a.data);  // found again: the same pixels, shared
  CHECK(a.at<uint16_t>(0, 0) == 7);
  const cv::Mat b = remembered_grey16(dir / "b.png");
  CHECK(remembered_grey16(dir / "a.png").data == a.data);  // both fit; a is now the more recent
  // A third: the least recently read (b) goes, a stays.
  remembered_grey16(dir / "c.png");
  CHECK(remembered_grey16(dir / "a.png").data == a.data);
  CHECK(remembered_grey16(dir / "b.png").data != b.data);

  // Edited (another size, so its size and time differ): decoded afresh.
  write_grey16(dir / "a.png", 8, 41);
  const cv::Mat edited = remembered_grey16(dir / "a.png");
  CHECK(edited.at<uint16_t>(0, 0) == 8);
  CHECK(edited.cols == 41);
  // The colour reading of a file is another image than its grey one.
  CHECK(remembered_color(dir / "c.png").type() == CV_8UC3);

  // A missing file is the reader's error, naming it.
  CHECK_THROWS_WITH(remembered_grey16(dir / "gone.png"), Catch::Contains("gone.png"));

  // Nothing kept any more once the budget is 0.
  keep_in_memory(2 * 40 * 30 * 2);
  const cv::Mat c = remembered_grey16(dir / "c.png");
  REQUIRE(remembered_grey16(dir / "c.png").data == c.data);
  keep_in_memory(0);
  CHECK(remembered_grey16(dir / "c.png").data != c.data);
}

TEST_CASE("values kept by name: found again by name and type, dropped beyond the budget, none kept by default") {
  keep_in_memory(0);
  remember<std::string>("a", std::make_shared<const std::string>("first"), 100);
  CHECK(!keeping_memory());
  CHECK(remembered<std::string>("a") == nullptr);  // nothing is kept by default

  const size_t each = 100 + named_value_overhead("a");  // what a value below takes: room for two, not three
  keep_in_memory(2 * each + each / 2);
  CHECK(keeping_memory());
  const KeptMemory empty = kept_memory();
  CHECK(empty.bytes == 0);
  CHECK(empty.values == 0);
  remember<std::string>("a", std::make_shared<const std::string>("first"), 100);
  remember<std::string>("b", std::make_shared<const std::string>("second"), 100);
  REQUIRE(remembered<std::string>("a") != nullptr);
  CHECK(*remembered<std::string>("a") == "first");
  CHECK(remembered<int>("a") == nullptr);  // of another type: not found, never cast
  remember<std::string>("a", std::make_shared<const std::string>("again"), 100);  // replaces, same room
  CHECK(*remembered<std::string>("a") == "again");
  CHECK(remembered<std::string>("b") != nullptr);
  // A third value does not fit: the least recently read goes ("b": "a" is read last here).
  CHECK(remembered<std::string>("a") != nullptr);
  remember<std::string>("c", std::make_shared<const std::string>("third"), 100);
  CHECK(remembered<std::string>("b") == nullptr);
  CHECK(remembered<std::string>("a") != nullptr);
  CHECK(remembered<std::string>("c") != nullptr);
  const KeptMemory two = kept_memory();  // what it holds and what it dropped, as counted
  CHECK(two.bytes == 2 * each);
  CHECK(two.values == 2);
  CHECK(two.dropped == empty.dropped + 1);
  keep_in_memory(0);
  CHECK(remembered<std::string>("a") == nullptr);
  CHECK(kept_memory().values == 0);
  CHECK(kept_memory().dropped == two.dropped + 2);  // let go for the budget of 0
}

TEST_CASE("a value larger than the whole budget is not kept, and pushes nothing else out") {
  keep_in_memory(250 + named_value_overhead("small"));
  remember<std::string>("small", std::make_shared<const std::string>("kept"), 100);
  const uint64_t dropped = kept_memory().dropped;
  remember<std::string>("huge", std::make_shared<const std::string>("too big"), 300);
  CHECK(remembered<std::string>("huge") == nullptr);
  CHECK(kept_memory().dropped == dropped + 1);  // not kept for the budget: counted as dropped
  CHECK(remembered<std::string>("small") != nullptr);
  remember<std::string>("small", std::make_shared<const std::string>("grown"), 300);  // replaced: gone
  CHECK(remembered<std::string>("small") == nullptr);
  keep_in_memory(0);
}

TEST_CASE("a value taken is no longer kept: its room is free, the taker holds the only reference") {
  const size_t each = 100 + named_value_overhead("a");
  keep_in_memory(2 * each + each / 2);  // room for two
  remember<std::string>("a", std::make_shared<const std::string>("first"), 100);
  remember<std::string>("b", std::make_shared<const std::string>("second"), 100);
  CHECK(taken<int>("a") == nullptr);  // of another type: not taken, still kept
  const std::shared_ptr<const std::string> a = taken<std::string>("a");
  REQUIRE(a != nullptr);
  CHECK(*a == "first");
  CHECK(a.use_count() == 1);
  CHECK(remembered<std::string>("a") == nullptr);
  CHECK(taken<std::string>("a") == nullptr);
  // Its room is free: "c" fits beside "b" without pushing it out.
  remember<std::string>("c", std::make_shared<const std::string>("third"), 100);
  CHECK(remembered<std::string>("b") != nullptr);
  CHECK(remembered<std::string>("c") != nullptr);
  keep_in_memory(0);
  remember<std::string>("d", std::make_shared<const std::string>("fourth"), 100);
  CHECK(taken<std::string>("d") == nullptr);  // nothing kept: nothing to take
}

TEST_CASE("a value remembered or made: made once while memory is kept and its inputs stay, one value a name") {
  int made = 0;
  const auto make = [&] { return std::to_string(++made); };
  const auto bytes = [](const std::string& s) { return s.size(); };
  keep_in_memory(0);
  CHECK(*remembered_or_made<std::string>("v", "d1", make, bytes) == "1");
  CHECK(*remembered_or_made<std::string>("v", "d1", make, bytes) == "2");  // olt run: nothing kept
  keep_in_memory(1000);
  CHECK(*remembered_or_made<std::string>("v", "d1", make, bytes) == "3");
  CHECK(*remembered_or_made<std::string>("v", "d1", make, bytes) == "3");  // olt watch: the one made
  CHECK(*remembered_or_made<std::string>("w", "", make, bytes) == "4");    // not to be kept (no digest)
  CHECK(*remembered_or_made<std::string>("w", "", make, bytes) == "5");
  // Its inputs changed: made again, in place of the one before (still one value under "v").
  const size_t values = kept_memory().values;
  CHECK(*remembered_or_made<std::string>("v", "d2", make, bytes) == "6");
  CHECK(kept_memory().values == values);
  CHECK(*remembered_or_made<std::string>("v", "d2", make, bytes) == "6");
  CHECK(remembered_from<std::string>("v", "d1") == nullptr);
  CHECK(*remembered_or_made<std::string>("v", "d1", make, bytes) == "7");  // an undo makes it again
  forget_from<std::string>("v");
  CHECK(remembered_from<std::string>("v", "d1") == nullptr);
  CHECK(kept_memory().values == values - 1);
  keep_in_memory(0);
}

TEST_CASE("values kept per item: an item taken again only where it is made from the same, once the run kept them all") {
  int made = 0;
  const auto run = [&](const std::vector<std::string>& made_of) {  // one run: each item's value
    KeptPerItem<std::string> kept("items", made_of.size());
    std::vector<std::string> values;
    for (size_t i = 0; i < made_of.size(); ++i)
      values.push_back(*kept.made_or_before(
          i, made_of[i], [&] { return made_of[i] + "#" + std::to_string(++made); },
          [](const std::string& s) { return s.size(); }));
    kept.remember_all();
    return values;
  };
  keep_in_memory(0);
  CHECK(run({"a", "b"}) == std::vector<std::string>{"a#1", "b#2"});
  CHECK(run({"a", "b"}) == std::vector<std::string>{"a#3", "b#4"});  // olt run: nothing kept
  keep_in_memory(100000);
  CHECK(run({"a", "b"}) == std::vector<std::string>{"a#5", "b#6"});
  CHECK(run({"a", "c"}) == std::vector<std::string>{"a#5", "c#7"});               // b changed to c: made again
  CHECK(run({"c", "a", "x"}) == std::vector<std::string>{"c#8", "a#9", "x#10"});  // by place, not by name
  CHECK(run({"c", "a"}) == std::vector<std::string>{"c#8", "a#9"});               // fewer items
  {
    KeptPerItem<std::string> unfinished("items", 2);  // a run that fails before it keeps its items
    CHECK(*unfinished.made_or_before(
              0, "z", [] { return std::string("z"); }, [](const std::string&) { return 1; }) == "z");
  }
  CHECK(run({"c", "a"}) == std::vector<std::string>{"c#8", "a#9"});  // the last run kept is the one used
  keep_in_memory(0);
}

TEST_CASE("values kept per item: held up to the budget, the rest made again next run - made side by side by threads") {
  int made = 0;
  const size_t kItemBytes = 1000;
  const auto run = [&](size_t items) {
    KeptPerItem<int> kept("big items", items);
    std::vector<int> values;
    for (size_t i = 0; i < items; ++i)
      values.push_back(*kept.made_or_before(
          i, "m", [&] { return ++made; }, [&](int) { return kItemBytes; }));
    kept.remember_all();
    return values;
  };
  // Room for the list and two of its three items, not three.
  keep_in_memory(0);
  keep_in_memory(sizeof(std::vector<int>) + 3 * 64 + named_value_overhead("big items") + 2 * (kItemBytes + 1) + 500);
  const uint64_t dropped = kept_memory().dropped;
  CHECK(run(3) == std::vector<int>{1, 2, 3});
  CHECK(kept_memory().dropped == dropped + 1);  // the item not held is told
  CHECK(run(3) == std::vector<int>{1, 2, 4});   // the third was not held: made again
  CHECK(run(3) == std::vector<int>{1, 2, 5});   // ... and the list trimmed so was kept again
  CHECK(kept_memory().dropped == dropped + 3);  // told each run
  // Names made piece by piece (more capacity than size), a list trimmed close to the budget: what
  // was held is kept, not the whole list dropped for a count that differs from the keeper's.
  const auto run_named = [&](size_t items) {
    KeptPerItem<int> kept("named items", items);
    std::vector<int> values;
    for (size_t i = 0; i < items; ++i) {
      std::string made_of = "frame ";
      made_of += std::string(150, 'x');
      made_of += std::to_string(i);
      values.push_back(*kept.made_or_before(
          i, made_of, [&] { return ++made; }, [&](int) { return kItemBytes; }));
    }
    kept.remember_all();
    return values;
  };
  keep_in_memory(0);
  keep_in_memory(sizeof(std::vector<int>) + 3 * 64 + named_value_overhead("named items") + 2 * (kItemBytes + 400) +
                 300);
  const std::vector<int> first = run_named(3);
  CHECK(run_named(3) == std::vector<int>{first[0], first[1], first[2] + 1});
  keep_in_memory(1 << 20);
  const uint64_t dropped_before_threads = kept_memory().dropped;
  {
    KeptPerItem<int> kept("threads", 1000);
    parallel_for(1000, [&](size_t i) {
      kept.made_or_before(
          i, std::to_string(i), [i] { return static_cast<int>(i); }, [](int) { return sizeof(int); });
    });
    kept.remember_all();
  }
  KeptPerItem<int> again("threads", 1000);
  std::vector<int> values(1000);
  parallel_for(1000, [&](size_t i) {
    values[i] = *again.made_or_before(
        i, std::to_string(i), [] { return -1; }, [](int) { return sizeof(int); });
  });
  std::vector<int> each_its_own(1000);  // none made again
  std::iota(each_its_own.begin(), each_its_own.end(), 0);
  CHECK(values == each_its_own);
  CHECK(kept_memory().dropped == dropped_before_threads);  // all held: none told
  keep_in_memory(0);
}
