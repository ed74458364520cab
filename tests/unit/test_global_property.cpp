// fix property/global parsing and validation (spec granular-models §3).
#include "global_property.h"

#include <gtest/gtest.h>

using dembridge::property::GlobalProperty;
using dembridge::property::Kind;
using dembridge::property::PropertyError;
using Args = std::vector<std::string>;

static std::string error_of(const Args &a)
{
  try {
    GlobalProperty::parse(a);
  } catch (const PropertyError &e) {
    return e.what();
  }
  return "";
}

TEST(GlobalProperty, PerTypePairIsRowMajorAndOneBased)
{
  const auto p = GlobalProperty::parse({"coefficientFriction", "peratomtypepair", "2", "0.5", "0.3", "0.3", "0.2"});
  EXPECT_EQ(p.kind(), Kind::PerTypePair);
  EXPECT_DOUBLE_EQ(p.per_type_pair(1, 1), 0.5);
  EXPECT_DOUBLE_EQ(p.per_type_pair(1, 2), 0.3);
  EXPECT_DOUBLE_EQ(p.per_type_pair(2, 2), 0.2);
}

TEST(GlobalProperty, AliasesMapToTheSameKinds)
{
  EXPECT_EQ(GlobalProperty::parse({"Y", "atomtype", "5.e7"}).kind(), Kind::PerType);
  EXPECT_EQ(GlobalProperty::parse({"Y", "vector", "5e7", "1e8"}).kind(), Kind::PerType);
  EXPECT_EQ(GlobalProperty::parse({"e", "atomtypepair", "1", "0.7"}).kind(), Kind::PerTypePair);
  EXPECT_EQ(GlobalProperty::parse({"V", "scalar", "1.0"}).kind(), Kind::Scalar);
  EXPECT_DOUBLE_EQ(GlobalProperty::parse({"Y", "peratomtype", "5.e7", "1e6"}).per_type(2), 1e6);
}

TEST(GlobalProperty, AsymmetricMatrixStyleIsAcceptedAsIn38)
{
  const auto p = GlobalProperty::parse({"mu", "matrix", "2", "0.5", "0.3", "0.1", "0.2"});
  EXPECT_DOUBLE_EQ(p.per_type_pair(1, 2), 0.3);
  EXPECT_DOUBLE_EQ(p.per_type_pair(2, 1), 0.1);
}

TEST(GlobalProperty, Errors)
{
  EXPECT_NE(error_of({"Y", "peratomtype"}).find("not enough arguments"), std::string::npos);
  EXPECT_NE(error_of({"Y", "perspective", "1"}).find("unknown style 'perspective'"), std::string::npos);
  EXPECT_NE(error_of({"Y", "peratomtype", "5e7", "abc"}).find("value 2 'abc' is not a finite number"), std::string::npos);
  EXPECT_NE(error_of({"Y", "peratomtype", "nan"}).find("not a finite number"), std::string::npos);
  EXPECT_NE(error_of({"V", "scalar", "1", "2"}).find("exactly 1 value"), std::string::npos);
  EXPECT_NE(error_of({"e", "peratomtypepair", "0", "0.7"}).find("number of columns as a positive integer"), std::string::npos);
  EXPECT_NE(error_of({"e", "peratomtypepair", "x", "0.7"}).find("got 'x'"), std::string::npos);
  EXPECT_NE(error_of({"e", "peratomtypepair", "2"}).find("has no values"), std::string::npos);
  EXPECT_NE(error_of({"e", "matrix", "2", "0.7", "0.7", "0.7"}).find("multiple of the number of columns"), std::string::npos);
  EXPECT_NE(error_of({"e", "peratomtypepair", "2", "0.7", "0.7"}).find("N*N total values"), std::string::npos);
  EXPECT_NE(error_of({"e", "peratomtypepair", "2", "0.3", "0.2", "0.25", "0.3"}).find("types (1,2) differs from (2,1)"),
            std::string::npos);
}

TEST(GlobalProperty, RequireChecksKindAndLength)
{
  const auto Y = GlobalProperty::parse({"youngsModulus", "peratomtypepair", "1", "5e7"});
  try {
    Y.require(Kind::PerType, 1, "pair_style gran/hooke");
    FAIL() << "kind mismatch not detected";
  } catch (const PropertyError &e) {
    EXPECT_NE(std::string(e.what()).find("peratomtype style required for fix property/global variable youngsModulus for usage with "
                                         "pair_style gran/hooke"),
              std::string::npos);
  }
  const auto nu = GlobalProperty::parse({"poissonsRatio", "peratomtype", "0.3"});
  EXPECT_THROW(nu.require(Kind::PerType, 2, "x"), PropertyError);
  EXPECT_NO_THROW(nu.require(Kind::PerType, 1, "x"));
  const auto e = GlobalProperty::parse({"e", "peratomtypepair", "2", "0.7", "0.5", "0.5", "0.9"});
  EXPECT_NO_THROW(e.require(Kind::PerTypePair, 1, "x"));  // 2.x: extra types are ignored
  EXPECT_THROW(e.require(Kind::PerTypePair, 3, "x"), PropertyError);
}
