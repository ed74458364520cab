// fix parmec/spring: the API for UNSPRING (fixes/torsion glue; doc/fix_parmec_spring.md "API for UNSPRING").
#include "fix_parmec_spring.h"
#include "rank_error.h"
#include "fix_parmec_spring_slot.h"

#include "atom.h"
#include "error.h"

#include <cmath>

using namespace LAMMPS_NS;
namespace sp = dembridge::springs;

namespace dembridge {

using namespace spring_fix;

int FixParmecSpring::spring_index(long spring_id) const
{
  auto it = id_index_.find(spring_id);
  return it == id_index_.end() ? -1 : it->second;
}

// The slot of a spring whose state this rank owns, or null. The (spring -> atom, record) index is rebuilt
// only after records moved (exchange, sort, restart), so lookups are O(1) otherwise.
const double *FixParmecSpring::owned_slot(int spring) const
{
  sync_records();
  const auto w = where_.find(records_, atom->nlocal, static_cast<int>(defs_.size()), spring);
  return w.first >= 0 ? records_.record(w.first, w.second) : nullptr;
}

namespace {
double state_entity(const sp::SpringState &st, FixParmecSpring::Entity e)
{
  switch (e) {
    case FixParmecSpring::Entity::Length: return st.length;
    case FixParmecSpring::Entity::Stroke: return st.stroke;
    case FixParmecSpring::Entity::F: return st.force_total;
    case FixParmecSpring::Entity::SF: return st.force_elastic;
    case FixParmecSpring::Entity::FF: return st.friction_force;
    case FixParmecSpring::Entity::SS: return st.code;
    default: return NAN;
  }
}
}  // namespace

double FixParmecSpring::entity_value(int spring, Entity e) const
{
  if (e == Entity::EQM) {  // from the output rows of the last evaluation
    if (spring < 0 || spring >= static_cast<int>(defs_.size())) return NAN;
    for (int r = 0; r < size_local_rows; r++)
      if (array_local[r][0] == static_cast<double>(defs_[spring].id)) return array_local[r][7];
    return NAN;
  }
  const double *slot = owned_slot(spring);
  if (!slot) return NAN;
  sp::SpringState st;
  st.unpack(slot + 1);
  return state_entity(st, e);
}

void FixParmecSpring::gather_entity(Entity e, std::vector<double> &out)
{
  sync_records();
  std::vector<double> mine(defs_.size(), 0.0);
  if (e == Entity::EQM) {
    for (int r = 0; r < size_local_rows; r++) {
      auto it = id_index_.find(std::lround(array_local[r][0]));
      if (it != id_index_.end()) mine[it->second] = array_local[r][7];
    }
  } else {
    sp::SpringState st;
    for (int i = 0; i < atom->nlocal; i++)
      for (int s = 0; s < records_.count(i); s++) {
        st.unpack(records_.record(i, s) + 1);
        mine[records_.key(i, s)] = state_entity(st, e);
      }
  }
  out.assign(defs_.size(), 0.0);
  MPI_Allreduce(mine.data(), out.data(), static_cast<int>(mine.size()), MPI_DOUBLE, MPI_SUM, world);
}

bool FixParmecSpring::set_state_code(int spring, int code)
{
  if (code < sp::kRegular) fail_on_this_rank(lmp, FLERR, cmd_ + ": set_state_code: code must be >= -3");
  double *slot = const_cast<double *>(owned_slot(spring));
  if (!slot) return false;
  hot_valid_ = false;  // the next step reloads the states from the records
  sp::SpringState st;
  st.unpack(slot + 1);
  st.code = code;
  st.pack(slot + 1);
  // The output row of this step reports the state at the end of the step, as Parmec's HISTORY 'SS' row
  // does: UNSPRING fires after the forces, and its row already shows the new code.
  const double id = static_cast<double>(defs_[spring].id);
  for (int r = 0; r < size_local_rows; r++)
    if (array_local[r][0] == id) array_local[r][6] = code;
  return true;
}

void FixParmecSpring::set_unspring_unload(int code, const sp::SpringTable *curve)
{
  if (code < 0) error->all(FLERR, cmd_ + ": set_unspring_unload: code must be >= 0");
  unspring_unload_[code] = curve;
}

}  // namespace dembridge
