#include "insert_keywords.h"

#include "insertion_args.h"
#include "seed_rule.h"

#include <stdexcept>

namespace dembridge::insertion {

namespace {
const char *const kGeneral[] = {"distributiontemplate", "maxattempt", "nparticles", "mass", "massrate",
                                "particlerate", "insert_every", "every", "start", "overlapcheck", "all_in",
                                "random_distribute", "verbose", "vel", "omega", "set_property"};
// accepted by LIGGGHTS 3.8 but not implemented here: refused rather than ignored, with what to use instead
struct Refused {
  const char *key, *instead;
};
const Refused kRefused[] = {
    {"orientation", "it orients multisphere and superquadric particles, which dembridge does not have; spheres need "
                    "none: remove it"},
    {"compress_tags", "renumber the atoms between runs with LAMMPS's 'reset_atoms id'"},
    {"insert_every_time", "give 'insert_every N' in steps (N = time / timestep)"},
    {"interval", "give 'insert_every N' in steps (N = time / timestep)"},
    {"start_time", "give 'start N' in steps (N = time / timestep)"},
    {"t_zero", "give 'start N' in steps (N = time / timestep)"},
    {"stop_time", "unfix the insertion after 'run N' instead"},
    {"t_last", "unfix the insertion after 'run N' instead"},
    {"inclusion_mesh", "give a LAMMPS region (intersect/union) instead of the mesh"},
    {"inside", "give a LAMMPS region (intersect/union) instead of the mesh"},
    {"outside", "give a LAMMPS region (intersect/union) instead of the mesh"}};

void need(const std::vector<std::string> &a, int i, int n, const std::string &what)
{
  if (i + n > static_cast<int>(a.size())) throw std::invalid_argument("'" + a[i] + "' expects " + what);
}
}  // namespace

bool is_general_keyword(const std::string &key)
{
  for (const char *g : kGeneral)
    if (key == g) return true;
  return false;
}

int parse_general_keywords(const std::vector<std::string> &a, InsertKeywords &k)
{
  const int n = static_cast<int>(a.size());
  if (n < 5 || a[3] != "seed") throw std::invalid_argument("expecting keyword 'seed' and a seed after the style");
  k.seed = parse_seed(a[4]);
  int i = 5;
  while (i < n) {
    const std::string &key = a[i];
    for (const Refused &r : kRefused)
      if (key == r.key) throw std::invalid_argument("keyword '" + key + "' is not supported by dembridge: " + r.instead);
    if (key == "distributiontemplate") {
      need(a, i, 2, "a fix ID");
      k.distribution = a[i + 1];
      i += 2;
    } else if (key == "maxattempt") {
      need(a, i, 2, "an integer");
      k.maxattempt = integer_arg(a[i + 1], key);
      if (k.maxattempt < 1) throw std::invalid_argument("'maxattempt' must be >= 1, got " + a[i + 1]);
      i += 2;
    } else if (key == "nparticles" || key == "mass") {
      need(a, i, 2, "a number or INF");
      if (a[i + 1] == "INF") k.n_infinite = true;
      else {
        const double v = number_arg(a[i + 1], key);
        if (v <= 0.) throw std::invalid_argument("'" + key + "' must be > 0, got " + a[i + 1]);
        (key == "mass" ? k.mass : k.nparticles) = v;
      }
      i += 2;
    } else if (key == "massrate" || key == "particlerate") {
      need(a, i, 2, "a number");
      const double v = number_arg(a[i + 1], key);
      if (v <= 0.) throw std::invalid_argument("'" + key + "' must be > 0, got " + a[i + 1]);
      (key == "massrate" ? k.massrate : k.particlerate) = v;
      i += 2;
    } else if (key == "insert_every" || key == "every") {
      need(a, i, 2, "'once' or a number of steps");
      if (a[i + 1] == "once") k.insert_every = 0;
      else {
        k.insert_every = integer_arg(a[i + 1], key);
        if (k.insert_every < 0) throw std::invalid_argument("insert_every must be >= 0, got " + a[i + 1]);
      }
      i += 2;
    } else if (key == "start") {
      need(a, i, 2, "a step");
      k.start = integer_arg(a[i + 1], key);
      i += 2;
    } else if (key == "overlapcheck" || key == "all_in" || key == "verbose") {
      need(a, i, 2, "yes or no");
      const bool v = yes_no_arg(a[i + 1], key);
      (key == "overlapcheck" ? k.overlapcheck : key == "all_in" ? k.all_in : k.verbose) = v;
      i += 2;
    } else if (key == "random_distribute") {
      need(a, i, 2, "exact or uncorrelated");
      if (a[i + 1] == "exact") k.exact_number = true;
      else if (a[i + 1] == "uncorrelated") k.exact_number = false;
      else throw std::invalid_argument("'random_distribute' expects 'exact' or 'uncorrelated', got '" + a[i + 1] + "'");
      i += 2;
    } else if (key == "vel") {
      need(a, i, 5, "constant vx vy vz | uniform vx vy vz dvx dvy dvz | gaussian vx vy vz sx sy sz");
      const std::string &s = a[i + 1];
      if (s == "constant") k.vel.style = VelocityRule::CONSTANT;
      else if (s == "uniform") k.vel.style = VelocityRule::UNIFORM;
      else if (s == "gaussian") k.vel.style = VelocityRule::GAUSSIAN;
      else throw std::invalid_argument("expecting keyword 'constant' or 'uniform' or 'gaussian' after keyword 'vel', got '" + s + "'");
      const int nv = s == "constant" ? 3 : 6;
      need(a, i, 2 + nv, "'" + s + "' and " + std::to_string(nv) + " numbers");
      for (int d = 0; d < 3; ++d) k.vel.v[d] = number_arg(a[i + 2 + d], "vel " + s);
      if (nv == 6)
        for (int d = 0; d < 3; ++d) k.vel.fluct[d] = number_arg(a[i + 5 + d], "vel " + s);
      i += 2 + nv;
    } else if (key == "omega") {
      need(a, i, 5, "constant wx wy wz");
      if (a[i + 1] != "constant")
        throw std::invalid_argument("expecting keyword 'constant' after keyword 'omega', got '" + a[i + 1] + "'");
      for (int d = 0; d < 3; ++d) k.omega[d] = number_arg(a[i + 2 + d], "omega constant");
      i += 5;
    } else if (key == "set_property") {
      need(a, i, 3, "a fix property/atom name and a value");
      k.set_property = a[i + 1];
      k.set_property_value = number_arg(a[i + 2], key);
      i += 3;
    } else {
      break;
    }
  }
  if (k.distribution.empty()) throw std::invalid_argument("have to define a 'distributiontemplate'");
  if (k.nparticles > 0 && k.mass > 0.) throw std::invalid_argument("must not define both 'nparticles' and 'mass'");
  if (k.particlerate > 0. && k.massrate > 0.)
    throw std::invalid_argument("must not define both 'particlerate' and 'massrate'");
  if (k.insert_every == 0 && (k.massrate > 0. || k.particlerate > 0.))
    throw std::invalid_argument("must not define 'particlerate' or 'massrate' for 'insert_every' = once");
  return i;
}

void parse_pack_keywords(const std::vector<std::string> &a, int i, PackKeywords &p)
{
  const int n = static_cast<int>(a.size());
  while (i < n) {
    const std::string &key = a[i];
    if (key == "region") {
      need(a, i, 2, "a region ID");
      p.region = a[i + 1];
    } else if (key == "volumefraction_region") {
      need(a, i, 2, "a number");
      p.volumefraction = number_arg(a[i + 1], key);
      if (p.volumefraction < 0. || p.volumefraction > 1.)
        throw std::invalid_argument("Invalid volumefraction " + a[i + 1] + " (expected 0 < volumefraction_region <= 1)");
    } else if (key == "particles_in_region") {
      need(a, i, 2, "an integer");
      p.ntotal = integer_arg(a[i + 1], key);
      if (p.ntotal <= 0) throw std::invalid_argument("'particles_in_region' > 0 required, got " + a[i + 1]);
    } else if (key == "mass_in_region") {
      need(a, i, 2, "a number");
      p.masstotal = number_arg(a[i + 1], key);
      if (p.masstotal <= 0.) throw std::invalid_argument("'mass_in_region' > 0 required, got " + a[i + 1]);
    } else if (key == "ntry_mc") {
      need(a, i, 2, "an integer");
      p.ntry_mc = integer_arg(a[i + 1], key);
      if (p.ntry_mc < 1000) throw std::invalid_argument("ntry_mc must be > 1000, got " + a[i + 1]);
    } else if (key == "warn_region" || key == "check_dist_from_subdomain_border") {
      need(a, i, 2, "yes or no");
      (key == "warn_region" ? p.warn_region : p.check_border) = yes_no_arg(a[i + 1], key);
    } else if (is_general_keyword(key)) {
      throw std::invalid_argument("unknown keyword '" + key +
                                  "' at this place: LIGGGHTS 3.8 needs the general keywords (" + key +
                                  ", vel, insert_every, ...) before region, volumefraction_region, "
                                  "particles_in_region, mass_in_region and ntry_mc");
    } else {
      throw std::invalid_argument("unknown keyword '" + key + "'");
    }
    i += 2;
  }
}

void parse_stream_keywords(const std::vector<std::string> &a, int i, StreamKeywords &s)
{
  const int n = static_cast<int>(a.size());
  while (i < n) {
    const std::string &key = a[i];
    if (key == "insertion_face") {
      need(a, i, 2, "a fix mesh/surface ID");
      s.face = a[i + 1];
    } else if (key == "extrude_length") {
      need(a, i, 2, "a length");
      s.extrude_length = number_arg(a[i + 1], key);
      if (s.extrude_length <= 0.) throw std::invalid_argument("invalid extrude_length " + a[i + 1] + " (expected > 0)");
    } else if (key == "duration") {
      need(a, i, 2, "a number of steps");
      s.duration = integer_arg(a[i + 1], key);
      if (s.duration < 1) throw std::invalid_argument("'duration' can not be < 1, got " + a[i + 1]);
    } else if (key == "ntry_mc") {
      need(a, i, 2, "an integer");
      s.ntry_mc = integer_arg(a[i + 1], key);
      if (s.ntry_mc < 1000) throw std::invalid_argument("ntry_mc must be > 1000, got " + a[i + 1]);
    } else if (key == "parallel") {
      need(a, i, 2, "yes or no");
      s.parallel = yes_no_arg(a[i + 1], key);
    } else if (is_general_keyword(key)) {
      throw std::invalid_argument("unknown keyword or wrong keyword order: '" + key +
                                  "' at this place: LIGGGHTS 3.8 needs the general keywords (" + key +
                                  ", vel, insert_every, ...) before insertion_face, extrude_length, duration "
                                  "and ntry_mc");
    } else {
      throw std::invalid_argument("unknown keyword '" + key + "'");
    }
    i += 2;
  }
}

}  // namespace dembridge::insertion
