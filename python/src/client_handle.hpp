#pragma once
// hapticd.Client's C++ side: a Client that can be closed before Python collects it (with-statement, close()).
#include <memory>
#include <stdexcept>

#include "hapticd/client/client.hpp"

namespace hapticd::python {

struct ClientHandle {
  std::unique_ptr<client::Client> client;
  client::Client& get() {
    if (!client) throw std::runtime_error("the client is closed");
    return *client;
  }
};

}  // namespace hapticd::python
