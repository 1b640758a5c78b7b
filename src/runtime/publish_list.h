#pragma once
// A stage's publish list (publish.json in its artifact): the files it puts in the output folder, as a
// JSON array of objects, written and read without a JSON value per entry (the labeling stage's holds
// 60,000 at 10,000 frames, and every publish reads every stage's).
#include <deque>
#include <functional>
#include <istream>
#include <string>
#include <string_view>

#include "olt/core/pieces.h"
#include "olt/stages/stage.h"

namespace olt {

/// A publish list made as its text an entry at a time, as the stage publishes (the labeling stage's
/// 60,000 entries are not held as values: the text beyond a few megabytes waits on disk).
class PublishListText {
 public:
  void add(const Published& p);
  size_t size() const { return count_; }
  /// The whole list's text (publish_list_pieces'), in pieces.
  void pieces(const PieceSink& sink) const;

 private:
  SpooledText text_;
  size_t count_ = 0;
  std::string entry_;                           ///< the last entry's text, its memory used again
  std::string observation_, observation_text_;  ///< the last entry's observation, and its member
  double timestamp_ = 0;
};

/// The list as dump(1) of its JSON array writes it (the bytes earlier versions wrote, so cached
/// artifacts keep their digests), handed to `sink` in pieces (12 MB at 60,000 entries, not held
/// whole).
void publish_list_pieces(const std::deque<Published>& list, const PieceSink& sink);

/// The same text whole (for tests and small lists).
std::string publish_list_text(const std::deque<Published>& list);

/// Calls `each` with every entry of a publish list, in order, parsed as events as the text is read
/// (no document built, the text not held: the labeling stage's is 12 MB at 10,000 frames); throws
/// std::runtime_error naming `name` on text that is not a publish list.
void read_publish_list(std::istream& text, const std::string& name, const std::function<void(Published&&)>& each);

}  // namespace olt
