#pragma once
// What a hapticd_client handle is (hapticd/client.h): the C++ client, the sender thread its commands go out by, and
// the events taken from the library but not yet handed out.
#include <deque>
#include <mutex>

#include "command_sender.hpp"
#include "hapticd/client.h"
#include "hapticd/client/client.hpp"

struct hapticd_client {
  explicit hapticd_client(hapticd::client::ClientOptions options) : client(std::move(options)), sender(client) {}
  hapticd::client::Client client;
  hapticd::client_c::CommandSender sender;  // after the client: stopped before it
  std::mutex events_mutex;
  std::deque<hapticd::client::Event> pending_events;  // taken from the library, not yet handed out
};
