// compute parmec/obstacles: LAMMPS glue only (the poses are fix parmec/granular's); see the header.
#include "compute_parmec_obstacles.h"
#include "fix_parmec_granular.h"
#include "style_registry.h"

#include "comm.h"
#include "error.h"
#include "modify.h"
#include "update.h"

#include <cstring>

using namespace LAMMPS_NS;

namespace dembridge {

ComputeParmecObstacles::ComputeParmecObstacles(LAMMPS *lmp, int narg, char **arg) : Compute(lmp, narg, arg)
{
  if (narg != 4) error->all(FLERR, "compute parmec/obstacles: expected one argument, the ID of a fix parmec/granular");
  fix_id_ = arg[3];
  local_flag = 1;
  size_local_rows = 0;
  size_local_cols = kCols;
  array_local = nullptr;
}

void ComputeParmecObstacles::init()
{
  Fix *f = modify->get_fix_by_id(fix_id_);
  if (!f || std::strcmp(f->style, "parmec/granular") != 0)
    error->all(FLERR, "compute parmec/obstacles: '{}' is not the ID of a fix parmec/granular", fix_id_);
}

void ComputeParmecObstacles::compute_local()
{
  invoked_local = update->ntimestep;
  auto *fix = dynamic_cast<FixParmecGranular *>(modify->get_fix_by_id(fix_id_));
  if (!fix) error->all(FLERR, "compute parmec/obstacles: fix '{}' is gone", fix_id_);
  data_.clear();
  if (comm->me == 0) {
    const auto &obs = fix->obstacles();
    for (std::size_t o = 0; o < obs.size(); o++) {
      const mesh::TriangleMesh &tm = obs[o].mesh();
      for (int t = 0; t < tm.size(); t++) {
        data_.push_back(double(o));
        data_.push_back(double(obs[o].color(t)));
        for (const mesh::Vec3 &p : tm.nodes(t)) data_.insert(data_.end(), p.begin(), p.end());
      }
    }
  }
  size_local_rows = static_cast<int>(data_.size() / kCols);
  rows_.resize(size_local_rows);
  for (int r = 0; r < size_local_rows; r++) rows_[r] = &data_[std::size_t(r) * kCols];
  array_local = size_local_rows ? rows_.data() : nullptr;
}

double ComputeParmecObstacles::memory_usage()
{
  return double(data_.capacity()) * sizeof(double) + double(rows_.capacity()) * sizeof(double *);
}

static RegisterStyle reg_compute_parmec_obstacles("compute", "parmec/obstacles",
                                                  "OBSTACLE triangles of a fix parmec/granular at their current pose",
                                                  create_fix<ComputeParmecObstacles>);

}  // namespace dembridge
