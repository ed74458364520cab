#include "material_table.h"

#include "vec3.h"

#include <cmath>
#include <cstring>

namespace dembridge::gran {

using property::GlobalProperty;
using property::Kind;

namespace {

std::string fmt(double v)
{
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// Reads properties for one model and records which were used.
class Reader {
 public:
  Reader(const PropertyLookup &lookup, int max_type, std::string caller, std::vector<std::string> &used)
      : lookup_(lookup), max_type_(max_type), caller_(std::move(caller)), used_(used) {}

  const GlobalProperty &get(const std::string &name, Kind kind)
  {
    const GlobalProperty *p = lookup_(name);
    if (!p) throw MaterialError(property::missing_property_message(name, caller_));
    try {
      p->require(kind, max_type_, caller_);
    } catch (const property::PropertyError &e) {
      throw MaterialError(e.what());
    }
    used_.push_back(name);
    return *p;
  }

 private:
  const PropertyLookup &lookup_;
  int max_type_;
  std::string caller_;
  std::vector<std::string> &used_;
};

bool uses_material(NormalModel n) { return n == NormalModel::Hooke || n == NormalModel::Hertz; }

}  // namespace

MaterialTable MaterialTable::build(const ModelDescription &model, const PropertyLookup &lookup, int max_type, UnitSystem units,
                                   double nktv2p)
{
  MaterialTable t;
  t.max_type_ = max_type;
  t.table_.assign((max_type + 1) * (max_type + 1), PairCoeffs{});
  const ContactConfig &cfg = model.contact;
  const std::string caller = "pair_style " + model.caller();
  Reader rd(lookup, max_type, caller, t.used_);
  const bool checks = model.sanity_checks;
  auto check = [&](bool ok, const std::string &msg) {
    if (checks && !ok) throw MaterialError(caller + ": " + msg + " (use 'sanity_checks off' to override)");
  };

  if (model.dialect == Dialect::LammpsNumeric) {
    for (int i = 1; i <= max_type; ++i)
      for (int j = 1; j <= max_type; ++j) {
        PairCoeffs &c = t.table_[i * (max_type + 1) + j];
        c.kn = model.numeric.kn / nktv2p;
        c.kt = model.numeric.kt / nktv2p;
        c.gamman = model.numeric.gamman;
        c.gammat = model.numeric.gammat;
        c.mu = model.numeric.xmu;
      }
    return t;
  }

  if (uses_material(cfg.normal)) {
    const auto &Y = rd.get("youngsModulus", Kind::PerType);
    const auto &nu = rd.get("poissonsRatio", Kind::PerType);
    for (int i = 1; i <= max_type; ++i) {
      const double y = Y.per_type(i), v = nu.per_type(i);
      if (units == UnitSystem::SI) check(y >= 5e6, "youngsModulus >= 5e6 required for SI units (type " + std::to_string(i) + " has " + fmt(y) + ")");
      if (units == UnitSystem::CGS) check(y >= 5e5, "youngsModulus >= 5e5 required for CGS units (type " + std::to_string(i) + " has " + fmt(y) + ")");
      if (!(y > 0)) throw MaterialError(caller + ": youngsModulus must be > 0 (type " + std::to_string(i) + " has " + fmt(y) + ")");
      check(v >= 0 && v <= 0.5, "0 <= poissonsRatio <= 0.5 required (type " + std::to_string(i) + " has " + fmt(v) + ")");
    }
    const bool need_e = !(cfg.normal == NormalModel::Hooke && cfg.viscous);  // viscous replaces e (3.8 rule)
    const GlobalProperty *e = need_e ? &rd.get("coefficientRestitution", Kind::PerTypePair) : nullptr;
    double V = 0;
    if (cfg.normal == NormalModel::Hooke) {
      V = rd.get("characteristicVelocity", Kind::Scalar).scalar();
      if (units == UnitSystem::SI) check(V >= 1e-2, "characteristicVelocity >= 1e-2 required for SI units (got " + fmt(V) + ")");
      if (!(V > 0)) throw MaterialError(caller + ": characteristicVelocity must be > 0 (got " + fmt(V) + ")");
    }
    for (int i = 1; i <= max_type; ++i)
      for (int j = 1; j <= max_type; ++j) {
        PairCoeffs &c = t.table_[i * (max_type + 1) + j];
        const double yi = Y.per_type(i), yj = Y.per_type(j), vi = nu.per_type(i), vj = nu.per_type(j);
        c.Yeff = 1. / ((1. - vi * vi) / yi + (1. - vj * vj) / yj);
        c.Geff = 1. / (2. * (2. - vi) * (1. + vi) / yi + 2. * (2. - vj) * (1. + vj) / yj);
        if (e) {
          const double eij = e->per_type_pair(i, j);
          check(eij > 0.05 && eij <= 1.0, "0.05 < coefficientRestitution <= 1 required (types " + std::to_string(i) + "," +
                                              std::to_string(j) + " have " + fmt(eij) + ")");
          if (!(eij > 0)) throw MaterialError(caller + ": coefficientRestitution must be > 0");
          c.lnE = std::log(eij);
          c.beta = c.lnE / std::sqrt(c.lnE * c.lnE + kPi * kPi);
        }
        c.char_vel = V;
      }
  } else {
    // stiffness models (§5.3, §5.4): no material ranges apply
    const auto &kn = rd.get("kn", Kind::PerTypePair);
    const auto &kt = rd.get("kt", Kind::PerTypePair);
    const bool abs = cfg.absolute_damping;
    const auto &gn = rd.get(abs ? "gamman_abs" : "gamman", Kind::PerTypePair);
    const auto &gt = rd.get(abs ? "gammat_abs" : "gammat", Kind::PerTypePair);
    for (int i = 1; i <= max_type; ++i)
      for (int j = 1; j <= max_type; ++j) {
        PairCoeffs &c = t.table_[i * (max_type + 1) + j];
        c.kn = kn.per_type_pair(i, j);
        c.kt = kt.per_type_pair(i, j);
        c.gamman = gn.per_type_pair(i, j);
        c.gammat = gt.per_type_pair(i, j);
      }
  }

  // rolling friction (spec §8)
  if (cfg.rolling != RollingModel::Off) {
    const auto &mur = rd.get("coefficientRollingFriction", Kind::PerTypePair);
    const bool dashpot = cfg.rolling == RollingModel::Epsd || cfg.rolling == RollingModel::Epsd3;
    const GlobalProperty *eta = dashpot ? &rd.get("coefficientRollingViscousDamping", Kind::PerTypePair) : nullptr;
    double kr = 0;
    if (cfg.rolling == RollingModel::Epsd3) {
      kr = rd.get("rollingStiffness", Kind::Scalar).scalar();
      if (units == UnitSystem::SI) check(kr >= 1.0, "rollingStiffness >= 1 required for SI units (got " + fmt(kr) + ")");
    }
    for (int i = 1; i <= max_type; ++i)
      for (int j = 1; j <= max_type; ++j) {
        PairCoeffs &c = t.table_[i * (max_type + 1) + j];
        c.mu_roll = mur.per_type_pair(i, j);
        if (c.mu_roll < 0) throw MaterialError(caller + ": coefficientRollingFriction must be >= 0");
        c.eta_roll = eta ? eta->per_type_pair(i, j) : 0.0;
        c.roll_stiffness = kr;
      }
  }
  // cohesion (spec §6)
  if (cfg.cohesion != CohesionModel::Off) {
    const auto &k = rd.get("cohesionEnergyDensity", Kind::PerTypePair);
    for (int i = 1; i <= max_type; ++i)
      for (int j = 1; j <= max_type; ++j) t.table_[i * (max_type + 1) + j].cohesion_energy_density = k.per_type_pair(i, j);
  }
  // viscous Stokes damping of the hooke model (spec §5.5)
  if (cfg.viscous) {
    const auto &mu = rd.get("FluidViscosity", Kind::PerTypePair);
    const auto &emax = rd.get("MaximumRestitution", Kind::PerTypePair);
    const auto &stc = rd.get("CriticalStokes", Kind::PerTypePair);
    for (int i = 1; i <= max_type; ++i)
      for (int j = 1; j <= max_type; ++j) {
        PairCoeffs &c = t.table_[i * (max_type + 1) + j];
        const std::string tp = " (types " + std::to_string(i) + "," + std::to_string(j) + ")";
        const double m = mu.per_type_pair(i, j), e = emax.per_type_pair(i, j), s = stc.per_type_pair(i, j);
        if (!(e > 0 && e <= 1)) throw MaterialError(caller + ": 0 < MaximumRestitution <= 1 required" + tp);
        if (!(m > 0)) throw MaterialError(caller + ": FluidViscosity > 0 required" + tp);
        if (!(s > 0)) throw MaterialError(caller + ": CriticalStokes > 0 required" + tp);
        c.fluid_viscosity = m;
        c.ln_max_restitution = std::log(e);
        c.critical_stokes = s;
      }
  }

  if (cfg.tangential != TangentialModel::None) {
    const auto &mu = rd.get("coefficientFriction", Kind::PerTypePair);
    for (int i = 1; i <= max_type; ++i)
      for (int j = 1; j <= max_type; ++j) {
        const double m = mu.per_type_pair(i, j);
        if (m < 0) throw MaterialError(caller + ": coefficientFriction must be >= 0 (types " + std::to_string(i) + "," + std::to_string(j) + ")");
        t.table_[i * (max_type + 1) + j].mu = m;
      }
  }
  return t;
}

bool MaterialTable::uniform() const
{
  if (max_type_ < 1) return false;
  for (int i = 1; i <= max_type_; ++i)
    for (int j = 1; j <= max_type_; ++j)
      if (std::memcmp(&at(i, j), &at(1, 1), sizeof(PairCoeffs)) != 0) return false;
  return true;
}

}  // namespace dembridge::gran
