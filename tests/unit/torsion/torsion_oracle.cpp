#include "torsion_oracle.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

namespace dt = dembridge::torsion;
namespace dsp = dembridge::springs;

double TorsionDeviations::worst() const { return std::max({angle.relative(), omega.relative(), torque.relative()}); }

void TorsionDeviations::print(const std::string& name) const {
  angle.print(name + " ROLL/PITCH/YAW");
  omega.print(name + " OX/OY/OZ");
  torque.print(name + " TRQTOT/TRQSPR/T");
}

namespace {

bool has_key(const std::string& json, const std::string& key) {
  try {
    return !oracle::meta_numbers(json, key).empty();
  } catch (const std::exception&) {
    return false;
  }
}

dt::Vec3 vec(const std::vector<double>& v) { return {v.at(0), v.at(1), v.at(2)}; }

// kroll/kpitch/kyaw and droll/dpitch/dyaw (table or ratio) from the meta keys that exist.
void set_axes(TorsionCase& c, const std::string& json) {
  const char* names[3] = {"roll", "pitch", "yaw"};
  for (int a = 0; a < 3; ++a) {
    const std::string k = std::string("k") + names[a], d = std::string("d") + names[a];
    if (has_key(json, k)) {
      c.spring.law.axis[a].spring = c.keep(dsp::SpringTable::from_pairs(oracle::meta_numbers(json, k), k.c_str()));
    }
    if (has_key(json, d)) {
      const auto v = oracle::meta_numbers(json, d);
      if (v.size() == 1) {
        c.spring.law.axis[a].ratio = v[0];
      } else {
        c.spring.law.axis[a].damper = c.keep(dsp::SpringTable::from_pairs(v, d.c_str()));
      }
    }
  }
}

}  // namespace

TorsionCase torsion_spring_one_case(const std::string& root, int number, std::string& file) {
  char meta_name[64];
  std::snprintf(meta_name, sizeof meta_name, "/meta_case%02d.json", number);
  const std::string json = root + meta_name;
  TorsionCase c;
  c.h = oracle::meta_number(json, "step");
  c.inertia = 1000.0 / 6.0;  // unit cube of density 1e3 (oracle README)
  const auto w0 = oracle::meta_numbers(json, "initial_angular_velocity");
  c.omega0 = replay::V3(w0.at(0), w0.at(1), w0.at(2));
  c.spring.reference = dt::reference_frame(vec(oracle::meta_numbers(json, "zdir")), vec(oracle::meta_numbers(json, "xdir")));
  set_axes(c, json);
  // file name: caseNN_<ending>.csv where <ending> is the only key of "cases"
  const std::string text = [&] {
    std::string s;
    std::FILE* f = std::fopen(json.c_str(), "r");
    if (!f) throw std::runtime_error("missing " + json);
    char buf[4096];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) s.append(buf, n);
    std::fclose(f);
    return s;
  }();
  const std::size_t p = text.find('"', text.find('{', text.find("\"cases\"") + 7)) + 1;
  char prefix[16];
  std::snprintf(prefix, sizeof prefix, "/case%02d_", number);
  file = root + prefix + text.substr(p, text.find('"', p) - p) + ".csv";
  c.spring.law.validate();
  return c;
}

TorsionCase analytic_torsion_case(const std::string& root, const std::string& name, std::string& file) {
  const std::string json = root + "/meta.json";
  TorsionCase c;
  c.h = oracle::meta_number(json, "step");
  c.inertia = oracle::meta_number(json, "I");
  const double k = oracle::meta_number(json, "k");
  c.spring.reference = dt::reference_frame({0.0, 0.0, 1.0}, {1.0, 0.0, 0.0});
  const dsp::SpringTable* K = c.keep(dsp::SpringTable::from_pairs({-1.0, k, 1.0, -k}));
  for (int a = 0; a < 3; ++a) c.spring.law.axis[a].spring = K;
  if (name == "yaw_undamped" || name == "yaw_ratio0.1") c.omega0 = replay::V3(0.0, 0.0, 1.0);
  if (name == "yaw_ratio0.1") c.spring.law.axis[dt::kYaw].ratio = oracle::meta_number(json, "dyaw");
  if (name == "roll_table") {
    c.omega0 = replay::V3(1.0, 0.0, 0.0);
    c.spring.law.axis[dt::kRoll].damper = c.keep(dsp::SpringTable::from_pairs(oracle::meta_numbers(json, "droll")));
  }
  if (name == "cone_roll_pitch") {
    c.omega0 = replay::V3(0.6, 0.8, 0.0);
    c.spring.law.cone = dt::parse_cone({"roll", "pitch"});
  }
  // the initial spin is also in row 0 of the history; meta lists it per case
  file = root + "/case_" + name + ".csv";
  c.spring.law.validate();
  return c;
}

TorsionDeviations replay_case(const TorsionCase& c, const oracle::History& h, bool q1, bool q3, bool parmec_axis_inertia) {
  replay::Body b;
  b.J = c.inertia * replay::Mat3::Identity();
  b.W = c.omega0;
  replay::Torsion s = c.spring;  // law points into c's tables (shared, alive while c is)
  s.state = dt::TorsionState{};
  replay::RigidReplay model({b}, {s}, c.h, q1, q3);
  model.use_parmec_axis_inertia(parmec_axis_inertia);
  TorsionDeviations dev;
  const char* ang[3] = {"trq0_ROLL", "trq0_PITCH", "trq0_YAW"};
  const char* tot[3] = {"trq0_TRQTOT_R", "trq0_TRQTOT_P", "trq0_TRQTOT_Y"};
  const char* spr[3] = {"trq0_TRQSPR_R", "trq0_TRQSPR_P", "trq0_TRQSPR_Y"};
  const char* om[3] = {"OX", "OY", "OZ"};
  const char* tq[3] = {"TX", "TY", "TZ"};
  model.step();  // step 0 is never sampled (spec §1.3)
  for (std::size_t i = 1; i < h.rows(); ++i) {
    if (std::fabs(h["TIME"][i] - static_cast<double>(i) * c.h) > 1e-9 * c.h * static_cast<double>(i))
      throw std::runtime_error("oracle rows are not one per step");
    model.step();
    const auto& sp = model.springs()[0];
    const auto& bd = model.bodies()[0];
    for (int a = 0; a < 3; ++a) {
      const long r = static_cast<long>(i);
      dev.angle.add(sp.state.angle[a], h[ang[a]][i], r);
      dev.omega.add(bd.w(a), h[om[a]][i], r);
      dev.torque.add(sp.state.torque_total[a], h[tot[a]][i], r);
      dev.torque.add(sp.state.torque_spring[a], h[spr[a]][i], r);
      dev.torque.add(bd.t(a), h[tq[a]][i], r);
    }
  }
  return dev;
}
