#include "loader/elf_exports.hpp"

#include <elf.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>

namespace hapticd::server {
namespace {

// A read-only mapping of a whole regular file, unmapped on every path out.
class MappedFile {
 public:
  explicit MappedFile(const std::filesystem::path& file) {
    const int fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) return;
    struct stat st {};
    if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0 &&
        static_cast<std::size_t>(st.st_size) <= kMaxPluginLibraryBytes) {
      void* p = ::mmap(nullptr, static_cast<std::size_t>(st.st_size), PROT_READ, MAP_PRIVATE, fd, 0);
      if (p != MAP_FAILED) {
        data_ = static_cast<const unsigned char*>(p);
        size_ = static_cast<std::size_t>(st.st_size);
      }
    }
    ::close(fd);
  }
  ~MappedFile() {
    if (data_ != nullptr) ::munmap(const_cast<unsigned char*>(data_), size_);
  }
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;

  // The object of type T at `offset`, or nullptr when it does not lie wholly inside the file.
  template <class T>
  [[nodiscard]] const T* at(std::uint64_t offset) const noexcept {
    if (data_ == nullptr || offset > size_ || size_ - offset < sizeof(T)) return nullptr;
    return reinterpret_cast<const T*>(data_ + offset);
  }
  [[nodiscard]] bool contains(std::uint64_t offset, std::uint64_t bytes) const noexcept {
    return data_ != nullptr && offset <= size_ && bytes <= size_ - offset;
  }
  [[nodiscard]] const unsigned char* data() const noexcept { return data_; }

 private:
  const unsigned char* data_ = nullptr;
  std::size_t size_ = 0;
};

}  // namespace

bool elf_exports_symbol(const std::filesystem::path& library, std::string_view symbol) {
  const MappedFile f(library);
  const auto* header = f.at<Elf64_Ehdr>(0);
  if (header == nullptr || std::memcmp(header->e_ident, ELFMAG, SELFMAG) != 0 ||
      header->e_ident[EI_CLASS] != ELFCLASS64 || header->e_ident[EI_DATA] != ELFDATA2LSB || header->e_type != ET_DYN ||
      header->e_shentsize != sizeof(Elf64_Shdr))
    return false;
  for (std::uint64_t s = 0; s < header->e_shnum; ++s) {
    const auto* section = f.at<Elf64_Shdr>(header->e_shoff + s * sizeof(Elf64_Shdr));
    if (section == nullptr) return false;
    if (section->sh_type != SHT_DYNSYM || section->sh_entsize != sizeof(Elf64_Sym)) continue;
    const auto* strings = section->sh_link < header->e_shnum
                              ? f.at<Elf64_Shdr>(header->e_shoff + section->sh_link * sizeof(Elf64_Shdr))
                              : nullptr;
    if (strings == nullptr || !f.contains(strings->sh_offset, strings->sh_size) ||
        !f.contains(section->sh_offset, section->sh_size))
      return false;
    const char* names = reinterpret_cast<const char*>(f.data() + strings->sh_offset);
    for (std::uint64_t k = 0; k < section->sh_size / sizeof(Elf64_Sym); ++k) {
      const auto* sym = f.at<Elf64_Sym>(section->sh_offset + k * sizeof(Elf64_Sym));
      if (sym == nullptr || sym->st_shndx == SHN_UNDEF || sym->st_name >= strings->sh_size) continue;
      const std::size_t room = strings->sh_size - sym->st_name;
      const std::size_t length = ::strnlen(names + sym->st_name, room);
      if (length < room && std::string_view(names + sym->st_name, length) == symbol) return true;
    }
  }
  return false;
}

}  // namespace hapticd::server
