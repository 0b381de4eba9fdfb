#include "gate/stop_latches.hpp"

namespace hapticd::server {

bool StopLatches::matches(const Stopper& s, const PeerId& peer, std::string_view client, const GoneCheck& gone) const {
  if (s.sender.peer == peer) return true;
  // Another peer under the stopper's id: only once the stopper has left (it cannot be two at once).
  return !client.empty() && s.client == client && gone(s.sender);
}

void StopLatches::add(const Stopper& who) {
  for (std::size_t i = 0; i < count_; ++i)
    if (stoppers_[i].sender.peer == who.sender.peer && stoppers_[i].client == who.client) {
      stoppers_[i].sender = who.sender;
      return;
    }
  if (count_ == kMax) {
    overflowed_ = true;
    return;
  }
  stoppers_[count_++] = who;
}

bool StopLatches::held_by(const PeerId& peer, std::string_view client, const GoneCheck& gone) const {
  for (std::size_t i = 0; i < count_; ++i)
    if (matches(stoppers_[i], peer, client, gone)) return true;
  return false;
}

bool StopLatches::release(const PeerId& peer, std::string_view client, const GoneCheck& gone) {
  bool released = false;
  for (std::size_t i = 0; i < count_;) {
    if (matches(stoppers_[i], peer, client, gone)) {
      stoppers_[i] = stoppers_[--count_];
      stoppers_[count_] = Stopper{};
      released = true;
    } else {
      ++i;
    }
  }
  return released;
}

std::string StopLatches::holders() const {
  std::string out;
  for (std::size_t i = 0; i < count_; ++i) out += (out.empty() ? "'" : ", '") + stoppers_[i].client + "'";
  if (overflowed_) out += (out.empty() ? "" : ", ") + std::string("more stoppers than can be told apart");
  return out;
}

}  // namespace hapticd::server
