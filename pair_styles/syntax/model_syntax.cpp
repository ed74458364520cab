#include "model_syntax.h"
#include "math/number_word.h"

#include <cstdlib>
#include <map>

namespace dembridge::gran {

namespace {

struct StyleInfo {
  NormalModel normal;
  TangentialModel tangential;
};

// 2.x names (seed 003) and their /simple aliases (spec granular-models §1).
const std::map<std::string, StyleInfo> &legacy_styles()
{
  static const std::map<std::string, StyleInfo> m = {
      {"gran/hooke", {NormalModel::Hooke, TangentialModel::NoHistory}},
      {"gran/hooke/history", {NormalModel::Hooke, TangentialModel::History}},
      {"gran/hertz/history", {NormalModel::Hertz, TangentialModel::History}},
      {"gran/hooke/stiffness", {NormalModel::HookeStiffness, TangentialModel::NoHistory}},
      {"gran/hooke/history/stiffness", {NormalModel::HookeStiffness, TangentialModel::History}},
      {"gran/hertz/history/stiffness", {NormalModel::HertzStiffness, TangentialModel::History}},
      {"gran/hooke/history/simple", {NormalModel::HookeStiffness, TangentialModel::History}},
      {"gran/hertz/history/simple", {NormalModel::HertzStiffness, TangentialModel::History}},
  };
  return m;
}

bool is_number(const std::string &w) { return math::is_number_word(w); }

bool on_off(const std::string &style, const std::string &key, const std::string &value)
{
  if (value == "on" || value == "yes") return true;
  if (value == "off" || value == "no") return false;
  throw SyntaxError("pair_style " + style + ": expecting 'on' or 'off' after keyword '" + key + "', got '" + value + "'");
}

bool is_stiffness(NormalModel n) { return n == NormalModel::HookeStiffness || n == NormalModel::HertzStiffness; }

// Rules shared by every dialect (spec §1.1, fixed quirks of §12.3).
void check_combination(ModelDescription &d)
{
  const std::string p = "pair_style " + d.style + ": ";
  if (d.contact.rolling_needs_history() && d.contact.tangential != TangentialModel::History && d.dialect == Dialect::Liggghts2x)
    throw SyntaxError(p + "rolling_friction epsd/epsd2/epsd3 needs per-contact history; use " +
                      std::string(is_stiffness(d.contact.normal) ? "gran/hooke/history/stiffness" : "gran/hooke/history") +
                      " (2.x silently computed cdt instead)");
  if (d.contact.viscous && is_stiffness(d.contact.normal))
    throw SyntaxError(p + "cannot use 'viscous stokes' with a stiffness model: it modifies the coefficient of restitution, "
                          "which stiffness models do not use");
  if (d.contact.viscous && d.contact.normal == NormalModel::Hertz) {
    if (d.dialect == Dialect::Liggghts3x)
      throw SyntaxError(p + "'viscous' is only available with model hooke");
    d.contact.viscous = false;
    d.warnings.push_back("pair_style " + d.style + ": 'viscous stokes' has no effect with hertz (as in LIGGGHTS 2.x); ignored");
  }
  if (d.contact.absolute_damping && d.contact.normal != NormalModel::HookeStiffness)
    throw SyntaxError(p + "'absolute_damping' is only available with the hooke stiffness styles "
                          "(gran/hooke/history/stiffness, gran/hooke/stiffness, model hooke/stiffness)");
}

ModelDescription parse_legacy(const std::string &style, const std::vector<std::string> &args)
{
  ModelDescription d;
  d.style = style;
  d.dialect = Dialect::Liggghts2x;
  const auto &info = legacy_styles().at(style);
  d.contact.normal = info.normal;
  d.contact.tangential = info.tangential;
  d.contact.tangential_reduce = true;  // 2.x: cohesion always inside the Coulomb/epsd limits
  d.contact.legacy_2x_expressions = true;
  for (std::size_t k = 0; k < args.size(); k += 2) {
    const std::string &key = args[k];
    if (k + 1 >= args.size())
      throw SyntaxError("pair_style " + style + ": keyword '" + key + "' needs a value");
    const std::string &val = args[k + 1];
    if (key == "rolling_friction") {
      if (val == "off") d.contact.rolling = RollingModel::Off;
      else if (val == "cdt") d.contact.rolling = RollingModel::Cdt;
      else if (val == "epsd") d.contact.rolling = RollingModel::Epsd;
      else if (val == "epsd2") d.contact.rolling = RollingModel::Epsd2;
      else if (val == "epsd3") d.contact.rolling = RollingModel::Epsd3;
      else throw SyntaxError("pair_style " + style + ": rolling_friction expects cdt, epsd, epsd2, epsd3 or off, got '" + val + "'");
    } else if (key == "cohesion") {
      if (val == "off") d.contact.cohesion = CohesionModel::Off;
      else if (val == "sjkr") d.contact.cohesion = CohesionModel::Sjkr;
      else if (val == "sjkr2") d.contact.cohesion = CohesionModel::Sjkr2;
      else throw SyntaxError("pair_style " + style + ": cohesion expects sjkr, sjkr2 or off, got '" + val + "'");
    } else if (key == "viscous") {
      if (val == "stokes") d.contact.viscous = true;
      else if (val == "off") d.contact.viscous = false;
      else throw SyntaxError("pair_style " + style + ": viscous expects stokes or off, got '" + val + "'");
    } else if (key == "tangential_damping") {
      d.contact.tangential_damping = on_off(style, key, val);
    } else if (key == "absolute_damping") {
      d.contact.absolute_damping = on_off(style, key, val);
      if (d.contact.normal == NormalModel::HertzStiffness)
        throw SyntaxError("pair_style " + style + ": 'absolute_damping' is not available with hertz stiffness "
                          "(damping is always multiplied by the effective mass; LIGGGHTS 2.x hung here)");
    } else if (key == "sanity_checks") {
      d.sanity_checks = on_off(style, key, val);
    } else if (key == "force") {
      d.force_on = on_off(style, key, val);
    } else {
      throw SyntaxError("pair_style " + style + ": unknown keyword '" + key +
                        "'; expected rolling_friction, cohesion, tangential_damping, viscous, absolute_damping, sanity_checks or force");
    }
  }
  check_combination(d);
  return d;
}

ModelDescription parse_numeric(const std::string &style, const std::vector<std::string> &args)
{
  ModelDescription d;
  d.style = style;
  d.dialect = Dialect::LammpsNumeric;
  d.contact.normal = style == "gran/hertz/history" ? NormalModel::HertzStiffness : NormalModel::HookeStiffness;
  d.contact.tangential = style == "gran/hooke" ? TangentialModel::NoHistory : TangentialModel::History;
  const char *usage = ": expected 'Kn Kt gamma_n gamma_t xmu dampflag [limit_damping]' (Kt, gamma_t may be NULL)";
  if (args.size() != 6 && args.size() != 7) throw SyntaxError("pair_style " + style + usage);
  auto num = [&](std::size_t k, const char *what) {
    double v;
    if (!math::read_number(args[k], v))
      throw SyntaxError("pair_style " + style + ": " + what + " '" + args[k] + "' is not a number" + usage);
    return v;
  };
  auto &c = d.numeric;
  c.kn = num(0, "Kn");
  c.kt = args[1] == "NULL" ? c.kn * 2.0 / 7.0 : num(1, "Kt");
  c.gamman = num(2, "gamma_n");
  c.gammat = args[3] == "NULL" ? 0.5 * c.gamman : num(3, "gamma_t");
  c.xmu = num(4, "xmu");
  if (args[5] != "0" && args[5] != "1") throw SyntaxError("pair_style " + style + ": dampflag must be 0 or 1, got '" + args[5] + "'");
  c.dampflag = args[5] == "1" ? 1 : 0;
  if (args.size() == 7) {
    if (args[6] != "limit_damping") throw SyntaxError("pair_style " + style + ": unknown keyword '" + args[6] + "', expected limit_damping");
    c.limit_damping = true;
  }
  if (c.kn < 0 || c.kt < 0 || c.gamman < 0 || c.gammat < 0 || c.xmu < 0 || c.xmu > 10000)
    throw SyntaxError("pair_style " + style + ": Kn, Kt, gamma_n, gamma_t must be >= 0 and 0 <= xmu <= 10000");
  if (c.dampflag == 0) c.gammat = 0.0;
  d.contact.tangential_damping = c.dampflag == 1;
  d.contact.lammps_formulation = true;
  d.contact.limit_damping = c.limit_damping;
  return d;
}

// A 3.x setting that exists but belongs to another model or sub-model: what it needs (nullptr if no setting).
const char *setting_owner(const std::string &key)
{
  if (key == "viscous") return "model hooke";
  if (key == "absolute_damping") return "model hooke/stiffness";
  if (key == "ktToKnUser") return "model hooke";
  if (key == "tangential_reduce") return "a cohesion model (cohesion sjkr|sjkr2)";
  if (key == "torsionTorque") return "a rolling friction model (rolling_friction cdt|epsd|epsd2|epsd3)";
  return nullptr;
}

// 3.x: gran model M [tangential T] [cohesion C] [rolling_friction R] [surface S] [setting on|off ...]
ModelDescription parse_liggghts3(const std::string &style, const std::vector<std::string> &args)
{
  ModelDescription d;
  d.style = style;
  d.dialect = Dialect::Liggghts3x;
  d.contact.stale_springs_until_rebuild = true;
  d.contact.tangential = TangentialModel::None;  // 3.x: no 'tangential' means no tangential force
  auto unknown = [&](const std::string &w) {
    return SyntaxError("pair_style gran: unknown argument or wrong keyword order: '" + w +
                       "' (expected: model M [tangential T] [cohesion C] [rolling_friction R] [surface S] [settings on|off])");
  };
  std::size_t k = 0;
  if (args.size() < 2 || args[0] != "model") throw SyntaxError("pair_style gran: expected 'model' followed by hooke, hertz, hooke/stiffness or hertz/stiffness");
  const std::string &m = args[1];
  if (m == "hooke") d.contact.normal = NormalModel::Hooke;
  else if (m == "hertz") d.contact.normal = NormalModel::Hertz;
  else if (m == "hooke/stiffness") d.contact.normal = NormalModel::HookeStiffness;
  else if (m == "hertz/stiffness") d.contact.normal = NormalModel::HertzStiffness;
  else throw SyntaxError("pair_style gran: unknown model '" + m + "', expected hooke, hertz, hooke/stiffness or hertz/stiffness");
  k = 2;
  auto value_after = [&](const char *key) -> const std::string & {
    if (k + 1 >= args.size()) throw SyntaxError(std::string("pair_style gran: '") + key + "' needs a value");
    return args[k + 1];
  };
  if (k < args.size() && args[k] == "tangential") {
    const std::string &v = value_after("tangential");
    if (v == "history") d.contact.tangential = TangentialModel::History;
    else if (v == "no_history") d.contact.tangential = TangentialModel::NoHistory;
    else throw SyntaxError("pair_style gran: tangential expects history or no_history, got '" + v + "'");
    k += 2;
  }
  if (k < args.size() && args[k] == "cohesion") {
    const std::string &v = value_after("cohesion");
    if (v == "sjkr") d.contact.cohesion = CohesionModel::Sjkr;
    else if (v == "sjkr2") d.contact.cohesion = CohesionModel::Sjkr2;
    else if (v == "off") d.contact.cohesion = CohesionModel::Off;
    else throw SyntaxError("pair_style gran: cohesion expects sjkr or sjkr2, got '" + v + "'");
    k += 2;
  }
  if (k < args.size() && args[k] == "rolling_friction") {
    const std::string &v = value_after("rolling_friction");
    if (v == "cdt") d.contact.rolling = RollingModel::Cdt;
    else if (v == "epsd") d.contact.rolling = RollingModel::Epsd;
    else if (v == "epsd2") d.contact.rolling = RollingModel::Epsd2;
    else if (v == "epsd3") d.contact.rolling = RollingModel::Epsd3;
    else if (v == "off") d.contact.rolling = RollingModel::Off;
    else throw SyntaxError("pair_style gran: rolling_friction expects cdt, epsd, epsd2 or epsd3, got '" + v + "'");
    k += 2;
  }
  if (k < args.size() && args[k] == "surface") {
    const std::string &v = value_after("surface");
    if (v != "default") throw SyntaxError("pair_style gran: only 'surface default' is available, got '" + v + "'");
    k += 2;
  }
  for (; k < args.size(); k += 2) {
    const std::string &key = args[k];
    bool *flag = nullptr;
    if (key == "tangential_damping") flag = &d.contact.tangential_damping;
    else if (key == "absolute_damping" && d.contact.normal == NormalModel::HookeStiffness) flag = &d.contact.absolute_damping;
    else if (key == "viscous" && d.contact.normal == NormalModel::Hooke) flag = &d.contact.viscous;
    else if (key == "limitForce") flag = &d.contact.limit_force;
    else if (key == "tangential_reduce" && d.contact.cohesion != CohesionModel::Off) flag = &d.contact.tangential_reduce;
    else if (key == "torsionTorque" && d.contact.rolling != RollingModel::Off) flag = &d.contact.torsion_torque;
    else if (key == "ktToKnUser" && d.contact.normal == NormalModel::Hooke) flag = &d.contact.kt_to_kn_user;
    else if (const char *owner = setting_owner(key))
      throw SyntaxError("pair_style gran: model " + m + " has no " + (key == "viscous" ? "viscous model" : "'" + key + "' setting") +
                        " ('" + key + "' is a setting of " + owner + ")");
    else throw unknown(key);
    if (k + 1 >= args.size()) throw SyntaxError("pair_style gran: '" + key + "' needs on or off");
    const std::string &v = args[k + 1];
    if (v != "on" && v != "off")
      throw SyntaxError("pair_style gran: while parsing '" + key + "' argument: unknown option or wrong keyword order: '" + v +
                        "' (expected on or off)");
    *flag = v == "on";
  }
  check_combination(d);
  return d;
}

}  // namespace

bool is_gran_style(const std::string &style) { return style == "gran" || legacy_styles().count(style) > 0; }

ModelDescription parse_pair_style(const std::string &style, const std::vector<std::string> &args)
{
  if (style == "gran") return parse_liggghts3(style, args);
  if (!legacy_styles().count(style)) throw SyntaxError("pair_style " + style + ": not a dembridge granular style");
  const bool numeric_capable = style == "gran/hooke" || style == "gran/hooke/history" || style == "gran/hertz/history";
  if (numeric_capable && !args.empty() && is_number(args[0])) return parse_numeric(style, args);
  return parse_legacy(style, args);
}

}  // namespace dembridge::gran
