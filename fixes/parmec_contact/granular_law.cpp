#include "granular_law.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace dembridge::parmec_contact {

namespace {

void require(bool ok, const char *name, const char *rule, double got)
{
  if (!ok) throw std::invalid_argument(std::string(name) + " must be " + rule + ", got " + std::to_string(got));
}

}  // namespace

void Pairing::validate() const
{
  require(std::isfinite(spring) && spring >= 0.0, "spring", ">= 0", spring);
  require(std::isfinite(damper) && damper >= 0.0, "damper", ">= 0 (a ratio of critical damping)", damper);
  require(std::isfinite(mu_static) && mu_static >= 0.0, "friction (static)", ">= 0", mu_static);
  require(std::isfinite(mu_dynamic) && mu_dynamic >= 0.0, "friction (dynamic)", ">= 0", mu_dynamic);
  require(std::isfinite(kskn) && kskn >= 0.0, "kskn", ">= 0", kskn);
}

void PairingTable::set(int color1, int color2, const Pairing &p)
{
  if (color1 < 0 || color2 < 0)
    throw std::invalid_argument("colours must be >= 0, got (" + std::to_string(color1) + ", " + std::to_string(color2) + ")");
  if ((color1 == 0) != (color2 == 0))
    throw std::invalid_argument("colour 0 only as (0, 0), the default of unspecified pairings; got (" +
                                std::to_string(color1) + ", " + std::to_string(color2) + ")");
  p.validate();
  if (color1 == 0) {
    default_ = p;
    return;
  }
  if (color1 > color2) std::swap(color1, color2);
  pairs_[{color1, color2}] = p;  // a later GRANULAR of the same pair replaces the earlier one
}

const Pairing &PairingTable::find(int color1, int color2) const
{
  if (color1 > color2) std::swap(color1, color2);
  const auto it = pairs_.find({color1, color2});
  return it == pairs_.end() ? default_ : it->second;
}

bool PairingTable::any_contact() const
{
  if (default_.touches()) return true;
  for (const auto &kv : pairs_)
    if (kv.second.touches()) return true;
  return false;
}

ContactOutput granular_force(const Pairing &p, const ContactInput &c, Vec3 &state, bool update)
{
  ContactOutput out{};
  out.kn = p.spring;
  out.en = p.damper * 2.0 * std::sqrt(p.spring * c.meff);
  const double vn = mesh::dot(c.vij, c.n);
  out.fn = out.kn * c.depth + out.en * vn;

  const double kt = out.kn * p.kskn, et = out.en * p.kskn;
  Vec3 vt, s = state, ft;
  for (int k = 0; k < 3; ++k) vt[k] = c.vij[k] - vn * c.n[k];
  if (update)  // a trial/setup pass repeats the last committed spring (a run split in two equals one run)
    for (int k = 0; k < 3; ++k) s[k] += c.h * vt[k];
  for (int k = 0; k < 3; ++k) ft[k] = kt * s[k] + et * vt[k];
  const double len = mesh::norm(ft);
  // Coulomb: scaled to the dynamic limit, the spring s kept. len > 0 guards Parmec's 0/0 when a separating
  // contact's damping makes F_n < 0 with no tangential force.
  if (len > p.mu_static * out.fn && len > 0.0) {
    const double scale = p.mu_dynamic * out.fn / len;
    for (int k = 0; k < 3; ++k) ft[k] *= scale;
  }
  for (int k = 0; k < 3; ++k) out.f[k] = out.fn * c.n[k] + ft[k];
  if (update) state = s;
  return out;
}

double restitution_of_damper(double zeta)
{
  if (zeta >= 1.0) return 0.0;
  return std::exp(-M_PI * zeta / std::sqrt(1.0 - zeta * zeta));
}

}  // namespace dembridge::parmec_contact
