// A k-way merge of bag readers by log time (the files of a split rosbag2 bag).
#include "merged_bag_reader.h"

#include <map>
#include <optional>
#include <utility>

namespace semgraph::ros {
namespace {

class MergedBagReader final : public BagReader {
 public:
  MergedBagReader(std::string path, BagFormat format, std::vector<BagReaderPtr> parts)
      : path_(std::move(path)), format_(format), parts_(std::move(parts)) {
    pending_.resize(parts_.size());
    state_.assign(parts_.size(), State::kNeedsNext);
    MergeTopics();
  }

  [[nodiscard]] BagFormat format() const noexcept override { return format_; }
  [[nodiscard]] const std::string& path() const noexcept override { return path_; }
  [[nodiscard]] const std::vector<BagTopic>& topics() const noexcept override { return topics_; }

  [[nodiscard]] Expected<bool, BagError> Next(BagRecord& out) override {
    if (failed_) return Unexpected{*failed_};
    std::size_t best = parts_.size();
    for (std::size_t i = 0; i < parts_.size(); ++i) {
      if (state_[i] == State::kNeedsNext) {
        auto got = parts_[i]->Next(pending_[i]);
        if (!got) {
          failed_ = got.error();
          return Unexpected{*failed_};
        }
        state_[i] = *got ? State::kPending : State::kDone;
        if (parts_[i]->topics().size() != part_topic_counts_[i]) MergeTopics();
      }
      if (state_[i] == State::kPending &&
          (best == parts_.size() || pending_[i].log_time_ns < pending_[best].log_time_ns)) {
        best = i;
      }
    }
    if (best == parts_.size()) return false;
    out = pending_[best];
    state_[best] = State::kNeedsNext;
    return true;
  }

 private:
  enum class State : unsigned char { kNeedsNext, kPending, kDone };

  // topics_: the parts' topics by (name, type), counts summed (-1 if any part does not know).
  void MergeTopics() {
    topics_.clear();
    part_topic_counts_.clear();
    std::map<std::pair<std::string, std::string>, std::size_t> index;
    for (const BagReaderPtr& part : parts_) {
      part_topic_counts_.push_back(part->topics().size());
      for (const BagTopic& topic : part->topics()) {
        auto [it, added] = index.try_emplace({topic.name, topic.type_name}, topics_.size());
        if (added) {
          topics_.push_back(topic);
          continue;
        }
        BagTopic& merged = topics_[it->second];
        merged.message_count = merged.message_count < 0 || topic.message_count < 0
                                   ? -1
                                   : merged.message_count + topic.message_count;
      }
    }
  }

  std::string path_;
  BagFormat format_;
  std::vector<BagReaderPtr> parts_;
  std::vector<BagRecord> pending_;
  std::vector<State> state_;
  std::vector<std::size_t> part_topic_counts_;
  std::vector<BagTopic> topics_;
  std::optional<BagError> failed_;
};

}  // namespace

BagReaderPtr MergeBagReaders(std::string path, BagFormat format, std::vector<BagReaderPtr> parts) {
  return std::make_unique<MergedBagReader>(std::move(path), format, std::move(parts));
}

}  // namespace semgraph::ros
