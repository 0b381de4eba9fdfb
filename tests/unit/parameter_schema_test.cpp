#include <gtest/gtest.h>

#include "hapticd/parameters.hpp"

namespace hapticd {
namespace {

ParameterSchema example_schema() {
  ParameterSchema s;
  s.real("kp", "gain").unit("N/m").minimum(0.0).maximum(100.0).default_value(10.0);
  s.real("mass", "mass").greater_than(0.0);
  s.integer("n", "count").minimum(1).default_value(std::int64_t{3});
  s.string("mode", "mode").choices({"a", "b"}).default_value(std::string("a"));
  s.real_vector("gains", "per joint").size(3).minimum(-1.0).maximum(1.0).default_value(std::vector<double>{0, 0, 0});
  return s;
}

TEST(ParameterSchema, ChecksBoundsAndSaysWhatIsValid) {
  const ParameterSchema s = example_schema();
  EXPECT_NO_THROW(s.find("kp")->check(0.0));
  EXPECT_NO_THROW(s.find("kp")->check(100.0));
  try {
    s.find("kp")->check(-0.5);
    FAIL();
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.key(), "kp");
    EXPECT_STREQ(e.what(), "value -0.5 is below the minimum 0");
  }
  EXPECT_THROW(s.find("kp")->check(100.5), ParameterError);
  EXPECT_THROW(s.find("kp")->check(std::numeric_limits<double>::quiet_NaN()), ParameterError);
  EXPECT_THROW(s.find("mass")->check(0.0), ParameterError);
  EXPECT_NO_THROW(s.find("mass")->check(1e-9));
  EXPECT_THROW(s.find("n")->check(std::int64_t{0}), ParameterError);
}

TEST(ParameterSchema, ChecksVectorsAndChoices) {
  const ParameterSchema s = example_schema();
  EXPECT_NO_THROW(s.find("gains")->check(std::vector<double>{1, 0, -1}));
  try {
    s.find("gains")->check(std::vector<double>{1, 0});
    FAIL();
  } catch (const ParameterError& e) {
    EXPECT_STREQ(e.what(), "expected 3 elements, got 2");
  }
  try {
    s.find("gains")->check(std::vector<double>{0, 2, 0});
    FAIL();
  } catch (const ParameterError& e) {
    EXPECT_STREQ(e.what(), "element 1 2 is above the maximum 1");
  }
  EXPECT_NO_THROW(s.find("mode")->check(std::string("b")));
  EXPECT_THROW(s.find("mode")->check(std::string("c")), ParameterError);
}

TEST(ParameterSchema, DocumentsEachParameter) {
  const ParameterSchema s = example_schema();
  EXPECT_EQ(s.find("kp")->constraints_text(), "real [N/m], >= 0, <= 100, default 10");
  EXPECT_EQ(s.find("mass")->constraints_text(), "real, > 0, required");
  EXPECT_EQ(s.find("mode")->constraints_text(), "string, one of: a b, default \"a\"");
  EXPECT_TRUE(s.find("mass")->required());
  EXPECT_FALSE(s.find("kp")->required());
  EXPECT_EQ(s.find("nope"), nullptr);
}

TEST(ParameterSchema, IntegerDefaultOfARealIsStoredAsReal) {
  ParameterSchema s;
  s.real("x", "x").default_value(std::int64_t{2});
  ASSERT_TRUE(std::holds_alternative<double>(*s.find("x")->default_value));
}

TEST(Parameters, TypedAccessAndOrigin) {
  Parameters p;
  p.set("kp", 2.5, "file.yaml:7");
  p.set("on", true);
  EXPECT_EQ(p.real("kp"), 2.5);
  EXPECT_TRUE(p.boolean("on"));
  EXPECT_EQ(p.origin("kp"), "file.yaml:7");
  EXPECT_EQ(p.origin("on"), "");
  EXPECT_THROW((void)p.integer("kp"), ParameterError);
  EXPECT_THROW((void)p.real("missing"), ParameterError);
}

}  // namespace
}  // namespace hapticd
