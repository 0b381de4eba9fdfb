#pragma once
// Plugin metadata and the entry points a plugin library exports. A library exports two C symbols:
//   int hapticd_plugin_api_version()                      -> kApiVersion it was built against
//   const hapticd::PluginCatalog* hapticd_plugin_catalog() -> the plugins it contains
// The loader reads the version first and refuses a mismatch before it touches the catalog (whose layout may
// differ between versions). Write them with HAPTICD_PLUGIN_LIBRARY(hapticd::describe_plugin<T>(...), ...).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <type_traits>
#include <utility>

#include "hapticd/api_version.hpp"
#include "hapticd/controller.hpp"
#include "hapticd/device.hpp"
#include "hapticd/export.hpp"
#include "hapticd/group_model.hpp"
#include "hapticd/inverse_kinematics.hpp"
#include "hapticd/parameters.hpp"
#include "hapticd/scene_service.hpp"
#include "hapticd/virtual_model.hpp"

namespace hapticd {

enum class PluginKind : std::uint8_t { device, controller, inverse_kinematics, virtual_model, group_model, scene };

[[nodiscard]] HAPTICD_API std::string_view to_string(PluginKind kind) noexcept;

struct PluginDescriptor {
  PluginKind kind;
  const char* name;     // unique among all plugins the server can load, e.g. "sim_vishard"
  const char* version;  // the plugin's own version
  const char* summary;  // one line for listings
  ParameterSchema (*parameter_schema)();
  // The device interfaces a chain plugin can drive (hapticd/handle.hpp): a plugin class says so with
  // `static constexpr DeviceInterfaces kDeviceInterfaces`; without it, inverse kinematics and controllers drive
  // joints, virtual models and group models either. The server refuses a chain that does not fit its device.
  DeviceInterfaces device_interfaces;
  // Exactly the factory matching kind is set.
  std::unique_ptr<Device> (*create_device)();
  std::unique_ptr<Controller> (*create_controller)();
  std::unique_ptr<InverseKinematics> (*create_inverse_kinematics)();
  std::unique_ptr<VirtualModel> (*create_virtual_model)();
  std::unique_ptr<GroupModel> (*create_group_model)();
  std::unique_ptr<SceneService> (*create_scene)();  // the session's scene (scene_service.hpp)
};

struct PluginCatalog {
  const PluginDescriptor* entries;
  std::size_t count;
};

namespace detail {
// The rule for exceptions (return_code.hpp): T's real-time methods are not declared noexcept.
template <class T>
constexpr bool realtime_methods_not_noexcept() {
  using std::declval;
  using Cycle = const CycleTime&;
  if constexpr (std::is_base_of_v<Device, T>) {
    return !noexcept(declval<T&>().read(declval<Cycle>(), declval<DeviceState&>())) &&
           !noexcept(declval<T&>().write(declval<Cycle>(), declval<const JointCommand&>())) &&
           !noexcept(declval<T&>().write_handle(declval<Cycle>(), declval<const HandleCommand&>())) &&
           !noexcept(declval<T&>().reset_fault()) && !noexcept(declval<T&>().brake(true));
  } else if constexpr (std::is_base_of_v<Controller, T>) {
    using In = const ControllerInput&;
    return !noexcept(declval<T&>().activate(declval<In>(), declval<const JointCommand&>())) &&
           !noexcept(declval<T&>().update(declval<Cycle>(), declval<In>(), declval<JointCommand&>()));
  } else if constexpr (std::is_base_of_v<InverseKinematics, T>) {
    using In = const InverseKinematicsInput&;
    return !noexcept(declval<T&>().activate(declval<In>())) &&
           !noexcept(declval<T&>().update(declval<Cycle>(), declval<In>(), declval<JointTarget&>()));
  } else if constexpr (std::is_base_of_v<GroupModel, T>) {
    using Hands = std::span<const GroupHand>;
    return !noexcept(declval<T&>().activate(declval<Hands>())) &&
           !noexcept(declval<T&>().update(declval<Cycle>(), declval<Hands>(), declval<std::span<Eigen::Vector3d>>()));
  } else if constexpr (std::is_base_of_v<VirtualModel, T>) {
    using In = const VirtualModelInput&;
    return !noexcept(declval<T&>().activate(declval<In>())) &&
           !noexcept(declval<T&>().update(declval<Cycle>(), declval<In>(), declval<TaskTarget&>()));
  } else {
    return true;
  }
}
}  // namespace detail

// Descriptor of plugin class T, which derives from one of the five interfaces and has a static
// `ParameterSchema parameter_schema()`.
template <class T>
PluginDescriptor describe_plugin(const char* name, const char* version, const char* summary) {
  static_assert(detail::realtime_methods_not_noexcept<T>(),
                "a plugin's real-time methods (read, write, reset_fault; activate, update) are not declared "
                "noexcept, so that the server can contain an exception thrown despite the contract "
                "(hapticd/return_code.hpp)");
  PluginDescriptor d{};
  d.name = name;
  d.version = version;
  d.summary = summary;
  d.parameter_schema = &T::parameter_schema;
  if constexpr (requires { T::kDeviceInterfaces; }) {
    d.device_interfaces = T::kDeviceInterfaces;
  } else if constexpr (std::is_base_of_v<Controller, T> || std::is_base_of_v<InverseKinematics, T>) {
    d.device_interfaces = kJointsOnly;
  } else {
    d.device_interfaces = kEitherInterface;
  }
  if constexpr (std::is_base_of_v<Device, T>) {
    d.kind = PluginKind::device;
    d.create_device = []() -> std::unique_ptr<Device> { return std::make_unique<T>(); };
  } else if constexpr (std::is_base_of_v<Controller, T>) {
    d.kind = PluginKind::controller;
    d.create_controller = []() -> std::unique_ptr<Controller> { return std::make_unique<T>(); };
  } else if constexpr (std::is_base_of_v<InverseKinematics, T>) {
    d.kind = PluginKind::inverse_kinematics;
    d.create_inverse_kinematics = []() -> std::unique_ptr<InverseKinematics> { return std::make_unique<T>(); };
  } else if constexpr (std::is_base_of_v<GroupModel, T>) {
    d.kind = PluginKind::group_model;
    d.create_group_model = []() -> std::unique_ptr<GroupModel> { return std::make_unique<T>(); };
  } else if constexpr (std::is_base_of_v<SceneService, T>) {
    d.kind = PluginKind::scene;
    d.create_scene = []() -> std::unique_ptr<SceneService> { return std::make_unique<T>(); };
  } else {
    static_assert(std::is_base_of_v<VirtualModel, T>,
                  "a plugin derives from Device, Controller, "
                  "InverseKinematics, VirtualModel, GroupModel or SceneService");
    d.kind = PluginKind::virtual_model;
    d.create_virtual_model = []() -> std::unique_ptr<VirtualModel> { return std::make_unique<T>(); };
  }
  return d;
}

}  // namespace hapticd

#define HAPTICD_PLUGIN_LIBRARY(...)                                                               \
  extern "C" HAPTICD_API int hapticd_plugin_api_version() { return ::hapticd::kApiVersion; }      \
  extern "C" HAPTICD_API const ::hapticd::PluginCatalog* hapticd_plugin_catalog() {               \
    static const ::hapticd::PluginDescriptor entries[] = {__VA_ARGS__};                           \
    static const ::hapticd::PluginCatalog catalog{entries, sizeof(entries) / sizeof(entries[0])}; \
    return &catalog;                                                                              \
  }
