// VendorLibrary (plugins/common/vendor_library.hpp): a vendor's SDK library found where the session or the
// machine says, its functions taken by name, and a plain error naming every place tried when it is not there.
#include "vendor_library.hpp"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <string>

#include "support/test_paths.hpp"

namespace hapticd::plugins {
namespace {

using Answer = int (*)();
using Scale = double (*)(double, char);

VendorLibrarySearch fixture_search() {
  VendorLibrarySearch s;
  s.vendor = "Example SDK";
  s.names = {"libvendor_fixture_missing.so", "libvendor_fixture.so"};
  s.environment = "HAPTICD_TEST_EXAMPLE_SDK";
  s.subdirs = {"lib"};
  return s;
}

TEST(VendorLibrary, FindsTheLibraryAtTheSessionsPathAFileOrAFolder) {
  VendorLibrarySearch s = fixture_search();
  s.path = test::fixture_dir() + "/libvendor_fixture.so";
  const VendorLibrary by_file(s);
  EXPECT_EQ(by_file.function<Answer>("fixture_answer")(), 42);
  EXPECT_DOUBLE_EQ(by_file.function<Scale>("fixture_scale")(2.0, 2), 6.0);
  s.path = test::fixture_dir();
  const VendorLibrary by_folder(s);
  EXPECT_EQ(by_folder.file(), test::fixture_dir() + "/libvendor_fixture.so");
  EXPECT_EQ(by_folder.function<Answer>("fixture_answer")(), 42);
}

TEST(VendorLibrary, FindsTheLibraryBelowTheVendorsVariable) {
  const std::filesystem::path root = std::filesystem::temp_directory_path() / "hapticd-vendor-sdk-test";
  std::filesystem::remove_all(root);
  std::filesystem::create_directories(root / "lib");
  std::filesystem::copy_file(test::fixture_dir() + "/libvendor_fixture.so", root / "lib" / "libvendor_fixture.so");
  ::setenv("HAPTICD_TEST_EXAMPLE_SDK", root.c_str(), 1);
  {
    const VendorLibrary library(fixture_search());
    EXPECT_EQ(library.file(), (root / "lib" / "libvendor_fixture.so").string());
    EXPECT_EQ(library.function<Answer>("fixture_answer")(), 42);
  }
  ::unsetenv("HAPTICD_TEST_EXAMPLE_SDK");
  std::filesystem::remove_all(root);
}

TEST(VendorLibrary, AMissingLibraryNamesTheVendorAndEveryPlaceTried) {
  VendorLibrarySearch s = fixture_search();
  s.names = {"libno_such_vendor_sdk.so"};
  ::setenv("HAPTICD_TEST_EXAMPLE_SDK", "/nonexistent/root", 1);
  try {
    const VendorLibrary library(s);
    FAIL() << "loaded " << library.file();
  } catch (const VendorLibraryError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("the Example SDK library was not found"), std::string::npos) << what;
    EXPECT_NE(what.find("$HAPTICD_TEST_EXAMPLE_SDK"), std::string::npos) << what;
    EXPECT_NE(what.find("/nonexistent/root/lib/libno_such_vendor_sdk.so"), std::string::npos) << what;
    EXPECT_NE(what.find("docs/devices.md"), std::string::npos) << what;
  }
  ::unsetenv("HAPTICD_TEST_EXAMPLE_SDK");
}

TEST(VendorLibrary, ASessionsPathIsTheOnlyPlaceTriedWhenGiven) {
  // A wrong sdk_path is an error, never another library found elsewhere: here the fixture library is in the folder of
  // the vendor's variable, and still not taken.
  VendorLibrarySearch s = fixture_search();
  s.path = "/nonexistent/sdk";
  ::setenv("HAPTICD_TEST_EXAMPLE_SDK", test::fixture_dir().c_str(), 1);
  try {
    const VendorLibrary library(s);
    FAIL() << "loaded " << library.file();
  } catch (const VendorLibraryError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("/nonexistent/sdk"), std::string::npos) << what;
  }
  ::unsetenv("HAPTICD_TEST_EXAMPLE_SDK");
}

TEST(VendorLibrary, AMissingFunctionIsAnErrorUnlessOptional) {
  VendorLibrarySearch s = fixture_search();
  s.path = test::fixture_dir();
  const VendorLibrary library(s);
  EXPECT_EQ(library.optional_function<Answer>("fixture_not_there"), nullptr);
  try {
    (void)library.function<Answer>("fixture_not_there");
    FAIL() << "a missing function was found";
  } catch (const VendorLibraryError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("has no function fixture_not_there"), std::string::npos) << what;
    EXPECT_NE(what.find("libvendor_fixture.so"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace hapticd::plugins
