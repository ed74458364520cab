#include "compute_wall_gran_local.h"

#include "fix_wall_gran.h"
#include "style_registry.h"

#include "atom.h"
#include "error.h"
#include "modify.h"
#include "update.h"

using namespace LAMMPS_NS;

namespace dembridge {

ComputeWallGranLocal::ComputeWallGranLocal(LAMMPS *lmp, int narg, char **arg) : Compute(lmp, narg, arg)
{
  if (narg != 4)
    error->all(FLERR, "compute " + std::string(id) + " wall/gran/local: expected exactly one argument, the ID of a fix wall/gran "
                                                      "(LIGGGHTS syntax), got " + std::to_string(narg - 3));
  wall_id_ = arg[3];
  FixWallGran *w = find_wall();
  w->request_records();
  ncols_ = kFixedCols + w->history_size();
  local_flag = 1;
  size_local_rows = 0;
  size_local_cols = ncols_;
  array_local = nullptr;
}

FixWallGran *ComputeWallGranLocal::find_wall()
{
  const std::string me = "compute " + std::string(id) + " wall/gran/local";
  Fix *f = modify->get_fix_by_id(wall_id_);
  if (!f) error->all(FLERR, me + ": no fix with ID '" + wall_id_ + "'; expected the ID of a fix wall/gran");
  auto *w = dynamic_cast<FixWallGran *>(f);
  if (!w)
    error->all(FLERR, me + ": fix '" + wall_id_ + "' (style " + std::string(f->style) +
                          ") is not a dembridge fix wall/gran with LIGGGHTS syntax");
  return w;
}

void ComputeWallGranLocal::init()
{
  wall_ = find_wall();
  wall_->request_records();
}

// The wall fix's records of this step's force evaluation (post_force runs before output).
void ComputeWallGranLocal::compute_local()
{
  invoked_local = update->ntimestep;
  const auto &rec = wall_->records();
  data_.assign(rec.size() * ncols_, 0.0);
  rows_.resize(rec.size());
  int n = 0;
  for (const auto &r : rec) {
    if (!(atom->mask[r.atom_index] & groupbit)) continue;
    double *row = &data_[std::size_t(n) * ncols_];
    row[0] = double(atom->tag[r.atom_index]);
    row[1] = r.mesh + 1;  // 0 for a primitive wall, else the position in 'meshes'
    row[2] = r.element + 1;  // triangle id, 1-based (0 for a primitive wall)
    row[3] = r.delta;
    row[4] = r.Fn;
    for (int k = 0; k < 3; ++k) {
      row[5 + k] = r.F[k];
      row[8 + k] = r.Ft[k];
      row[11 + k] = r.cp[k];
    }
    for (int k = kFixedCols; k < ncols_; ++k) row[k] = r.hist[k - kFixedCols];
    rows_[n] = row;
    ++n;
  }
  size_local_rows = n;
  array_local = n ? rows_.data() : nullptr;
}

double ComputeWallGranLocal::memory_usage() { return double(data_.capacity() * sizeof(double) + rows_.capacity() * sizeof(double *)); }

static void *create(void *lmp, int narg, char **arg) { return new ComputeWallGranLocal(static_cast<LAMMPS *>(lmp), narg, arg); }
static RegisterStyle reg("compute", "wall/gran/local", "per-contact output of a dembridge fix wall/gran", create);

}  // namespace dembridge
