// The playback device (plugins/devices/playback): a recording of two test devices (mass-springs following a
// sine) replayed - the recorded cycles exactly at the recording's rate, interpolated at another rate or speed,
// the three ways to end, the configuration errors naming their key, and read() without allocating.
#include "playback_device.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/stat.h>
#include <yaml-cpp/yaml.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <thread>

#include "app/served_session.hpp"
#include "config/yaml_reader.hpp"
#include "executor/executor.hpp"
#include "hapticd/recording/recording_reader.hpp"
#include "hapticd/testing/allocation_guard.hpp"
#include "recorder/recorder.hpp"
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
    const server::LoopPlan loops = s.impl().loop_plan(&recorder);
    server::Executor executor(s.impl().executor_settings(), loops.loops());
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

// A copy of the recording whose dataset `path` of device "a" is replaced by `rows` x `width` doubles, written or
// only declared (a small file declaring a large dataset).
std::filesystem::path crafted(const std::string& name, const std::string& path, hsize_t rows, hsize_t width,
                              bool written = true) {
  const auto file = test::write_temp_file(name, "");
  std::filesystem::copy_file(recording(), file, std::filesystem::copy_options::overwrite_existing);
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  EXPECT_GE(f, 0);
  const std::string full = "/devices/a/" + path;
  EXPECT_GE(H5Ldelete(f, full.c_str(), H5P_DEFAULT), 0);
  const hsize_t dims[2] = {rows, width};
  const hid_t space = H5Screate_simple(2, dims, nullptr);
  const hid_t d = H5Dcreate2(f, full.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  EXPECT_GE(d, 0);
  if (written) {
    const std::vector<double> zeros(rows * width, 0.0);
    EXPECT_GE(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, zeros.data()), 0);
  }
  H5Dclose(d);
  H5Sclose(space);
  H5Fclose(f);
  return file;
}

// The configuration error a recording gives (the key and the message), or "accepted".
std::string refusal_of(const std::filesystem::path& file) {
  try {
    const Parameters p = server::read_parameters(YAML::Load("{recording: " + file.string() + ", device: a}"),
                                                 PlaybackDevice::parameter_schema(), "test.yaml", "parameters", 1);
    PlaybackDevice d;
    d.configure(p, PluginContext{});
  } catch (const ParameterError& e) {
    return e.key() + ": " + e.what();
  }
  return "accepted";
}

TEST(PlaybackDevice, AMalformedRecordingIsAnErrorNamingTheDatasetBeforeTheFirstCycle) {
  // The third hardening round's crafted recordings: a 1-column sensor wrench (a crash of the whole server), a
  // position 3 wide for 1 joint (replayed scrambled), a small file declaring a huge dataset (gigabytes taken),
  // a FIFO (a hang).
  const std::size_t rows = recorded_b().cycles;
  const std::string narrow = refusal_of(crafted("narrow_wrench.h5", "wrench/sensor", rows, 1));
  EXPECT_EQ(narrow.rfind("recording: ", 0), 0u) << narrow;
  EXPECT_NE(narrow.find("/devices/a/wrench/sensor is 1 wide"), std::string::npos) << narrow;
  const std::string wide = refusal_of(crafted("wide_position.h5", "joints/position", rows, 3));
  EXPECT_NE(wide.find("/devices/a/joints/position is 3 wide; the recorded device has 1 joints, so it must be 1"),
            std::string::npos)
      << wide;
  const auto before = std::chrono::steady_clock::now();
  const auto huge_file = crafted("huge.h5", "joints/velocity", hsize_t{1} << 36, 1, /*written=*/false);
  EXPECT_LT(std::filesystem::file_size(huge_file), std::filesystem::file_size(recording()) + (1u << 16));  // small
  const std::string huge = refusal_of(huge_file);
  EXPECT_NE(huge.find("joints/velocity declares 68719476736 x 1 values but the file stores"), std::string::npos)
      << huge;
  EXPECT_LT(std::chrono::steady_clock::now() - before, std::chrono::seconds(5));
  const auto fifo = test::write_temp_file("fifo.h5", "");
  std::filesystem::remove(fifo);
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const std::string pipe = refusal_of(fifo);  // (before: blocked in open() for good)
  EXPECT_NE(pipe.find("not a regular file"), std::string::npos) << pipe;
  std::filesystem::remove(fifo);
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
