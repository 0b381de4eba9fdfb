#include "hapticd/dds/topics.hpp"

namespace hapticd::dds {

Qos topic_qos(TopicKind kind, const CommandTiming& timing) {
  Qos q(dds_create_qos());
  dds_qos_t* p = q.get();
  switch (kind) {
    case TopicKind::description:  // a late joiner gets every device's description (and its last fault report)
    case TopicKind::fault_report:
      dds_qset_reliability(p, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
      dds_qset_durability(p, DDS_DURABILITY_TRANSIENT_LOCAL);
      dds_qset_history(p, DDS_HISTORY_KEEP_LAST, 1);
      break;
    case TopicKind::state:  // only the newest state matters; never block the server
    case TopicKind::telemetry:
      dds_qset_reliability(p, DDS_RELIABILITY_BEST_EFFORT, 0);
      dds_qset_durability(p, DDS_DURABILITY_VOLATILE);
      dds_qset_history(p, DDS_HISTORY_KEEP_LAST, 1);
      break;
    case TopicKind::command:  // latest wins; a silent or dead engine is visible quickly. One instance per device
      // (every engine's commands share it): a few samples of history, so that a burst from another writer does
      // not displace the owner's before the server's listener has taken it.
      dds_qset_reliability(p, DDS_RELIABILITY_BEST_EFFORT, 0);
      dds_qset_durability(p, DDS_DURABILITY_VOLATILE);
      dds_qset_history(p, DDS_HISTORY_KEEP_LAST, 8);
      dds_qset_deadline(p, DDS_SECS(1) * timing.deadline_s);
      dds_qset_liveliness(p, DDS_LIVELINESS_AUTOMATIC,
                          static_cast<dds_duration_t>(DDS_SECS(1) * timing.liveliness_lease_s));
      break;
    case TopicKind::request:  // nothing lost; a burst of requests is kept (one instance per device: every
      // client's requests share it, so the history is deep)
      dds_qset_reliability(p, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
      dds_qset_durability(p, DDS_DURABILITY_VOLATILE);
      dds_qset_history(p, DDS_HISTORY_KEEP_LAST, 256);
      break;
    case TopicKind::reply:  // one instance per device, every client's replies in it: a deep history, as for requests
      dds_qset_reliability(p, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
      dds_qset_durability(p, DDS_DURABILITY_VOLATILE);
      dds_qset_history(p, DDS_HISTORY_KEEP_LAST, 256);
      break;
    case TopicKind::link:  // a teleoperation link: every packet counts (wave variables), none may block a server;
      // a few cycles of history, so that a burst is taken whole at the receiver's next cycle
      dds_qset_reliability(p, DDS_RELIABILITY_BEST_EFFORT, 0);
      dds_qset_durability(p, DDS_DURABILITY_VOLATILE);
      dds_qset_history(p, DDS_HISTORY_KEEP_LAST, 64);
      break;
    case TopicKind::event:
      dds_qset_reliability(p, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
      dds_qset_durability(p, DDS_DURABILITY_VOLATILE);
      dds_qset_history(p, DDS_HISTORY_KEEP_LAST, 64);
      break;
  }
  return q;
}

}  // namespace hapticd::dds
