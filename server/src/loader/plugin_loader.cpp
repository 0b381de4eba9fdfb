#include "loader/plugin_loader.hpp"

#include <algorithm>
#include <boost/dll/runtime_symbol_info.hpp>
#include <cstdlib>
#include <sstream>

#include "loader/elf_exports.hpp"

namespace hapticd::server {
namespace fs = std::filesystem;
namespace {

constexpr const char* kVersionSymbol = "hapticd_plugin_api_version";
constexpr const char* kCatalogSymbol = "hapticd_plugin_catalog";

std::string join_paths(const std::vector<fs::path>& paths) {
  std::string out;
  for (const auto& p : paths) out += (out.empty() ? "" : ", ") + p.string();
  return out.empty() ? "(no search paths)" : out;
}

bool looks_like_path(const std::string& s) {
  return s.find('/') != std::string::npos || (s.size() > 3 && s.ends_with(".so"));
}

}  // namespace

PluginLoader::PluginLoader(std::vector<fs::path> search_paths) : search_paths_(std::move(search_paths)) {}

std::vector<fs::path> PluginLoader::search_paths_for(const std::vector<fs::path>& configured) {
  std::vector<fs::path> paths = configured;
  if (const char* env = std::getenv("HAPTICD_PLUGIN_PATH"); env != nullptr) {
    std::stringstream list(env);
    std::string item;
    while (std::getline(list, item, ':'))
      if (!item.empty()) paths.emplace_back(item);
  }
  const fs::path exe_dir = boost::dll::program_location().parent_path().string();
  paths.push_back(exe_dir / ".." / "lib" / "hapticd" / "plugins");
  // Linked into a shared library (the session API, libhapticd_server.so in <prefix>/lib): the plugins installed
  // beside it, whichever program loaded it.
  const fs::path code_dir = boost::dll::this_line_location().parent_path().string();
  if (code_dir != exe_dir) paths.push_back(code_dir / "hapticd" / "plugins");
  return paths;
}

std::shared_ptr<const LoadedLibrary> PluginLoader::open(const fs::path& file) {
  std::error_code ec;
  const fs::path canonical = fs::canonical(file, ec);
  const fs::path key = ec ? file : canonical;
  if (auto it = loaded_.find(key); it != loaded_.end()) return it->second;

  auto loaded = std::make_shared<LoadedLibrary>();
  loaded->path = key;
  try {
    loaded->library.load(key.string(), boost::dll::load_mode::rtld_now | boost::dll::load_mode::rtld_local);
  } catch (const std::exception& e) {
    throw PluginLoadError("cannot load plugin library " + key.string() + ": " + e.what());
  }
  if (!loaded->library.has(kVersionSymbol))
    throw PluginLoadError(key.string() + " is not a hapticd plugin library: it exports no '" + kVersionSymbol +
                          "' symbol (declare its plugins with HAPTICD_PLUGIN_LIBRARY)");
  const int version = loaded->library.get<int()>(kVersionSymbol)();
  if (version != kApiVersion)
    throw PluginLoadError(key.string() + " was built against plugin API version " + std::to_string(version) +
                          ", this server uses version " + std::to_string(kApiVersion) +
                          ": rebuild the plugin against this hapticd");
  if (!loaded->library.has(kCatalogSymbol))
    throw PluginLoadError(key.string() + " exports '" + kVersionSymbol + "' but no '" + kCatalogSymbol +
                          "' symbol (declare its plugins with HAPTICD_PLUGIN_LIBRARY)");
  loaded->catalog = loaded->library.get<const PluginCatalog*()>(kCatalogSymbol)();
  if (loaded->catalog == nullptr) throw PluginLoadError(key.string() + ": the plugin catalog is empty");
  loaded_[key] = loaded;
  return loaded;
}

std::shared_ptr<const LoadedLibrary> PluginLoader::load_library(const std::string& name) {
  if (looks_like_path(name)) {
    if (!fs::exists(name)) throw PluginLoadError("plugin library " + name + " does not exist");
    if (!elf_exports_symbol(name, kVersionSymbol))
      throw PluginLoadError(name + " is not a hapticd plugin library: it exports no '" + std::string(kVersionSymbol) +
                            "' symbol (declare its plugins with HAPTICD_PLUGIN_LIBRARY); it was not loaded");
    return open(name);
  }
  for (const auto& dir : search_paths_) {
    for (const std::string& file : {"lib" + name + ".so", name + ".so"}) {
      const fs::path candidate = dir / file;
      if (!fs::exists(candidate)) continue;
      if (!elf_exports_symbol(candidate, kVersionSymbol))
        throw PluginLoadError(candidate.string() + " is not a hapticd plugin library: it exports no '" +
                              std::string(kVersionSymbol) + "' symbol; it was not loaded");
      return open(candidate);
    }
  }
  throw PluginLoadError("plugin library '" + name + "' not found (looked for lib" + name + ".so in: " +
                        join_paths(search_paths_) + "; add a folder with server.plugin_paths or HAPTICD_PLUGIN_PATH)");
}

std::vector<fs::path> PluginLoader::candidate_files() const {
  std::vector<fs::path> files;
  for (const auto& dir : search_paths_) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) continue;
    std::vector<fs::path> here;
    // Only hapticd plugin libraries: a library is loaded (its initialisers run) only when its symbol table says
    // it is one. A folder of other libraries (plugin_paths: [/usr/lib/...]) is passed over, not loaded.
    for (const auto& entry : fs::directory_iterator(dir, ec))
      if (entry.is_regular_file() && entry.path().extension() == ".so" &&
          elf_exports_symbol(entry.path(), kVersionSymbol))
        here.push_back(entry.path());
    std::sort(here.begin(), here.end());
    files.insert(files.end(), here.begin(), here.end());
  }
  return files;
}

