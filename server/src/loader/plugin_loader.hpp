#pragma once
// Loads plugin libraries with Boost.DLL and creates plugin objects. A library is kept loaded as long as any
// object created from it lives: PluginInstance holds the library before the object, so the object is always
// destroyed first.
#include <boost/dll/shared_library.hpp>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "hapticd/plugin.hpp"

namespace hapticd::server {

class PluginLoadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct LoadedLibrary {
  std::filesystem::path path;
  boost::dll::shared_library library;
  const PluginCatalog* catalog = nullptr;
};

struct PluginHandle {
  std::shared_ptr<const LoadedLibrary> library;
  const PluginDescriptor* descriptor = nullptr;
};

template <class T>
struct PluginInstance {
  std::shared_ptr<const LoadedLibrary> library;  // declared first: destroyed after the object
  const PluginDescriptor* descriptor = nullptr;
  std::unique_ptr<T> object;
  // The values in effect of every parameter: the configured ones, then each accepted run-time set (tune()).
  Parameters parameters;

  T* operator->() const noexcept { return object.get(); }
  T& operator*() const noexcept { return *object; }
};

class PluginLoader {
 public:
  explicit PluginLoader(std::vector<std::filesystem::path> search_paths);

  // Search order: the session's plugin_paths, then HAPTICD_PLUGIN_PATH (colon-separated), then the folder
  // installed beside the executable (<bin>/../lib/hapticd/plugins), then, for a program that uses the session
  // API's shared library, the folder installed beside that library (<lib>/hapticd/plugins).
  static std::vector<std::filesystem::path> search_paths_for(const std::vector<std::filesystem::path>& configured);

  // Loads one library by file name ("libfoo.so"), short name ("foo" -> libfoo.so) or path. Throws
  // PluginLoadError: file not found, not loadable, not a hapticd plugin, other API version.
  std::shared_ptr<const LoadedLibrary> load_library(const std::string& name_or_path);

  // Finds the plugin `name` of `kind`, in `library` if given, else in every library on the search paths.
  PluginHandle find(PluginKind kind, const std::string& name, const std::optional<std::string>& library);

  // Every plugin in every library on the search paths (libraries that fail to load are reported in `problems`).
  std::vector<PluginHandle> list_all(std::vector<std::string>* problems = nullptr);

  [[nodiscard]] const std::vector<std::filesystem::path>& search_paths() const noexcept { return search_paths_; }

 private:
  std::shared_ptr<const LoadedLibrary> open(const std::filesystem::path& file);
  std::vector<std::filesystem::path> candidate_files() const;

  std::vector<std::filesystem::path> search_paths_;
  std::map<std::filesystem::path, std::shared_ptr<const LoadedLibrary>> loaded_;
};

template <class T>
PluginInstance<T> create_plugin(const PluginHandle& handle) {
  PluginInstance<T> instance;
  instance.library = handle.library;
  instance.descriptor = handle.descriptor;
  if constexpr (std::is_same_v<T, Device>)
    instance.object = handle.descriptor->create_device();
  else if constexpr (std::is_same_v<T, Controller>)
    instance.object = handle.descriptor->create_controller();
  else if constexpr (std::is_same_v<T, InverseKinematics>)
    instance.object = handle.descriptor->create_inverse_kinematics();
  else if constexpr (std::is_same_v<T, GroupModel>)
    instance.object = handle.descriptor->create_group_model();
  else if constexpr (std::is_same_v<T, SceneService>)
    instance.object = handle.descriptor->create_scene();
  else
    instance.object = handle.descriptor->create_virtual_model();
  if (!instance.object)
    throw PluginLoadError(std::string("plugin '") + handle.descriptor->name + "' returned no object");
  return instance;
}

}  // namespace hapticd::server
