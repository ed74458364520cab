// fix mbdyn: what MBDyn sends is checked before any atom moves. An orientation matrix that is not
// a rotation (all zero, skewed, mirrored) or a position that puts a coupled atom outside a fixed
// ('f') boundary of the box is an ERROR naming the node and the field; otherwise the first sign of
// it would be LAMMPS's "Lost atoms", naming nothing. NaN and infinity are refused by the protocol
// library when the message is decoded.
#include "fix_mbdyn.h"

#include "domain.h"
#include "update.h"

#include "nodal_message.h"
#include "peer_session.h"
#include "rotation_check.h"

#include <cmath>
#include <cstdio>
#include <string>

using namespace LAMMPS_NS;

namespace dembridge {

namespace {

std::string vec_text(const double *x)
{
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.9g, %.9g, %.9g)", x[0], x[1], x[2]);
  return buf;
}

// The first dimension d in which x lies beyond a fixed boundary by more than margin, else -1.
// A periodic dimension accepts one box length beyond (LAMMPS remaps by one period); a
// shrink-wrapped side follows the atoms.
int outside_box(const Domain *domain, const double *x, double margin)
{
  const double *lo = domain->triclinic ? domain->boxlo_bound : domain->boxlo;
  const double *hi = domain->triclinic ? domain->boxhi_bound : domain->boxhi;
  for (int d = 0; d < 3; ++d) {
    const double len = hi[d] - lo[d];
    if (domain->periodicity[d]) {
      if (x[d] - margin < lo[d] - len || x[d] + margin > hi[d] + len) return d;
      continue;
    }
    if (domain->boundary[d][0] == 1 && x[d] - margin < lo[d]) return d;
    if (domain->boundary[d][1] == 1 && x[d] + margin >= hi[d]) return d;
  }
  return -1;
}

std::string box_text(const Domain *domain, int d)
{
  const double *lo = domain->triclinic ? domain->boxlo_bound : domain->boxlo;
  const double *hi = domain->triclinic ? domain->boxhi_bound : domain->boxhi;
  char buf[128];
  std::snprintf(buf, sizeof buf, "outside the box in %c: [%.9g, %.9g]%s", "xyz"[d], lo[d], hi[d],
                domain->periodicity[d] ? " by more than one period" : " (fixed boundary)");
  return buf;
}

}  // namespace

void FixMBDyn::check_poses(const std::vector<Pose> &poses)
{
  const mbdyn::Kinematics &k = kinematics();
  const std::string at = " in the message received at LAMMPS step " + std::to_string(update->ntimestep);
  if (k.has_reference && options_->nodal.mapping_reference &&
      k.reference_rotation == mbdyn::Rotation::OrientationMatrix) {
    const std::string why = mbdyn::rotation_matrix_defect(k.reference_rotation_matrix());
    if (!why.empty()) fail_all("the reference node's orientation matrix" + at + " " + why);
  }
  if (k.rotation == mbdyn::Rotation::OrientationMatrix && options_->nodal.has_rotation()) {
    if (k.has_reference) {
      const std::string why = mbdyn::rotation_matrix_defect(k.reference_rotation_matrix());
      if (!why.empty()) fail_all("the reference node's orientation matrix" + at + " " + why);
    }
    for (std::size_t i = 0; i < num_points_; ++i) {  // the reference body's slot: checked above
      const std::string why = mbdyn::rotation_matrix_defect(mbdyn::matrix_from_wire_column_major(&k.orientation[9 * i]));
      if (!why.empty())
        fail_all(slot_name(i) + " (" + nodes_[i].text + "): MBDyn's orientation matrix" + at + " " + why);
    }
  }
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const NodeSpec &n = nodes_[i];
    if (n.is_mesh || (!n.is_atom && node_radius_.size() != poses.size())) continue;  // groups: once bound
    const Pose &p = poses[i];
    const double radius = n.is_atom ? 0.0 : node_radius_[i];
    const int d = outside_box(domain, p.x.data(), radius);
    if (d < 0) continue;
    const std::string head = slot_name(i) + " (" + n.text + "): MBDyn's position " + vec_text(p.x.data()) + at;
    if (n.is_atom) fail_all(head + " puts atom " + std::to_string(n.tag) + " " + box_text(domain, d) + "; LAMMPS would lose it");
    // The bounding sphere reaches out of the box: look at the atoms themselves.
    for (const auto &tm : member_list_) {
      if (tm.second.node != static_cast<int>(i)) continue;
      const double *r = tm.second.r;
      double x[3];
      for (int c = 0; c < 3; ++c) x[c] = p.x[c] + p.R[3 * c] * r[0] + p.R[3 * c + 1] * r[1] + p.R[3 * c + 2] * r[2];
      const int e = outside_box(domain, x, 0.0);
      if (e >= 0)
        fail_all(head + " puts atom " + std::to_string(tm.first) + " at " + vec_text(x) + " " + box_text(domain, e) +
                 "; LAMMPS would lose it");
    }
  }
}

}  // namespace dembridge