std::vector<PluginHandle> PluginLoader::list_all(std::vector<std::string>* problems) {
  std::vector<PluginHandle> handles;
  for (const auto& file : candidate_files()) {
    std::shared_ptr<const LoadedLibrary> library;
    try {
      library = open(file);
    } catch (const PluginLoadError& e) {
      if (problems != nullptr) problems->push_back(e.what());
      continue;
    }
    for (std::size_t i = 0; i < library->catalog->count; ++i)
      handles.push_back(PluginHandle{library, &library->catalog->entries[i]});
  }
  return handles;
}

PluginHandle PluginLoader::find(PluginKind kind, const std::string& name, const std::optional<std::string>& library) {
  std::vector<PluginHandle> candidates;
  if (library) {
    auto lib = load_library(*library);
    for (std::size_t i = 0; i < lib->catalog->count; ++i)
      candidates.push_back(PluginHandle{lib, &lib->catalog->entries[i]});
  } else {
    candidates = list_all();
  }

  std::vector<std::string> same_kind;
  for (const auto& h : candidates) {
    if (name == h.descriptor->name) {
      if (h.descriptor->kind != kind)
        throw PluginLoadError("plugin '" + name + "' (" + h.library->path.string() + ") is a " +
                              std::string(to_string(h.descriptor->kind)) + " plugin, but a " +
                              std::string(to_string(kind)) + " plugin is needed here");
      return h;
    }
    if (h.descriptor->kind == kind) same_kind.push_back(h.descriptor->name);
  }
  std::string available;
  for (const auto& n : same_kind) available += (available.empty() ? "" : ", ") + n;
  throw PluginLoadError(
      "no " + std::string(to_string(kind)) + " plugin named '" + name + "'" +
      (library ? " in library '" + *library + "'" : " on the search paths (" + join_paths(search_paths_) + ")") +
      "; available: " + (available.empty() ? "none" : available));
}

}  // namespace hapticd::server
