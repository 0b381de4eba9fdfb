#pragma once
// A WebSocket client of Haply's Inverse Service (its simulation channel, ws://HOST:PORT, one state message for
// each message sent): connect with a timeout, send a text message, receive one. Blocking, for the device's I/O
// thread; close() from another thread ends a receive that waits. Boost.Beast behind a small interface, so the
// Beast headers are compiled once. Nothing here throws: errors are returned as text (an exception thrown in this
// file's Asio-using code ended the process instead of reaching the caller's handler - seen with GCC 12 and lld,
// cause not found; the caller throws).
#include <memory>
#include <string>
#include <string_view>

namespace hapticd::plugins::haply {

class InverseServiceClient {
 public:
  // Why `url` is not "ws://host:port[/path]" ("" when it is).
  [[nodiscard]] static std::string check_url(const std::string& url);
  // `url` as check_url() accepts it.
  explicit InverseServiceClient(const std::string& url);
  ~InverseServiceClient();
  InverseServiceClient(const InverseServiceClient&) = delete;
  InverseServiceClient& operator=(const InverseServiceClient&) = delete;

  // Connects and completes the WebSocket handshake within `timeout_s`; "" on success, else why (naming the URL).
  [[nodiscard]] std::string connect(double timeout_s);
  // Sends one text message; false with error() set when the connection failed.
  bool send(std::string_view text) noexcept;
  // Receives one message (waits at most `timeout_s`, 0: without limit); its text until the next receive. False
  // with error() set when the connection failed, closed or timed out.
  bool receive(std::string_view& text, double timeout_s = 0.0) noexcept;
  // Any thread: ends the connection (a receive that waits returns false).
  void close() noexcept;
  // Ends the connection as a WebSocket client should: a close frame, the service's reply awaited (at most
  // `timeout_s`), then the socket shut. Only from the thread that sends and receives, with no receive waiting.
  void close_gracefully(double timeout_s) noexcept;
  [[nodiscard]] const std::string& error() const noexcept { return error_; }
  [[nodiscard]] const std::string& url() const noexcept { return url_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string url_, host_, port_, path_;
  std::string error_;
};

}  // namespace hapticd::plugins::haply
