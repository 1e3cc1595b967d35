#pragma once
// The queue of a lazy greedy (docs/planning.md, Selection).

#include <cstddef>
#include <optional>
#include <queue>
#include <utility>

namespace scanplan::detail {

// Items (poses, places in a list of poses) by their rate, a pair compared in order (say
// priority, then other samples gained per cost), the highest first and the lowest index on
// ties, for a greedy whose rates only fall: an entry is looked at when it comes to the top,
// and queued again at its item's present rate when that has fallen (the lazy greedy). An
// item that may be picked must have an entry at or above its rate.
class RateQueue {
 public:
  using Rate = std::pair<double, double>;
  void push(std::size_t item, Rate rate) { heap_.push({rate, item}); }

  // The item of the highest present rate `rate_of` among those `kept` (an entry of one not
  // kept is dropped), if that rate is above zero.
  template <class RateOf, class Kept>
  std::optional<std::size_t> top(RateOf rate_of, Kept kept) {
    while (!heap_.empty()) {
      const Entry entry = heap_.top();
      if (!kept(entry.item)) {
        heap_.pop();
        continue;
      }
      if (const Rate now = rate_of(entry.item); now != entry.rate) {
        heap_.pop();
        heap_.push({now, entry.item});
        continue;
      }
      if (entry.rate > Rate{0, 0}) return entry.item;
      return std::nullopt;
    }
    return std::nullopt;
  }

 private:
  struct Entry {
    Rate rate;
    std::size_t item;
    bool operator<(const Entry& other) const {  // the top is the greatest
      return rate < other.rate || (rate == other.rate && item > other.item);
    }
  };
  std::priority_queue<Entry> heap_;
};

}  // namespace scanplan::detail
