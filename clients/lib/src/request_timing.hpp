#pragma once
// How the client library waits for a server's answer (client.cpp's requests, scene_client.cpp's): a request without
// an answer is sent again, with the same id, every kRequestRetry until the caller's timeout.
#include <algorithm>
#include <chrono>

#include "hapticd/client/types.hpp"

namespace hapticd::client {

inline constexpr std::chrono::milliseconds kRequestRetry{250};

// A timeout the steady clock can count: at most about three years (1e10 s and more overflowed its nanoseconds and
// returned at once); not positive or NaN: none.
inline std::chrono::steady_clock::duration countable(Timeout timeout) {
  constexpr Timeout kLongest{1e8};
  const Timeout t = timeout > Timeout::zero() ? std::min(timeout, kLongest) : Timeout::zero();
  return std::chrono::duration_cast<std::chrono::steady_clock::duration>(t);
}

}  // namespace hapticd::client
