#pragma once
// Typed writers and readers of hapticd's topics. The message types are fixed-size, so reading copies into
// caller-owned samples and never allocates message memory.
#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "hapticd/dds/participant.hpp"
#include "hapticd/dds/topics.hpp"

namespace hapticd::dds {

template <class T>
Entity make_topic(const Participant& participant, const CommandTiming& timing) {
  const Qos qos = topic_qos(TopicOf<T>::kind, timing);
  return Entity(
      check(dds_create_topic(participant.get(), TopicOf<T>::descriptor(), TopicOf<T>::name, qos.get(), nullptr),
            "cannot create a DDS topic"));
}

// The DDS partition of a request, command or group command for a device or group (`target`; "*": every device):
// "hapticd.<target>", "hapticd.all" for "*". Clients write in it, the server reads all of its own; DDS Security's
// permissions grant an identity the partitions of the devices it may command (docs/deployment.md).
[[nodiscard]] std::string target_partition(std::string_view target);

// A publisher or subscriber in the given partitions (none: the default partition).
[[nodiscard]] Entity publisher_in(const Participant& participant, const std::vector<std::string>& partitions);
[[nodiscard]] Entity subscriber_in(const Participant& participant, const std::vector<std::string>& partitions);

template <class T>
class Writer {
 public:
  // partition: "" the default partition; else a publisher of its own in that partition.
  explicit Writer(const Participant& participant, const CommandTiming& timing = {}, const std::string& partition = {})
      : topic_(make_topic<T>(participant, timing)) {
    const Qos qos = topic_qos(TopicOf<T>::kind, timing);
    dds_entity_t parent = participant.get();
    if (!partition.empty()) {
      publisher_ = publisher_in(participant, {partition});
      parent = publisher_.get();
    }
    writer_ = Entity(check(dds_create_writer(parent, topic_.get(), qos.get(), nullptr), "cannot create a DDS writer"));
  }
  bool write(const T& sample) const noexcept { return dds_write(writer_.get(), &sample) == DDS_RETCODE_OK; }
  // With an explicit source timestamp (ns since the epoch, the wall clock).
  bool write(const T& sample, dds_time_t source_time) const noexcept {
    return dds_write_ts(writer_.get(), &sample, source_time) == DDS_RETCODE_OK;
  }
  [[nodiscard]] dds_entity_t get() const noexcept { return writer_.get(); }
  // Number of matched readers.
  [[nodiscard]] int matched() const noexcept {
    dds_publication_matched_status_t s{};
    return dds_get_publication_matched_status(writer_.get(), &s) == DDS_RETCODE_OK ? static_cast<int>(s.current_count)
                                                                                   : 0;
  }

 private:
  Entity topic_;
  Entity publisher_;  // when in a partition of its own
  Entity writer_;
};

template <class T>
class Reader {
 public:
  static constexpr std::size_t kBatch = 16;

  // filter: samples it refuses are dropped before the reader stores them (no instance is created for them); it
  // runs on Cyclone's receive threads. The reader has a topic entity of its own, so the filter is the reader's.
  // partitions: none, the default partition; else a subscriber of its own in them.
  explicit Reader(const Participant& participant, const CommandTiming& timing = {},
                  const dds_topic_filter* filter = nullptr, const std::vector<std::string>& partitions = {})
      : topic_(make_topic<T>(participant, timing)) {
    for (std::size_t i = 0; i < kBatch; ++i) pointers_[i] = &samples_[i];
    const Qos qos = topic_qos(TopicOf<T>::kind, timing);
    if (filter != nullptr) check(dds_set_topic_filter_extended(topic_.get(), filter), "cannot set a DDS topic filter");
    dds_entity_t parent = participant.get();
    if (!partitions.empty()) {
      subscriber_ = subscriber_in(participant, partitions);
      parent = subscriber_.get();
    }
    reader_ = Entity(check(dds_create_reader(parent, topic_.get(), qos.get(), nullptr), "cannot create a DDS reader"));
  }
  // Callbacks on Cyclone's receive thread from now on (Cyclone copies the listener). Set it once the owner
  // is fully built: a callback may run at once.
  void set_listener(const dds_listener_t* listener) {
    check(dds_set_listener(reader_.get(), listener), "cannot set a DDS listener");
  }
  // Takes everything available; calls f(sample, info) for each valid sample and returns how many there were.
  template <class F>
  int take(F&& f) {
    int total = 0;
    for (;;) {
      const dds_return_t n = dds_take(reader_.get(), pointers_.data(), infos_.data(), kBatch, kBatch);
      if (n <= 0) break;
      for (dds_return_t i = 0; i < n; ++i) {
        if (!infos_[static_cast<std::size_t>(i)].valid_data) continue;
        f(samples_[static_cast<std::size_t>(i)], infos_[static_cast<std::size_t>(i)]);
        ++total;
      }
      if (static_cast<std::size_t>(n) < kBatch) break;
    }
    return total;
  }
  [[nodiscard]] dds_entity_t get() const noexcept { return reader_.get(); }
  [[nodiscard]] int matched() const noexcept {
    dds_subscription_matched_status_t s{};
    return dds_get_subscription_matched_status(reader_.get(), &s) == DDS_RETCODE_OK ? static_cast<int>(s.current_count)
                                                                                    : 0;
  }

 private:
  Entity topic_;
  Entity subscriber_;  // when in partitions of its own
  Entity reader_;
  std::array<T, kBatch> samples_{};
  std::array<void*, kBatch> pointers_{};
  std::array<dds_sample_info_t, kBatch> infos_{};
};

}  // namespace hapticd::dds
