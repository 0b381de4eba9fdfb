// The playback device (plugins/devices/playback): a recording of two test devices (mass-springs following a
// sine) replayed - the recorded cycles exactly at the recording's rate, interpolated at another rate or speed,
// the three ways to end, the configuration errors naming their key, and read() without allocating.
#include "playback_device.hpp"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <atomic>

#include "app/served_session.hpp"
#include "config/yaml_reader.hpp"
#include "executor/executor.hpp"
#include "hapticd/testing/allocation_guard.hpp"
#include "recorder/recorder.hpp"
#include "recorder/recording_reader.hpp"
#include "support/temp_file.hpp"
#include "support/test_session.hpp"

namespace hapticd::playback {
namespace {

// Two devices, 0.5 s at 2 kHz (and the 0.1 s ramp): 1200 cycles each.
const std::filesystem::path& recording() {
  static const std::filesystem::path file = [] {
    auto s = test::build_test_session(
        "server: {clock: lockstep, rate_hz: 2000, duration_s: 0.5, shutdown_ramp_s: 0.1, seed: 3}\ndevices:\n" +
        test::mass_spring_device_yaml("a") + test::mass_spring_device_yaml("b", ", initial_position_m: 0.02"));
    const auto path = test::write_temp_file("playback_source.h5", "");
    server::Recorder recorder(path, server::recording_header(s.impl().config, s.impl().device_pointers()), true);
    server::Executor executor(s.impl().executor_settings(), s.impl().device_pointers(), &recorder);
    std::atomic<bool> stop{false};
    (void)executor.run(stop);
    recorder.close();
    return path;
  }();
  return file;
}

const recording::RecordedDevice& recorded_b() {
  static const recording::RecordedDevice r =
      recording::read_device(recording(), "b", {"time_s", "joints/position", "joints/velocity"});
  return r;
}

struct Rig {
  explicit Rig(const std::string& parameters_yaml, double rate_hz = 2000.0) {
    const Parameters p =
        server::read_parameters(YAML::Load("{recording: " + recording().string() + ", " + parameters_yaml + "}"),
                                PlaybackDevice::parameter_schema(), "test.yaml", "parameters", 1);
    PluginContext context;
    context.rate_hz = rate_hz;
    device.configure(p, context);
    period_ns = static_cast<std::int64_t>(1e9 / rate_hz);
    state.joints.resize(device.description().dof());
    (void)device.enable();
  }
  Outcome read(std::int64_t k) {
    return device.read(CycleTime{k * period_ns, period_ns, static_cast<std::uint64_t>(k)}, state);
  }
  PlaybackDevice device;
  DeviceState state;
  std::int64_t period_ns = 0;
};

double recorded_position(std::size_t row) { return recorded_b().datasets.at("joints/position").values.at(row); }

TEST(PlaybackDevice, ReplaysTheRecordedCyclesAtTheRecordingsRate) {
  Rig rig("device: b");
  const DeviceDescription& d = rig.device.description();
  EXPECT_EQ(d.model, "playback of test_mass_spring");
  ASSERT_EQ(d.dof(), 1);
  EXPECT_EQ(d.joints[0].name, "x");
  EXPECT_TRUE(d.simulated);
  EXPECT_TRUE(d.reports_joint_velocity);
  EXPECT_FALSE(d.reports_wrench);  // the recorded device had no sensor
  const auto& velocity = recorded_b().datasets.at("joints/velocity").values;
  ASSERT_EQ(recorded_b().cycles, 1200u);
  EXPECT_NEAR(rig.device.duration_s(), 1199 * 0.0005, 1e-12);
  for (std::int64_t k = 0; k < 1200; ++k) {
    ASSERT_TRUE(rig.read(k).ok());
    ASSERT_EQ(rig.state.joints.position[0], recorded_position(static_cast<std::size_t>(k))) << k;
    ASSERT_EQ(rig.state.joints.velocity[0], velocity[static_cast<std::size_t>(k)]) << k;
  }
  EXPECT_GT(std::abs(recorded_position(300) - recorded_position(100)), 1e-3);  // it moved: the check means something
}

TEST(PlaybackDevice, InterpolatesAtAnotherRateAndSpeedAndStartsLater) {
  Rig fast("device: b", 4000.0);  // every other cycle between two recorded ones
  for (std::int64_t k = 0; k < 400; ++k) {
    ASSERT_TRUE(fast.read(k).ok());
    const auto row = static_cast<std::size_t>(k / 2);
    const double expected =
        k % 2 == 0 ? recorded_position(row) : 0.5 * (recorded_position(row) + recorded_position(row + 1));
    ASSERT_NEAR(fast.state.joints.position[0], expected, 1e-15) << k;
  }
  Rig twice("device: b, speed: 2, start_s: 0.1");  // cycle k: recorded row 200 + 2k
  for (std::int64_t k = 0; k < 400; ++k) {
    ASSERT_TRUE(twice.read(k).ok());
    ASSERT_NEAR(twice.state.joints.position[0], recorded_position(200 + 2 * static_cast<std::size_t>(k)), 1e-15) << k;
  }
}

TEST(PlaybackDevice, HoldsLoopsOrFaultsAtTheEnd) {
  Rig hold("device: b");
  Rig loop("device: b, at_end: loop");
  Rig fault("device: b, at_end: fault");
  for (std::int64_t k = 0; k < 1200; ++k) ASSERT_TRUE(hold.read(k).ok() && loop.read(k).ok() && fault.read(k).ok());
  const double last = recorded_position(1199);
  for (std::int64_t k = 1200; k < 1500; ++k) {
    ASSERT_TRUE(hold.read(k).ok());
    EXPECT_EQ(hold.state.joints.position[0], last);
  }
  // Looping: 1199 periods long, so cycle 1199 + j is row j again (to rounding of the time).
  for (std::int64_t j = 1; j < 300; ++j) {
    ASSERT_TRUE(loop.read(1199 + j).ok());
    ASSERT_NEAR(loop.state.joints.position[0], recorded_position(static_cast<std::size_t>(j)), 1e-9) << j;
  }
  const Outcome ended = fault.read(1200);
  EXPECT_FALSE(ended.ok());
  EXPECT_STREQ(ended.reason, "the recording ended");
}

TEST(PlaybackDevice, ConfigurationErrorsNameTheirKey) {
  const auto key_of = [](const std::string& yaml) -> std::string {
    try {
      Rig rig(yaml);
    } catch (const ParameterError& e) {
      return e.key() + ": " + e.what();
    }
    return "accepted";
  };
  const std::string two = key_of("device: ''");
  EXPECT_EQ(two.rfind("device: ", 0), 0u) << two;
  EXPECT_NE(two.find("has 2 devices (a, b): name the one to replay"), std::string::npos) << two;
  const std::string unknown = key_of("device: c");
  EXPECT_EQ(unknown.rfind("device: ", 0), 0u) << unknown;
  EXPECT_NE(unknown.find("has no device 'c' (it has a, b)"), std::string::npos) << unknown;
  const std::string late = key_of("device: a, start_s: 5");
  EXPECT_EQ(late.rfind("start_s: ", 0), 0u) << late;
  EXPECT_THROW(Rig("device: a, at_end: rewind"), std::exception);  // not one of the schema's choices
  for (const char* yaml : {"{recording: /nonexistent/run.h5}", "{recording: /nonexistent/run.h5, device: a}"}) {
    try {  // a missing file is the recording's fault, whether a device is named or not
      const Parameters p =
          server::read_parameters(YAML::Load(yaml), PlaybackDevice::parameter_schema(), "test.yaml", "parameters", 1);
      PlaybackDevice d;
      d.configure(p, PluginContext{});
      ADD_FAILURE() << "a missing recording was accepted: " << yaml;
    } catch (const ParameterError& e) {
      EXPECT_EQ(e.key(), "recording") << yaml;
      EXPECT_NE(std::string(e.what()).find("cannot open /nonexistent/run.h5"), std::string::npos) << e.what();
    }
  }
}

TEST(PlaybackDevice, ReadDoesNotAllocate) {
  if (!testing::AllocationGuard::available()) GTEST_SKIP() << "no allocation counting in this build";
  Rig rig("device: a, at_end: loop", 3000.0);
  ASSERT_TRUE(rig.read(0).ok());
  const testing::AllocationGuard guard;
  for (std::int64_t k = 1; k < 5000; ++k) ASSERT_TRUE(rig.read(k).ok());
  EXPECT_EQ(guard.allocations(), 0u);
}

}  // namespace
}  // namespace hapticd::playback
