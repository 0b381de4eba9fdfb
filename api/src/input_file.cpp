#include "hapticd/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace hapticd {
namespace {

// Closes the descriptor on every path out.
struct Descriptor {
  int fd;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

std::string read_input_file(const std::filesystem::path& file, std::string_view what, std::size_t max_bytes) {
  const std::string name = file.string();
  // O_NONBLOCK: opening a named pipe must not wait for a writer; fstat on the open descriptor (not the name)
  // decides, so the file cannot be swapped between the check and the read.
  const Descriptor d{::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY)};
  if (d.fd < 0) throw std::runtime_error(name + ": cannot open the " + std::string(what) + ": " + std::strerror(errno));
  struct stat st {};
  if (::fstat(d.fd, &st) != 0)
    throw std::runtime_error(name + ": cannot read the " + std::string(what) + ": " + std::strerror(errno));
  if (S_ISDIR(st.st_mode)) throw std::runtime_error(name + ": is a directory, not a " + std::string(what));
  if (!S_ISREG(st.st_mode))
    throw std::runtime_error(name + ": not a regular file (a pipe, socket or device): a " + std::string(what) +
                             " must be a file");
  if (static_cast<std::size_t>(st.st_size) > max_bytes)
    throw std::runtime_error(name + ": the " + std::string(what) + " is " + std::to_string(st.st_size) +
                             " bytes; at most " + std::to_string(max_bytes) + " are accepted");
  std::string text(static_cast<std::size_t>(st.st_size), '\0');
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::read(d.fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw std::runtime_error(name + ": cannot read the " + std::string(what) + ": " + std::strerror(errno));
    if (n == 0) break;  // it shrank meanwhile
    done += static_cast<std::size_t>(n);
  }
  text.resize(done);
  return text;
}

}  // namespace hapticd
