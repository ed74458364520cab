// fix mbdyn's per-step kernels for `node atom` couplings (every MBDyn point drives one atom that
// sits on it): set the atoms' pose, gather their loads. Issue 12, P5: in a step of 10^4 particles
// the ~100 coupled atoms' rows of x, v, omega, f and torque have left the caches, and a loop that
// meets them one at a time waits for one miss after another. So the atoms are first looked up
// (the atom map read directly) and their rows prefetched, then visited; the rows are addressed as
// the contiguous arrays LAMMPS allocates (&x[0][0] + 3 i: no load of the row pointer). Local
// indices change only when LAMMPS rebuilds its neighbour lists (exchange, sort and atom insertion or
// deletion all happen then; the lists themselves hold local indices), so the lookup is kept from
// one build to the next and only the prefetches are issued per use: 100 random reads of the atom
// map saved twice a step.
// The arithmetic is the general path's (fix_mbdyn.cpp, apply_pose and accumulate_loads), term by
// term, so both give the same bits.
#include "fix_mbdyn.h"
#include "lammps_compat.h"

#include "atom.h"
#include "domain.h"
#include "neighbor.h"
#include "update.h"

#include "peer_session.h"

#include <cmath>
#include <limits>

using namespace LAMMPS_NS;

namespace dembridge {

bool FixMBDyn::node_atoms_fast_path() const
{
  return one_atom_per_node_ && atom->map_style != Atom::MAP_NONE && !update->setupflag;
}

void FixMBDyn::find_node_atoms(int rows_for_write)
{
  // The map holds a tag's owned atom when it has one (LAMMPS sets it from the last index down, so
  // an owned atom wins over its ghost images): an index below nlocal is the atom itself.
  const int nlocal = atom->nlocal;
  const int *map_array = atom->map_style == Atom::MAP_ARRAY ? atom->get_map_array() : nullptr;
  const std::size_t n = node_tags_.size();
  const bool current = node_local_.size() == n && node_local_build_ == neighbor->ncalls &&
                       node_local_nlocal_ == nlocal && node_local_tags_ == tags_version_;
  node_local_.resize(n);
  int *local = node_local_.data();
  const tagint *tags = node_tags_.data();
  node_local_build_ = neighbor->ncalls;
  node_local_nlocal_ = nlocal;
  node_local_tags_ = tags_version_;
  if (current) {
    // same atoms at the same indices as at the last lookup: only the prefetches below
  } else if (map_array) {
    for (std::size_t j = 0; j < n; ++j) local[j] = map_array[tags[j]];
  } else {
    for (std::size_t j = 0; j < n; ++j) local[j] = atom->map(tags[j]);
  }
  if (nlocal == 0) {
    if (!current)
      for (std::size_t j = 0; j < n; ++j) local[j] = -1;
    return;
  }
  double *x = &atom->x[0][0], *v = &atom->v[0][0], *f = &atom->f[0][0];
  double *omega = atom->omega_flag ? &atom->omega[0][0] : nullptr;
  double *torque = atom->torque_flag ? &atom->torque[0][0] : nullptr;
  imageint *image = atom->image;
  for (std::size_t j = 0; j < n; ++j) {
    int i = local[j];
    if (i >= nlocal) local[j] = i = -1;  // a ghost image only (the owner is on another rank)
    if (i < 0) continue;
    if (rows_for_write) {
      __builtin_prefetch(x + 3 * i, 1);
      __builtin_prefetch(v + 3 * i, 1);
      __builtin_prefetch(image + i, 1);
      if (omega) __builtin_prefetch(omega + 3 * i, 1);
    } else {
      __builtin_prefetch(x + 3 * i, 0);
      __builtin_prefetch(f + 3 * i, 0);
      if (torque) __builtin_prefetch(torque + 3 * i, 0);
    }
  }
}

void FixMBDyn::apply_pose_node_atoms(const std::vector<Pose> &poses, bool set_x)
{
  find_node_atoms(1);
  if (atom->nlocal == 0) return;
  double *x = &atom->x[0][0], *v = &atom->v[0][0];
  double *omega = atom->omega_flag && options_->nodal.has_rotation() ? &atom->omega[0][0] : nullptr;
  imageint *image = atom->image;
  const imageint image0 = ((imageint) IMGMAX << IMG2BITS) | ((imageint) IMGMAX << IMGBITS) | IMGMAX;
  // remap only where it can change x (see apply_pose)
  const bool remap = domain->xperiodic || domain->yperiodic || domain->zperiodic || domain->triclinic;
  constexpr double inf = std::numeric_limits<double>::infinity();
  const int periodic[3] = {domain->xperiodic, domain->yperiodic, domain->zperiodic};
  double lo[3], hi[3];
  for (int c = 0; c < 3; ++c) {
    lo[c] = periodic[c] ? domain->boxlo[c] : -inf;
    hi[c] = periodic[c] ? domain->boxhi[c] : inf;
  }
  const Pose *pose = poses.data();
  const int *local = node_local_.data(), *node = node_index_.data();
  const std::size_t n = node_local_.size();
  for (std::size_t j = 0; j < n; ++j) {
    const int i = local[j];
    if (i < 0) continue;
    const Pose &P = pose[node[j]];
    double *xi = x + 3 * i;
    if (set_x) {
      for (int c = 0; c < 3; ++c) xi[c] = P.x[c] + 0.0;  // R r = 0 on the point, as in apply_pose
      image[i] = image0;
      if (remap && (domain->triclinic || !(xi[0] >= lo[0] && xi[0] < hi[0] && xi[1] >= lo[1] && xi[1] < hi[1] &&
                                           xi[2] >= lo[2] && xi[2] < hi[2])))
        domain->remap(xi, image[i]);
    }
    for (int c = 0; c < 3; ++c) v[3 * i + c] = P.v[c] + 0.0;
    if (omega)
      for (int c = 0; c < 3; ++c) omega[3 * i + c] = P.w[c];
  }
}

void FixMBDyn::accumulate_loads_node_atoms(const std::vector<Pose> &poses, std::vector<double> &local)
{
  // Each node's six entries are written once, zero when its atom is on another rank (0.0 + term:
  // the same bits as adding to a zeroed slot, as the general path does).
  find_node_atoms(0);
  const int n = static_cast<int>(nodes_.size());
  local.resize(6 * static_cast<std::size_t>(n));
  const bool any = atom->nlocal > 0;
  const double *x = any ? &atom->x[0][0] : nullptr, *f = any ? &atom->f[0][0] : nullptr;
  const double *torque = any && atom->torque_flag ? &atom->torque[0][0] : nullptr;
  // minimum_image only where it can change the arm (see accumulate_loads)
  const bool periodic = domain->xperiodic || domain->yperiodic || domain->zperiodic;
  constexpr double inf = std::numeric_limits<double>::infinity();
  const bool triclinic = domain->triclinic != 0;
  const double half[3] = {domain->xperiodic ? domain->prd_half[0] : inf, domain->yperiodic ? domain->prd_half[1] : inf,
                          domain->zperiodic ? domain->prd_half[2] : inf};
  const Pose *pose = poses.data();
  const int *index = node_local_.data(), *node = node_index_.data();
  double *out = local.data();
  const std::size_t nm = node_local_.size();
  for (std::size_t j = 0; j < nm; ++j) {
    const int i = index[j], k = node[j];
    double *slot = out + 6 * static_cast<std::size_t>(k);
    if (i < 0) {
      for (int c = 0; c < 6; ++c) slot[c] = 0.0;
      continue;
    }
    const double *xi = x + 3 * i, *fi = f + 3 * i, *px = pose[k].x.data();
    double d[3] = {xi[0] - px[0], xi[1] - px[1], xi[2] - px[2]};
    if (periodic &&
        (triclinic || std::fabs(d[0]) > half[0] || std::fabs(d[1]) > half[1] || std::fabs(d[2]) > half[2]))
      dembridge::minimum_image(domain, FLERR, d);
    const double m[3] = {d[1] * fi[2] - d[2] * fi[1], d[2] * fi[0] - d[0] * fi[2], d[0] * fi[1] - d[1] * fi[0]};
    for (int c = 0; c < 3; ++c) {
      slot[c] = 0.0 + fi[c];
      slot[3 + c] = 0.0 + (m[c] + (torque ? torque[3 * i + c] : 0.0));
    }
  }
}

}  // namespace dembridge
