// The layout a parameter's description travels in (hapticd/parameter_info.hpp): written and read back, bounds
// absent or exclusive, a field with a tab, a reply of another kind.
#include "hapticd/parameter_info.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace hapticd {
namespace {

TEST(ParameterInfo, ReadsBackWhatItWrote) {
  ParameterInfo p;
  p.name = "controller.kp";
  p.type = ParameterType::real_vector;
  p.unit = "N/m";
  p.description = "gain\twith a tab";
  p.tunable = true;
  p.minimum = 0.0;
  p.minimum_exclusive = true;
  p.value_text = "[1, 2, 3]";
  p.value = {1.0, 2.0, 3.0};
  const RuntimeReply r = encode_parameter_info(p, 7);
  EXPECT_TRUE(r.accepted);
  EXPECT_TRUE(std::isnan(r.values[3]));  // no maximum
  const auto d = decode_parameter_info(r.message, r.values);
  ASSERT_TRUE(d.has_value());
  EXPECT_EQ(d->count, 7u);
  EXPECT_EQ(d->info.name, p.name);
  EXPECT_EQ(d->info.type, p.type);
  EXPECT_EQ(d->info.unit, p.unit);
  EXPECT_EQ(d->info.description, "gain with a tab");
  EXPECT_TRUE(d->info.tunable);
  EXPECT_EQ(d->info.minimum, 0.0);
  EXPECT_FALSE(d->info.maximum.has_value());
  EXPECT_TRUE(d->info.minimum_exclusive);
  EXPECT_EQ(d->info.value, p.value);
  EXPECT_EQ(d->info.value_text, p.value_text);
  EXPECT_EQ(d->info.bounds_text(), "> 0");
}

TEST(ParameterInfo, SaysTheBoundsInOnePhrase) {
  ParameterInfo p;
  EXPECT_EQ(p.bounds_text(), "any");
  p.minimum = 0.1;
  p.maximum = 1000.0;
  EXPECT_EQ(p.bounds_text(), "0.1 to 1000");
  p.minimum.reset();
  EXPECT_EQ(p.bounds_text(), "<= 1000");
}

TEST(ParameterInfo, RefusesAReplyOfAnotherLayout) {
  EXPECT_FALSE(decode_parameter_info("mass_kg = [3, 3, 3]", {3.0, 3.0, 3.0}).has_value());   // a get reply
  EXPECT_FALSE(decode_parameter_info("a\treal\t\t1", {1.0, 0.0}).has_value());               // too few numbers
  EXPECT_FALSE(decode_parameter_info("a\tcomplex\t\t1", {1.0, 0.0, NAN, NAN}).has_value());  // unknown type
  EXPECT_FALSE(decode_parameter_info("a\treal\t\t1", {0.0, 0.0, NAN, NAN}).has_value());     // no parameters
  EXPECT_FALSE(decode_parameter_info("a\treal\t\t1", {1.0, 9.0, NAN, NAN}).has_value());     // unknown flags
}

}  // namespace
}  // namespace hapticd
