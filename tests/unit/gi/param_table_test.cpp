// The parameter tables of every field type (gi/param_table.h), tested from the tables
// themselves: every parameter has range cases (a parameter declared without a range fails here
// unless it is listed as having no out-of-range value), values just outside a range are refused
// by validate() with the parameter's name and range, the bounds are accepted, each name reads
// and writes its own member, and text round-trips.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "gi/field_params.h"
#include "gi/shadow_params.h"
#include "gi/world_cache.h"

namespace ddgi {
namespace {

using ::testing::HasSubstr;

// Each field type's table, and its parameters that no value of their type puts out of range:
// booleans, seeds, and limits that are rules across parameters (tested with the struct's
// validate(), e.g. FieldParams.OutOfRangeValuesNameTheFieldAndRange).
template <typename P>
struct Field;
template <>
struct Field<IrradianceFieldParams> {
  static const ParamTable<IrradianceFieldParams>& table() { return field_param_table(); }
  static std::vector<std::string> unbounded() {
    return {"track_camera", "classification", "max_rays_per_update", "seed"};
  }
};
template <>
struct Field<ShadowFieldParams> {
  static const ParamTable<ShadowFieldParams>& table() { return shadow_param_table(); }
  static std::vector<std::string> unbounded() { return {"split_update", "seed"}; }
};

template <>
struct Field<WorldCacheParams> {
  static const ParamTable<WorldCacheParams>& table() { return world_cache_param_table(); }
  static std::vector<std::string> unbounded() { return {}; }
};

template <typename P>
class ParamTableTest : public ::testing::Test {};
using FieldTypes = ::testing::Types<IrradianceFieldParams, ShadowFieldParams, WorldCacheParams>;
TYPED_TEST_SUITE(ParamTableTest, FieldTypes);

TYPED_TEST(ParamTableTest, EveryParameterHasRangeCases) {
  const std::vector<std::string> unbounded = Field<TypeParam>::unbounded();
  for (const ParamSpec<TypeParam>& spec : Field<TypeParam>::table().specs()) {
    const auto refused =
        std::count_if(spec.examples.begin(), spec.examples.end(),
                      [](const ParamExample<TypeParam>& e) { return !e.refusal.empty(); });
    const bool listed = std::find(unbounded.begin(), unbounded.end(), spec.name) != unbounded.end();
    if (listed) {
      EXPECT_EQ(refused, 0) << spec.name << " has out-of-range values: take it off the list";
    } else {
      EXPECT_GT(refused, 0) << spec.name << " has no out-of-range value: declare its range";
    }
    EXPECT_LT(refused, std::ssize(spec.examples)) << spec.name << " has no accepted value";
  }
}

TYPED_TEST(ParamTableTest, ValuesOutsideTheRangeAreRefusedWithNameAndRange) {
  const ParamTable<TypeParam>& table = Field<TypeParam>::table();
  for (const ParamSpec<TypeParam>& spec : table.specs()) {
    for (const ParamExample<TypeParam>& example : spec.examples) {
      if (example.refusal.empty()) continue;
      TypeParam p;
      example.apply(p);
      const Status status = validate(p);
      ASSERT_FALSE(status.ok()) << spec.name << " = " << example.value;
      EXPECT_THAT(status.error().message, HasSubstr(table.prefix() + example.refusal))
          << spec.name << " = " << example.value;
    }
  }
}

// The bounds pass the table's ranges (validate() may still refuse them for a rule across
// parameters, e.g. fixed_rays=0 while relocation is on).
TYPED_TEST(ParamTableTest, BoundsAreAccepted) {
  const ParamTable<TypeParam>& table = Field<TypeParam>::table();
  for (const ParamSpec<TypeParam>& spec : table.specs()) {
    for (const ParamExample<TypeParam>& example : spec.examples) {
      if (!example.refusal.empty()) continue;
      TypeParam p;
      example.apply(p);
      const Status status = table.check(p);
      EXPECT_TRUE(status.ok()) << spec.name << " = " << example.value << ": "
                               << (status.ok() ? "" : status.error().message);
    }
  }
}

// Setting one parameter changes no other parameter (two names on one member would).
TYPED_TEST(ParamTableTest, EachParameterIsItsOwnMember) {
  const ParamTable<TypeParam>& table = Field<TypeParam>::table();
  const TypeParam defaults;
  for (const ParamSpec<TypeParam>& spec : table.specs()) {
    for (const ParamExample<TypeParam>& example : spec.examples) {
      TypeParam p;
      example.apply(p);
      for (const ParamSpec<TypeParam>& other : table.specs()) {
        if (other.name == spec.name) continue;
        EXPECT_EQ(other.format(p), other.format(defaults))
            << spec.name << " = " << example.value << " changed " << other.name;
      }
    }
  }
}

// What format() writes, parse() reads back to the same struct, at every accepted value.
TYPED_TEST(ParamTableTest, TextRoundTripsTheBounds) {
  const ParamTable<TypeParam>& table = Field<TypeParam>::table();
  for (const ParamSpec<TypeParam>& spec : table.specs()) {
    for (const ParamExample<TypeParam>& example : spec.examples) {
      if (!example.refusal.empty()) continue;
      TypeParam p;
      example.apply(p);
      const std::string text = spec.format(p);
      TypeParam read;
      const Status status = table.set(read, spec.name, text);
      ASSERT_TRUE(status.ok()) << spec.name << "=" << text << ": " << status.error().message;
      EXPECT_TRUE(read == p) << spec.name << "=" << text;
    }
  }
}

TYPED_TEST(ParamTableTest, NamesAreUniqueAndHelpHasALineEach) {
  const ParamTable<TypeParam>& table = Field<TypeParam>::table();
  std::set<std::string> names;
  const std::string help = table.help();
  for (const ParamSpec<TypeParam>& spec : table.specs()) {
    EXPECT_TRUE(names.insert(spec.name).second) << spec.name << " is declared twice";
    EXPECT_THAT(help, HasSubstr("  " + spec.name + " ")) << spec.name;
    EXPECT_THAT(help, HasSubstr(" " + spec.help + "\n")) << spec.name;
  }
  EXPECT_EQ(std::count(help.begin(), help.end(), '\n'), std::ssize(table.specs()));
}

// The world cache's one rule beyond its ranges: a table of a power of two slots (the shaders
// mask keys into it). A control: the same number of slots rounded to a power passes.
TEST(WorldCacheParams, EntriesMustBeAPowerOfTwo) {
  WorldCacheParams p;
  p.entries = 3000;
  const Status status = validate(p);
  ASSERT_FALSE(status.ok());
  EXPECT_THAT(status.error().message, HasSubstr("world cache entries must be a power of two"));
  p.entries = 4096;
  EXPECT_TRUE(validate(p).ok());
}

}  // namespace
}  // namespace ddgi
