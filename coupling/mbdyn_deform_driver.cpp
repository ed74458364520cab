#include "mbdyn_deform_driver.h"

#include "fix_mesh_surface.h"
#include "vertex_loads.h"

#include "error.h"
#include "lammps.h"

#include <mpi.h>

namespace dembridge {

void MbdynDeformDriver::attach(LAMMPS_NS::LAMMPS *lmp, const std::string &mesh_id, const std::string &caller)
{
  lmp_ = lmp;
  mesh_ = FixMeshSurface::find(lmp, mesh_id, caller);
  if (!mesh_->stress_on())
    lmp->error->all(FLERR, caller + ": mapping " + mesh_id + " needs fix mesh/surface/stress (with stress on), "
                                    "whose wall contacts give the loads of the mapped points");
  if (mesh_->moving() && !mesh_->driven_externally())
    lmp->error->all(FLERR, caller + ": mapping " + mesh_id + " is also moved by fix move/mesh; a mesh follows "
                                    "either MBDyn or fix move/mesh");
  mesh_->drive_externally();
  mesh_->record_contacts();
}

std::string MbdynDeformDriver::bind(const std::vector<V3> &points, double tol)
{
  if (!corners_.empty()) return "";  // a later run: the vertices keep their points
  try {
    corners_ = mesh::match_corners(mesh_->mesh(), points, tol);
  } catch (const mesh::MeshError &e) {
    return e.what();
  }
  points_ = points.size();
  return "";
}

void MbdynDeformDriver::move_to(const std::vector<V3> &x, const std::vector<V3> &v)
{
  mesh_->mesh_for_motion().place_corners(corners_, x, v);
}

void MbdynDeformDriver::loads(double *out6) const
{
  // every rank's contacts to every rank, then one canonical sum (the same on any rank count)
  const std::vector<double> &mine = mesh_->contacts();
  static_assert(sizeof(mesh::MeshContact) == 7 * sizeof(double), "a contact is 7 doubles");
  int nprocs = 1;
  MPI_Comm_size(lmp_->world, &nprocs);
  // on one rank this rank's contacts are all of them: sorted where they are, not in a gathered copy
  const mesh::MeshContact *all = reinterpret_cast<const mesh::MeshContact *>(mine.data());
  std::size_t nall = mine.size() / 7;
  std::vector<mesh::MeshContact> gathered;
  if (nprocs > 1) {
    const int n = static_cast<int>(mine.size());
    std::vector<int> counts(nprocs), displs(nprocs, 0);
    MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, lmp_->world);
    int total = 0;
    for (int r = 0; r < nprocs; ++r) {
      displs[r] = total;
      total += counts[r];
    }
    gathered.resize(total / 7);
    MPI_Allgatherv(mine.data(), n, MPI_DOUBLE, reinterpret_cast<double *>(gathered.data()), counts.data(), displs.data(),
                   MPI_DOUBLE, lmp_->world);
    all = gathered.data();
    nall = gathered.size();
  }
  std::vector<double> p(3 * points_, 0.0);
  mesh::distribute_contacts(mesh_->mesh(), corners_, all, nall, p.data());
  for (std::size_t j = 0; j < points_; ++j)
    for (int a = 0; a < 3; ++a) out6[6 * j + a] += p[3 * j + a];
}

void MbdynDeformDriver::restart_totals() { mesh_->pre_force(0); }

}  // namespace dembridge
