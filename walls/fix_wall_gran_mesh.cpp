// fix wall/gran ... mesh: the particle-triangle pass of spec liggghts-walls §4.5 on the meshes of
// fix mesh/surface (candidates, closest points, wall velocity, stress sums come from that fix).
#include "rank_error.h"
#include "fix_wall_gran.h"

#include "fix_mesh_surface.h"

#include "atom.h"
#include "error.h"
#include "update.h"

#include <cmath>

using namespace LAMMPS_NS;

namespace dembridge {

namespace {
// Contact key: which triangle of which mesh of this fix (exact in a double).
constexpr double kMeshStride = 4294967296.0;
inline double contact_key(int mesh, int tri) { return mesh * kMeshStride + tri; }
inline int key_mesh(double key) { return int(std::floor(key / kMeshStride)); }
inline int key_tri(double key) { return int(key - key_mesh(key) * kMeshStride); }
}  // namespace

// The local id of a contact's triangle. A rank keeps every triangle within reach of its atoms, with
// a margin of the neighbour cutoff, so a triangle touched on the last step is always kept.
int FixWallGran::local_tri(const mesh::TriangleMesh &mesh, double key)
{
  const int t = mesh.local_id(key_tri(key));
  if (t < 0)
    fail_on_this_rank(lmp, FLERR, cmd_ + ": mesh triangle " + std::to_string(key_tri(key) + 1) +
                                      " of a contact is not kept on this rank (a particle moved further than the "
                                      "neighbour cutoff in one step?); 'distribute no' on the mesh keeps it whole");
  return t;
}

void FixWallGran::init_meshes()
{
  meshes_.clear();
  for (const auto &mid : spec_.mesh_ids) {
    FixMeshSurface *m = FixMeshSurface::find(lmp, mid, cmd_);
    check_wall_type(m->wall_type(), ("type of mesh " + mid).c_str());
    meshes_.push_back(m);
  }
}

// The atoms with a candidate triangle on some mesh, ascending: the others (most of them) touch nothing,
// and a pass over all atoms with the contact loop's set-up cost about 90 instructions per atom. The
// candidate lists change only when a mesh builds them again (at re-neighbouring, where atoms also
// move between ranks or are sorted), so the atoms are found again only then: between two builds,
// each pass scans this list alone (before: four passes over all atoms per step, ~20 Ir/atom-step on
// the hopper). Returns true when it searched again.
bool FixWallGran::find_active_atoms()
{
  const int nlocal = atom->nlocal;
  bool same = !update->setupflag && nlocal == active_nlocal_ && active_builds_.size() == meshes_.size();
  for (std::size_t m = 0; same && m < meshes_.size(); ++m) same = active_builds_[m] == meshes_[m]->candidate_builds();
  if (same) return false;
  active_builds_.clear();
  for (FixMeshSurface *ms : meshes_) active_builds_.push_back(ms->candidate_builds());
  active_nlocal_ = nlocal;
  has_candidates_.assign(nlocal, 0);
  for (FixMeshSurface *ms : meshes_)
    for (int i = 0; i < nlocal; ++i) has_candidates_[i] |= ms->ncandidates(i);
  active_.clear();
  for (int i = 0; i < nlocal; ++i)
    if (has_candidates_[i]) active_.push_back(i);
  return true;
}

void FixWallGran::mesh_pass(bool update_history)
{
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  double **x = atom->x;
  const double *radius = atom->radius;
  const int cap = capacity_;
  const int nv = history_size();
  // the key of atom i's s-th contact, and where its history values start
  auto key_of = [this](int i, int s) { return records_.record(i, s)[0]; };
  auto values_of = [this](int i, int s) { return records_.record(i, s) + 1; };
  const bool face_only = !spec_.model.contact.legacy_2x_expressions;  // 2.x: coplanar rules for every new contact (§11)
  const bool searched = find_active_atoms();
  kept_.assign(active_.size() * cap, 0);
  double fpw[3], vw[3], scratch[6] = {0, 0, 0, 0, 0, 0};

  for (std::size_t k = 0; k < active_.size(); ++k) {
    const int i = active_[k];
    if (!(mask[i] & groupbit)) continue;  // (group membership may change between builds: fix group dynamic)
    unsigned char *kept = &kept_[k * cap];
    for (int m = 0; m < int(meshes_.size()); ++m) {
      FixMeshSurface *ms = meshes_[m];
      const auto &mesh = ms->mesh();
      const int nc = ms->ncandidates(i);
      const int *cand = ms->candidates(i);
      for (int c = 0; c < nc; ++c) {
        const int t = cand[c];
        const mesh::TriangleContact tc = ms->closest(t, x[i], radius[i]);
        if (!(tc.dist_minus_r <= 0.0)) continue;
        const int g = mesh.global_id(t);  // history keys and output use file-order ids (any rank, any split)
        const double key = contact_key(m, g);
        int slot = records_.find(i, key);
        if (slot < 0) {
          const bool face = !face_only || tc.kind == mesh::ContactKind::Face;
          if (face) {  // coplanar de-duplication: a flat neighbour already acts in this pass
            bool skip = false;
            for (int s = 0; s < records_.count(i) && !skip; ++s) {
              const double k2 = key_of(i, s);
              skip = kept[s] && key_mesh(k2) == m && key_tri(k2) != g && mesh.coplanar_node_neighbors(local_tri(mesh, k2), t);
            }
            if (skip) continue;
          }
          if (records_.count(i) >= cap)
            fail_on_this_rank(lmp, FLERR, cmd_ + ": atom " + std::to_string(atom->tag[i]) + " touches more than " + std::to_string(cap) +
                                              " mesh triangles at once (mesh contact history overflow)");
          records_.append(i, key);
          slot = records_.count(i) - 1;
          if (face && nv > 0)  // carry the shear spring across a flat shared edge (last partner wins)
            for (int s = 0; s < slot; ++s) {
              const double k2 = key_of(i, s);
              if (key_mesh(k2) == m && key_tri(k2) != g && mesh.coplanar_node_neighbors(local_tri(mesh, k2), t))
                std::copy(values_of(i, s), values_of(i, s) + nv, values_of(i, slot));
            }
        }
        kept[slot] = 1;
        ms->wall_velocity(t, tc.bary, vw);
        touch(i, gran::WallTouch{tc.dist_minus_r, tc.delta.data(), vw}, ms->wall_type(), nv ? values_of(i, slot) : scratch,
              update_history, m, g, fpw);
        if (ms->stress_on() && (mask[i] & ms->groupbit)) {
          const double frc[3] = {-fpw[0], -fpw[1], -fpw[2]};
          const double cp[3] = {x[i][0] + tc.delta[0], x[i][1] + tc.delta[1], x[i][2] + tc.delta[2]};
          ms->add_wall_force(t, frc, cp);
          ms->add_wear(t, x[i], atom->v[i], cp, vw, fpw, atom->type[i]);
        }
      }
    }
  }
  // Contacts not seen in this pass are over: their history goes at once (spec §4.5). An atom without
  // candidates kept none. Only the active atoms can hold contacts between two searches (the others' went
  // at the pass that searched).
  if (!searched) {
    for (std::size_t k = 0; k < active_.size(); ++k)
      for (int s = records_.count(active_[k]) - 1; s >= 0; --s)
        if (!kept_[k * cap + s]) records_.remove(active_[k], s);
    return;
  }
  std::size_t k = 0;
  for (int i = 0; i < nlocal; ++i) {
    while (k < active_.size() && active_[k] < i) ++k;
    const unsigned char *kept = (k < active_.size() && active_[k] == i) ? &kept_[k * cap] : nullptr;
    for (int s = records_.count(i) - 1; s >= 0; --s)
      if (!(kept && kept[s])) records_.remove(i, s);
  }
}

}  // namespace dembridge
