// The Force Dimension stand-in (tests/standins/forcedimension): loaded as the plugin will load the vendor's
// library (VendorLibrary, by the documented function names and prototypes), it behaves as the SDK's documentation
// says - open by serial number, the default device, errors with their text, force enabling refused before
// calibration - and its handle moves under force: what the device tests will rely on.
#include <gtest/gtest.h>

#include <string>

#include "support/test_paths.hpp"
#include "vendor_library.hpp"

namespace hapticd::plugins {
namespace {

struct Dhd {
  explicit Dhd(const VendorLibrary& l)
      : open_serial(l.function<int (*)(int)>("dhdOpenSerial")),
        close(l.function<int (*)(char)>("dhdClose")),
        enable_force(l.function<int (*)(unsigned char, char)>("dhdEnableForce")),
        position(l.function<int (*)(double*, double*, double*, char)>("dhdGetPosition")),
        set_force(l.function<int (*)(double, double, double, double, double, double, double, char)>(
            "dhdSetForceAndTorqueAndGripperForce")),
        error_text(l.function<const char* (*)()>("dhdErrorGetLastStr")),
        calibrated(l.function<bool (*)(char)>("drdIsInitialized")),
        auto_init(l.function<int (*)(char)>("drdAutoInit")),
        setup(l.function<void (*)(const char*)>("standin_dhd_setup")),
        set_step(l.function<void (*)(double)>("standin_dhd_set_step")),
        fault(l.function<bool (*)(int, const char*)>("standin_dhd_fault")),
        hand(l.function<bool (*)(int, double, double, double, unsigned)>("standin_dhd_hand")),
        call_log(l.function<const char* (*)()>("standin_dhd_call_log")) {}
  int (*open_serial)(int);
  int (*close)(char);
  int (*enable_force)(unsigned char, char);
  int (*position)(double*, double*, double*, char);
  int (*set_force)(double, double, double, double, double, double, double, char);
  const char* (*error_text)();
  bool (*calibrated)(char);
  int (*auto_init)(char);
  void (*setup)(const char*);
  void (*set_step)(double);
  bool (*fault)(int, const char*);
  bool (*hand)(int, double, double, double, unsigned);
  const char* (*call_log)();
};

VendorLibrary standin() {
  VendorLibrarySearch s;
  s.vendor = "Force Dimension SDK";
  s.names = {"libdrd.so"};
  s.path = test::standin_dir() + "/forcedimension";
  return VendorLibrary(s);
}

TEST(DhdStandin, OpensBySerialNumberAndMovesItsHandleUnderForce) {
  const VendorLibrary library = standin();
  Dhd dhd(library);
  dhd.setup("omega.6:10001,omega.7:10002");
  dhd.set_step(0.001);
  EXPECT_EQ(dhd.open_serial(12345), -1);
  EXPECT_STREQ(dhd.error_text(), "no compatible Force Dimension device found");
  const int id = dhd.open_serial(10002);
  ASSERT_EQ(id, 1);
  ASSERT_EQ(dhd.enable_force(1, static_cast<char>(id)), 0);
  // 1 N along +x on 0.25 kg against 2 N s/m for 0.1 s (tau 0.125 s): x = (1/2)(0.1 - 0.125 (1 - e^{-0.8})) = 15.6 mm
  // (the stand-in's 1 ms semi-implicit Euler steps: 15.8 mm).
  for (int k = 0; k < 101; ++k) ASSERT_EQ(dhd.set_force(1.0, 0, 0, 0, 0, 0, 0, static_cast<char>(id)), 0);
  double x = 0, y = 0, z = 0;
  ASSERT_EQ(dhd.position(&x, &y, &z, -1), 0);  // -1: the default device, the last one opened
  EXPECT_NEAR(x, 0.0156, 0.0003);
  EXPECT_EQ(y, 0.0);
  // A force beyond the device's peak is capped, and the call says so (DHD_MOTOR_SATURATED).
  EXPECT_EQ(dhd.set_force(50.0, 0, 0, 0, 0, 0, 0, static_cast<char>(id)), 2);
  ASSERT_EQ(dhd.enable_force(0, static_cast<char>(id)), 0);
  ASSERT_EQ(dhd.close(static_cast<char>(id)), 0);
  EXPECT_EQ(std::string(dhd.call_log()), "dhdOpen(1)\ndhdEnableForce(on)(1)\ndhdEnableForce(off)(1)\ndhdClose(1)\n");
}

TEST(DhdStandin, FaultsOnCueWithTheVendorsErrorText) {
  const VendorLibrary library = standin();
  Dhd dhd(library);
  dhd.setup("omega.6:10001");
  ASSERT_TRUE(dhd.fault(0, "uncalibrated"));
  const int id = dhd.open_serial(10001);
  ASSERT_EQ(id, 0);
  EXPECT_FALSE(dhd.calibrated(0));
  EXPECT_EQ(dhd.enable_force(1, 0), -1);
  EXPECT_STREQ(dhd.error_text(), "device not ready (not calibrated)");
  ASSERT_EQ(dhd.auto_init(0), 0);
  EXPECT_TRUE(dhd.calibrated(0));
  ASSERT_EQ(dhd.enable_force(1, 0), 0);
  ASSERT_TRUE(dhd.fault(0, "fail_next_force"));
  EXPECT_EQ(dhd.set_force(0, 0, 0, 0, 0, 0, 0, 0), -1);
  EXPECT_EQ(dhd.set_force(0, 0, 0, 0, 0, 0, 0, 0), 0);  // once
  ASSERT_TRUE(dhd.fault(0, "unplug"));
  double x = 0, y = 0, z = 0;
  EXPECT_EQ(dhd.position(&x, &y, &z, 0), -1);
  EXPECT_STREQ(dhd.error_text(), "communication error between the host and the device");
  EXPECT_FALSE(dhd.fault(3, "unplug"));
  EXPECT_FALSE(dhd.fault(0, "no_such_fault"));
}

}  // namespace
}  // namespace hapticd::plugins
