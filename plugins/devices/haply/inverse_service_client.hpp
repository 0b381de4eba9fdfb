#pragma once
// A WebSocket client of Haply's Inverse Service (its simulation channel, ws://HOST:PORT, one state message for
// each message sent): connect with a timeout, send a text message, receive one. Blocking for its caller (the
// device's I/O thread) with a deadline on every call that waits: each runs as Asio's asynchronous operation under
// `io_context::run_for`, and one that has not completed by its deadline is cancelled and reported. (Socket time-outs
// - SO_RCVTIMEO - do not bound Beast's blocking calls: Asio answers their EAGAIN with poll(fd, -1), so a service that
// never answers hung the server's start and exit.) close() from another thread ends a call that waits. Messages
// larger than kMaxMessageBytes are refused. Boost.Beast behind a small interface, so its headers are compiled once.
// Nothing here throws: errors are returned as text (the caller throws).
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

namespace hapticd::plugins::haply {

class InverseServiceClient {
 public:
  // The largest message taken from the service (its states are about 1 kB; an inventory of many devices a few).
  static constexpr std::size_t kMaxMessageBytes = 256 * 1024;

  // Why `url` is not "ws://host:port[/path]" ("" when it is).
  [[nodiscard]] static std::string check_url(const std::string& url);
  // `url` as check_url() accepts it.
  explicit InverseServiceClient(const std::string& url);
  ~InverseServiceClient();
  InverseServiceClient(const InverseServiceClient&) = delete;
  InverseServiceClient& operator=(const InverseServiceClient&) = delete;

  // Connects and completes the WebSocket handshake within `timeout_s`; "" on success, else why (naming the URL).
  [[nodiscard]] std::string connect(double timeout_s);
  // Sends one text message within `timeout_s`; false with error() set when the connection failed or timed out.
  bool send(std::string_view text, double timeout_s) noexcept;
  // Receives one message within `timeout_s`; its text until the next receive. False with error() set when the
  // connection failed, closed or timed out, or the message was larger than kMaxMessageBytes.
  bool receive(std::string_view& text, double timeout_s) noexcept;
  // Any thread: ends the connection (a call that waits returns false).
  void close() noexcept;
  // Ends the connection as a WebSocket client should: a close frame, the service's reply awaited (at most
  // `timeout_s`), then the socket shut. Only from the thread that sends and receives, with no call waiting.
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
