// The library's entry: every example plugin, one of each kind but inverse kinematics.
#include "linear_axis_device.hpp"
#include "point_mass_model.hpp"
#include "spring_link_group_model.hpp"
#include "spring_wall_controller.hpp"
#include "wall_model.hpp"

HAPTICD_PLUGIN_LIBRARY(
    hapticd::describe_plugin<example::SpringWallController>("example_spring_wall", "1.0.0",
                                                            "example: joint PD plus a one-sided wall on joint 1"),
    hapticd::describe_plugin<example::WallModel>("example_wall", "1.0.0",
                                                 "example: a horizontal wall (impedance-type virtual model)"),
    hapticd::describe_plugin<example::PointMassModel>("example_point_mass", "1.0.0",
                                                      "example: a damped point mass (admittance-type virtual model)"),
    hapticd::describe_plugin<example::LinearAxisDevice>("example_linear_axis", "1.0.0",
                                                        "example: a simulated linear axis (device)"),
    hapticd::describe_plugin<example::SpringLinkGroupModel>("example_spring_link", "1.0.0",
                                                            "example: a spring between two hands (group model)"))
