// Entry points of the test plugin library.
#include "axis_inverse_kinematics.hpp"
#include "faulty_group_model.hpp"
#include "hapticd/plugin.hpp"
#include "mass_spring_device.hpp"
#include "pd_controller.hpp"
#include "sine_setpoint_model.hpp"

using namespace hapticd;
using namespace hapticd::test_plugins;

HAPTICD_PLUGIN_LIBRARY(
    describe_plugin<MassSpringDevice>("test_mass_spring", "1.0.0", "1-DOF mass on a spring (foundation tests)"),
    describe_plugin<PdController>("test_pd", "1.0.0", "joint PD control (foundation tests)"),
    describe_plugin<SineSetpointModel>("test_sine_setpoint", "1.0.0", "sinusoidal desired motion along x"),
    describe_plugin<AxisInverseKinematics>("test_axis_ik", "1.0.0", "identity map x,y,z -> joints 1..3"),
    describe_plugin<FaultyGroupModel>("test_faulty_group_model", "1.0.0", "a group model that fails on cue"))
