// Material tables and contact sub-models against the worked numbers of spec granular-models §4
// (Y=5e7, ν=0.3, e=0.7, V=1, R_i=R_j=5 mm, ρ=2500) and closed-form limits.
#include "contact_law.h"
#include "material_table.h"

#include <gtest/gtest.h>

#include <map>

using namespace dembridge;
using namespace dembridge::gran;
using property::GlobalProperty;

namespace {

struct Props {
  std::map<std::string, GlobalProperty> by_name;
  void add(const std::vector<std::string> &args) { by_name[args[0]] = GlobalProperty::parse(args); }
  PropertyLookup lookup() const
  {
    return [this](const std::string &n) -> const GlobalProperty * {
      auto it = by_name.find(n);
      return it == by_name.end() ? nullptr : &it->second;
    };
  }
};

Props default_material()
{
  Props p;
  p.add({"youngsModulus", "peratomtype", "5.e7"});
  p.add({"poissonsRatio", "peratomtype", "0.3"});
  p.add({"coefficientRestitution", "peratomtypepair", "1", "0.7"});
  p.add({"coefficientFriction", "peratomtypepair", "1", "0.3"});
  p.add({"characteristicVelocity", "scalar", "1.0"});
  return p;
}

constexpr double kMass = 1.308996938995747e-3;  // 4/3 π (5 mm)³ 2500
constexpr double kMeff = 6.544984694978735e-4;

}  // namespace

TEST(MaterialTable, EffectiveModuliAndBetaMatchSpecWorkedNumbers)
{
  const auto p = default_material();
  const auto t = MaterialTable::build(parse_pair_style("gran/hooke", {}), p.lookup(), 1, UnitSystem::SI);
  EXPECT_NEAR(t.at(1, 1).Yeff, 2.747252747252747e7, 1e-15 * 2.7e7);
  EXPECT_NEAR(t.at(1, 1).Geff, 5.656108597285068e6, 1e-15 * 5.7e6);
  EXPECT_NEAR(t.at(1, 1).beta, -0.11280845069358131, 1e-16);
  EXPECT_DOUBLE_EQ(t.at(1, 1).mu, 0.3);
}

TEST(NormalModels, HookeCoefficientsMatchSpecWorkedNumbers)
{
  const auto p = default_material();
  const auto model = parse_pair_style("gran/hooke", {});
  const auto t = MaterialTable::build(model, p.lookup(), 1, UnitSystem::SI);
  ContactGeometry g{};
  g.reff = 2.5e-3;
  g.delta = 1e-5;
  const auto c = normal_coefficients(model.contact, t.at(1, 1), g, kMeff);
  EXPECT_NEAR(c.kn, 19765.126693457853, 1e-11 * 19765.0);
  EXPECT_NEAR(c.kt, 19765.126693457853, 1e-11 * 19765.0);
  EXPECT_NEAR(c.gamman, 0.8114761298240408, 1e-14);
  EXPECT_NEAR(c.gammat, 0.8114761298240408, 1e-14);
  auto off = model.contact;
  off.tangential_damping = false;
  EXPECT_EQ(normal_coefficients(off, t.at(1, 1), g, kMeff).gammat, 0.0);
}

TEST(NormalModels, HertzCoefficientsMatchSpecWorkedNumbers)
{
  const auto p = default_material();
  const auto model = parse_pair_style("gran/hertz/history", {});
  const auto t = MaterialTable::build(model, p.lookup(), 1, UnitSystem::SI);
  ContactGeometry g{};
  g.reff = 2.5e-3;
  g.delta = 1e-5;
  const auto c = normal_coefficients(model.contact, t.at(1, 1), g, kMeff);
  EXPECT_NEAR(c.kn, 5791.717326315712, 1e-12 * 5791.0);
  EXPECT_NEAR(c.kt, 7154.474344272351, 1e-12 * 7154.0);
  EXPECT_NEAR(c.gamman, 0.4911166219344317, 1e-15);
  EXPECT_NEAR(c.gammat, 0.4456810722507629, 1e-15);
}

