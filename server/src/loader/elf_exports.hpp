#pragma once
// Whether a shared library exports a symbol, read from its ELF dynamic symbol table without loading it. The
// plugin loader looks at a library in a search folder only when it exports hapticd's entry point: loading runs
// the library's initialisers, and a folder such as /usr/lib must not have every library in it run.
// Defensive: any file that is not a well-formed 64-bit little-endian ELF shared object gives false.
#include <cstddef>
#include <filesystem>
#include <string_view>

namespace hapticd::server {

// Files larger than this are not read (no plugin library is this large).
inline constexpr std::size_t kMaxPluginLibraryBytes = 256u * 1024u * 1024u;

[[nodiscard]] bool elf_exports_symbol(const std::filesystem::path& library, std::string_view symbol);

}  // namespace hapticd::server
