#pragma once

namespace hapticd {

// Version of the binary plugin contract (interfaces, value types, descriptor layout). A plugin built against
// another version is refused by the loader before any of its code is called. Bump on every change to a type
// in api/include/hapticd that a plugin compiles against.
inline constexpr int kApiVersion = 17;  // 2: DeviceState::sensor_acceleration; 3: ChainState in the inputs;
                                        // 4: EngineInput in VirtualModelInput; 5: EngineInput weight,
                                        //    local model and motion; 6: RenderGuard in
                                        //    VirtualModelInput, update() may throw;
                                        // 7: RedundancyResolution (IK -> controller)
                                        // 8: inputs by reference; one joint velocity (DeviceState's, the
                                        //    estimate; ChainState::velocity gone); RenderPort with the model's
                                        //    answers in TaskTarget; the parsed robot model in PluginContext;
                                        //    DeviceDescription::simulated, Device::simulated_truth
                                        //    (8 is unreleased until Core v2 closes: it may still grow)
                                        // 9: GroupModel (a fifth plugin kind: the group stage's model),
                                        //    ChainState::neighbour (the nearest arm of the group)
                                        // 10: one SDK for every kind: RuntimeRequests (tune, handle_request)
                                        //    shared by all five; Outcome from every real-time call; the
                                        //    rule for noexcept checked by describe_plugin; RenderPort
                                        //    records limit() and take_safety_force() (TaskTarget's
                                        //    wrench_limited, includes_safety_force gone)
                                        // 11: handle devices (DeviceDescription::interface and handle,
                                        //    DeviceState::handle, ChainState::has_handle), the
                                        //    descriptor's device_interfaces
                                        // 12: Device::clock() (device-clocked loops)
                                        // 13: DeviceDescription::serial and vendor_software
                                        // 14: HandleCommand and Device::write_handle (a handle device takes
                                        //    newtons, not joint torques); Device::write no longer pure
                                        // 15: the scene plugin kind (SceneService, PluginDescriptor::create_scene)
                                        //    and PluginContext::scene
                                        // 16: SceneService::add_mesh (a mesh an engine uploaded);
                                        // 17: SceneService::drawing (the live view's picture of the scene)

}  // namespace hapticd