TEST(MaterialTable, RangeChecksNameTheProperty)
{
  auto p = default_material();
  p.add({"coefficientRestitution", "peratomtypepair", "1", "0.05"});
  try {
    MaterialTable::build(parse_pair_style("gran/hooke", {}), p.lookup(), 1, UnitSystem::SI);
    FAIL();
  } catch (const MaterialError &e) {
    EXPECT_NE(std::string(e.what()).find("0.05 < coefficientRestitution <= 1 required"), std::string::npos);
  }
  // sanity_checks off lets it through
  EXPECT_NO_THROW(MaterialTable::build(parse_pair_style("gran/hooke", {"sanity_checks", "off"}), p.lookup(), 1, UnitSystem::SI));
  auto q = default_material();
  q.by_name.erase("characteristicVelocity");
  try {
    MaterialTable::build(parse_pair_style("gran/hooke", {}), q.lookup(), 1, UnitSystem::SI);
    FAIL();
  } catch (const MaterialError &e) {
    EXPECT_NE(std::string(e.what()).find("Could not locate a fix/property storing value(s) for characteristicVelocity as requested by "
                                         "pair_style gran/hooke"),
              std::string::npos);
  }
}

TEST(ContactLaw, NoHistoryTangentialIsCappedByCoulomb)
{
  const auto p = default_material();
  const auto model = parse_pair_style("gran/hooke", {});
  const auto t = MaterialTable::build(model, p.lookup(), 1, UnitSystem::SI);
  ContactLaw law(model.contact);
  // two 5 mm spheres overlapping by 1e-5 along x, sliding fast along y: force must be μ|Fn|
  const double xi[3] = {-0.005 + 0.5e-5, 0, 0}, xj[3] = {0.005 - 0.5e-5, 0, 0};
  const double vi[3] = {0, 5.0, 0}, vj[3] = {0, 0, 0}, w0[3] = {0, 0, 0};
  ContactResult r;
  // gran/hooke keeps no history; a real (unused) buffer rather than nullptr, because GCC's
  // -Warray-bounds in the -O1 sanitizer build flags the history model's branch it cannot rule out
  double no_history[3] = {0, 0, 0};
  ASSERT_TRUE(law.evaluate({xi, vi, w0, 0.005}, {xj, vj, w0, 0.005}, kMeff, t.at(1, 1), no_history, true, 1e-6, r));
  EXPECT_NEAR(r.delta, 1e-5, 1e-18);
  EXPECT_NEAR(r.Fn, 19765.126693457853 * 1e-5, 1e-12);  // vn = 0: spring only
  EXPECT_NEAR(std::hypot(r.Ft[1], r.Ft[2]), 0.3 * r.Fn, 1e-15);
  EXPECT_LT(r.Ft[1], 0.0);  // opposes the sliding of i
  // slow sliding: viscous, γt vrel, below the cap
  const double vslow[3] = {0, 1e-4, 0};
  ASSERT_TRUE(law.evaluate({xi, vslow, w0, 0.005}, {xj, vj, w0, 0.005}, kMeff, t.at(1, 1), no_history, true, 1e-6, r));
  EXPECT_NEAR(r.Ft[1], -0.8114761298240408 * 1e-4, 1e-16);
  // lever arm is R - δ/2, not R
  EXPECT_NEAR(r.Ti[2], (0.005 - 0.5e-5) * r.Ft[1], 1e-18);  // contact point (R_i - δ/2) x̂ from i, crossed with Ft
  // apart: no contact
  const double far[3] = {0.02, 0, 0};
  EXPECT_FALSE(law.evaluate({xi, vi, w0, 0.005}, {far, vj, w0, 0.005}, kMeff, t.at(1, 1), no_history, true, 1e-6, r));
}
