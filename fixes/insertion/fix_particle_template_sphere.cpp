#include "fix_particle_template_sphere.h"

#include "atom.h"
#include "error.h"
#include "modify.h"
#include "style_registry.h"

#include "insertion_args.h"
#include "seed_rule.h"

#include <cstring>
#include <stdexcept>

using namespace LAMMPS_NS;

namespace dembridge {

FixParticleTemplateSphere::FixParticleTemplateSphere(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  const std::string prefix = std::string("Fix particletemplate/sphere (id ") + id + "): ";
  bool have_radius = false, have_density = false;
  try {
    if (narg < 4) throw std::invalid_argument("expects a seed, then atom_type, density and radius");
    seed_ = insertion::parse_seed(arg[3]);
    for (int i = 4; i < narg;) {
      const std::string key = arg[i];
      if (key == "atom_type") {
        if (i + 2 > narg) throw std::invalid_argument("'atom_type' expects a type");
        sphere_.type = insertion::integer_arg(arg[i + 1], key);
        if (sphere_.type < 1) throw std::invalid_argument("invalid atom type (must be >=1)");
        i += 2;
      } else if (key == "radius" || key == "density") {
        if (i + 3 > narg) throw std::invalid_argument("'" + key + "' expects 'constant' and a value");
        if (std::strcmp(arg[i + 1], "constant") != 0)
          throw std::invalid_argument("invalid " + key + " random style '" + arg[i + 1] +
                                      "': LIGGGHTS 3.8 accepts only 'constant' (a size distribution is several "
                                      "templates in one fix particledistribution/discrete)");
        const double v = insertion::number_arg(arg[i + 2], key);
        if (v <= 0.) throw std::invalid_argument(key + " must be > 0, got " + arg[i + 2]);
        (key == "radius" ? sphere_.radius : sphere_.density) = v;
        (key == "radius" ? have_radius : have_density) = true;
        i += 3;
      } else {
        throw std::invalid_argument("unrecognized keyword '" + key + "' (expected atom_type, density or radius)");
      }
    }
    if (!have_density) throw std::invalid_argument("have to define 'density'");
    if (!have_radius) throw std::invalid_argument("have to define 'radius'");
  } catch (const std::invalid_argument &e) {
    error->all(FLERR, prefix + e.what());
  }
}

void FixParticleTemplateSphere::init()
{
  if (sphere_.type > atom->ntypes)
    error->all(FLERR, "Fix particletemplate/sphere (id {}): atom_type {} is larger than the number of atom types ({})",
               id, sphere_.type, atom->ntypes);
}

FixParticleTemplateSphere *FixParticleTemplateSphere::find(LAMMPS *lmp, const std::string &id)
{
  Fix *f = lmp->modify->get_fix_by_id(id);
  if (!f || std::strcmp(f->style, "particletemplate/sphere") != 0) return nullptr;
  return static_cast<FixParticleTemplateSphere *>(f);
}

static RegisterStyle reg_fix_particletemplate_sphere("fix", "particletemplate/sphere",
                                                     "LIGGGHTS particle template (constant radius and density)",
                                                     create_fix<FixParticleTemplateSphere>);

}  // namespace dembridge
