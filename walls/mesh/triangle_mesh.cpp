// Per-triangle quantities, validation, topology (edge/corner activity) and rigid motion of a
// triangle mesh, written from spec liggghts-walls §4.2, §4.3, §7.2, §7.3.
#include "triangle_mesh.h"

#include "node_index.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <type_traits>
#include <map>
#include <sstream>

namespace dembridge::mesh {

namespace {

std::string tri_label(int t) { return "triangle " + std::to_string(t + 1) + " (file order)"; }

std::string number(double v)
{
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

TriangleMesh::TriangleMesh(std::vector<TriangleNodes> triangles, const MeshOptions &opt) : opt_(opt)
{
  if (!(opt_.precision > 0.0) || !std::isfinite(opt_.precision))
    throw MeshError("precision must be a positive number");
  if (triangles.empty()) throw MeshError("the mesh has no triangles");
  node_ = std::move(triangles);
  for (int t = 0; t < size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (!all_finite(node_[t][k]))
        throw MeshError(tri_label(t) + " has a non-finite (NaN or inf) node coordinate");

  std::vector<std::array<int, 3>> ids = index_nodes(node_, opt_.precision);
  if (opt_.heal_remove_duplicates) {
    std::map<std::array<int, 3>, int> seen;
    std::vector<TriangleNodes> kept;
    std::vector<std::array<int, 3>> kept_ids;
    for (int t = 0; t < size(); ++t) {
      std::array<int, 3> key = ids[t];
      std::sort(key.begin(), key.end());
      if (!seen.emplace(key, t).second) {
        ++removed_duplicates_;
        continue;
      }
      kept.push_back(node_[t]);
      kept_ids.push_back(ids[t]);
    }
    node_ = std::move(kept);
    ids = std::move(kept_ids);
  }

  const std::size_t n = node_.size();
  edge_vec_.resize(n);
  edge_norm_.resize(n);
  edge_len_.resize(n);
  normal_.resize(n);
  center_.resize(n);
  rbound_.resize(n);
  area_.resize(n);
  obtuse_.resize(n);
  active_.assign(n, 0x3f);
  validate();
  for (int t = 0; t < size(); ++t) {
    compute_geometry(t);
    compute_center_rbound(t);
  }
  build_topology(ids);
  global_size_ = size();
  bounding_box(box_lo_, box_hi_);
}

void TriangleMesh::validate()
{
  for (int t = 0; t < size(); ++t) {
    const TriangleNodes &nd = node_[t];
    Vec3 ev[3];
    for (int k = 0; k < 3; ++k) {
      const Vec3 v = sub(nd[(k + 1) % 3], nd[k]);
      const double l = norm(v);
      if (std::isinf(l)) {
        double big = 0.0;
        for (const Vec3 &p : nd)
          for (double c : p) big = std::max(big, std::fabs(c));
        throw MeshError(tri_label(t) + ": the length of edge " + std::to_string(k + 1) + " overflows double precision (coordinates up to " +
                        number(big) + "); expected coordinates well below 1e150 (scale the mesh)");
      }
      if (!(l > opt_.precision))
        throw MeshError(tri_label(t) + " is degenerate: edge " + std::to_string(k + 1) +
                        " is shorter than the precision " + number(opt_.precision));
      ev[k] = div_by(v, l);
    }
    if (!(norm(cross(ev[0], ev[1])) > 0.0)) throw MeshError(tri_label(t) + " is degenerate: its nodes are colinear");
    for (int k = 0; k < 3; ++k) {
      // angle at node k between edge k (outgoing) and edge k-1 (incoming, reversed)
      const double cos_angle = -dot(ev[k], ev[(k + 2) % 3]);
      if (cos_angle > opt_.curvature && !opt_.curvature_tolerant) {
        std::ostringstream os;
        os << tri_label(t) << " has an angle of " << std::acos(std::min(1.0, cos_angle)) * 180.0 / 3.14159265358979323846
           << " degrees at node " << k + 1 << ", below the curvature limit (use curvature_tolerant yes to accept it)";
        throw MeshError(os.str());
      }
    }
  }
}

void TriangleMesh::compute_geometry(int t)
{
  const TriangleNodes &nd = node_[t];
  for (int k = 0; k < 3; ++k) {
    const Vec3 v = sub(nd[(k + 1) % 3], nd[k]);
    const double l = norm(v);
    edge_len_[t][k] = l;
    edge_vec_[t][k] = div_by(v, l);
  }
  const Vec3 c = cross(edge_vec_[t][0], edge_vec_[t][1]);
  normal_[t] = div_by(c, norm(c));
  for (int k = 0; k < 3; ++k) {
    const Vec3 en = cross(edge_vec_[t][k], normal_[t]);
    edge_norm_[t][k] = div_by(en, norm(en));
  }
  // the flag is overwritten for every node in turn, so only node 2 can end up obtuse (§4.2)
  obtuse_[t] = dot(edge_vec_[t][2], edge_vec_[t][1]) > 0.0 ? 2 : -1;
  area_[t] = 0.5 * norm(cross(sub(nd[1], nd[0]), sub(nd[2], nd[0])));
}

void TriangleMesh::compute_center_rbound(int t)
{
  const TriangleNodes &nd = node_[t];
  Vec3 sum{0.0, 0.0, 0.0};
  for (int k = 0; k < 3; ++k) sum = add(nd[k], sum);
  center_[t] = div_by(sum, 3.0);
  double rb = 0.0;
  for (int k = 0; k < 3; ++k) rb = std::max(rb, norm(sub(center_[t], nd[k])));
  rbound_[t] = rb;
}

void TriangleMesh::build_topology(const std::vector<std::array<int, 3>> &ids)
{
  const int n = size();
  int nnodes = 0;
  for (const auto &a : ids)
    for (int id : a) nnodes = std::max(nnodes, id + 1);
  // node -> triangles containing it (ascending)
  std::vector<std::vector<int>> tris_of(nnodes);
  for (int t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k)
      if (tris_of[ids[t][k]].empty() || tris_of[ids[t][k]].back() != t) tris_of[ids[t][k]].push_back(t);

  neigh_.assign(n, {});
  for (int t = 0; t < n; ++t) {
    std::vector<int> &nb = neigh_[t];
    for (int k = 0; k < 3; ++k)
      for (int u : tris_of[ids[t][k]])
        if (u != t) nb.push_back(u);
    std::sort(nb.begin(), nb.end());
    nb.erase(std::unique(nb.begin(), nb.end()), nb.end());
  }

  // Shared edges: coplanar -> inactive on both; else active only on the larger id (§4.3).
  std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> edges;
  for (int t = 0; t < n; ++t)
    for (int e = 0; e < 3; ++e) {
      const int a = ids[t][e], b = ids[t][(e + 1) % 3];
      edges[{std::min(a, b), std::max(a, b)}].push_back({t, e});
    }
  auto set_edge = [this](int t, int e, bool on) {
    if (on) active_[t] |= std::uint8_t(1u << e);
    else active_[t] &= std::uint8_t(~(1u << e));
  };
  for (const auto &kv : edges) {
    const auto &list = kv.second;
    for (std::size_t i = 1; i < list.size(); ++i)
      for (std::size_t j = 0; j < i; ++j) {
        const auto [ti, ei] = list[i];
        const auto [tj, ej] = list[j];
        if (ti == tj) continue;
        if (std::fabs(dot(normal_[ti], normal_[tj])) >= opt_.curvature) {
          set_edge(ti, ei, false);
          set_edge(tj, ej, false);
        } else {
          const bool i_hi = ti > tj;
          set_edge(i_hi ? tj : ti, i_hi ? ej : ei, false);
          set_edge(i_hi ? ti : tj, i_hi ? ei : ej, true);
        }
      }
  }

  // Corners: active only on the largest-id triangle at the node, if one of the edges there is
  // active and no two of those edges are colinear with different far ends (§4.3).
  for (int t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::vector<int> &has = tris_of[ids[t][k]];
      std::vector<Vec3> ev;
      std::vector<int> ends;
      bool any_active = false;
      for (int u : has) {
        const int ku = int(std::find(ids[u].begin(), ids[u].end(), ids[t][k]) - ids[u].begin());
        const int kprev = (ku + 2) % 3;
        ev.push_back(edge_vec_[u][ku]);
        ev.push_back(edge_vec_[u][kprev]);
        ends.push_back(ids[u][(ku + 1) % 3]);
        ends.push_back(ids[u][kprev]);
        if (edge_active(u, ku) || edge_active(u, kprev)) any_active = true;
      }
      bool colinear = false;
      for (std::size_t a = 0; a < ev.size() && !colinear; ++a)
        for (std::size_t b = a + 1; b < ev.size(); ++b)
          if (std::fabs(std::fabs(dot(ev[a], ev[b])) - 1.0) < 1e-10 && ends[a] != ends[b]) {
            colinear = true;
            break;
          }
      const bool on = !colinear && any_active && t == has.back();
      if (on) active_[t] |= std::uint8_t(1u << (3 + k));
      else active_[t] &= std::uint8_t(~(1u << (3 + k)));
    }
}

bool TriangleMesh::are_node_neighbors(int a, int b) const
{
  const std::vector<int> &nb = neigh_[a];
  return std::binary_search(nb.begin(), nb.end(), b);
}

bool TriangleMesh::coplanar_node_neighbors(int a, int b) const
{
  return are_node_neighbors(a, b) && std::fabs(dot(normal_[a], normal_[b])) > opt_.curvature;
}

void TriangleMesh::zero_velocity()
{
  vel_.resize(node_.size());
  for (auto &v : vel_) v = {Vec3{0.0, 0.0, 0.0}, Vec3{0.0, 0.0, 0.0}, Vec3{0.0, 0.0, 0.0}};
}

Vec3 TriangleMesh::velocity_at(int t, const Vec3 &b) const
{
  if (vel_.empty()) return {0.0, 0.0, 0.0};
  const auto &v = vel_[t];
  Vec3 r;
  for (int k = 0; k < 3; ++k) r[k] = b[0] * v[0][k] + b[1] * v[1][k] + b[2] * v[2][k];
  return r;
}

void TriangleMesh::translate(const Vec3 &dx)
{
  ++version_;
  moved_ = true;
  for (auto &nd : node_)
    for (auto &p : nd) p = add(p, dx);
  for (auto &c : center_) c = add(c, dx);
  for (auto &p : attached_) p = add(p, dx);
}

void TriangleMesh::rotate(double dphi, const Vec3 &axis, const Vec3 &origin)
{
  ++version_;
  moved_ = true;
  const Quat q = axis_angle_quat(div_by(axis, norm(axis)), dphi);
  const bool shift = dot(origin, origin) > 0.0;
  auto rot_point = [&](Vec3 &p) {
    if (shift) p = add(quat_rotate(sub(p, origin), q), origin);
    else p = quat_rotate(p, q);
  };
  for (int t = 0; t < size(); ++t) {
    for (auto &p : node_[t]) rot_point(p);
    for (int k = 0; k < 3; ++k) {
      edge_vec_[t][k] = quat_rotate(edge_vec_[t][k], q);
      edge_norm_[t][k] = quat_rotate(edge_norm_[t][k], q);
    }
    normal_[t] = quat_rotate(normal_[t], q);
    Vec3 sum{0.0, 0.0, 0.0};
    for (int k = 0; k < 3; ++k) sum = add(node_[t][k], sum);
    center_[t] = div_by(sum, 3.0);
  }
  for (auto &p : attached_) rot_point(p);
}

void TriangleMesh::refresh_geometry()
{
  for (int t = 0; t < size(); ++t) compute_geometry(t);
}

void TriangleMesh::place_nodes(const std::vector<TriangleNodes> &nodes)
{
  if (nodes.size() != node_.size())
    throw MeshError("place_nodes: expected " + std::to_string(node_.size()) + " triangles, got " +
                    std::to_string(nodes.size()));
  node_ = nodes;
  placed();
}

// After place_nodes / place_corners: every triangle's geometry from its new nodes.
void TriangleMesh::placed()
{
  ++version_;
  moved_ = true;
  for (int t = 0; t < size(); ++t) {
    compute_geometry(t);
    compute_center_rbound(t);
  }
}

void TriangleMesh::place_corners(const std::vector<std::array<int, 3>> &corner, const std::vector<Vec3> &points,
                                 const std::vector<Vec3> &velocities)
{
  if (corner.size() != node_.size())
    throw MeshError("place_corners: expected " + std::to_string(node_.size()) + " triangles, got " +
                    std::to_string(corner.size()));
  vel_.resize(node_.size());
  const Vec3 zero{0.0, 0.0, 0.0};
  for (int t = 0; t < size(); ++t)
    for (int k = 0; k < 3; ++k) {
      node_[t][k] = points[corner[t][k]];
      vel_[t][k] = add(zero, velocities[corner[t][k]]);
    }
  placed();
}

int TriangleMesh::attach_point(const Vec3 &p)
{
  // after restore_state(), points attached later (movers created after the mesh) take their
  // restored position
  const std::size_t i = attached_.size();
  attached_.push_back(i < restored_attached_.size() ? restored_attached_[i] : p);
  return static_cast<int>(attached_.size()) - 1;
}

namespace {
constexpr double kUnmoved = -1.0;  // third word of a saved state whose nodes are the file's
void put(std::vector<double> &b, const Vec3 &v) { b.insert(b.end(), v.begin(), v.end()); }
void get(const std::vector<double> &b, std::size_t &i, Vec3 &v)
{
  for (int k = 0; k < 3; ++k) v[k] = b.at(i++);
}
// get(), noting whether the value changed
void get(const std::vector<double> &b, std::size_t &i, Vec3 &v, bool &changed)
{
  const Vec3 old = v;
  get(b, i, v);
  changed = changed || old != v;
}
}  // namespace

std::vector<double> TriangleMesh::save_state() const
{
  std::vector<double> b;
  b.push_back(double(global_size_));
  b.push_back(double(attached_.size()));
  if (!moved_) {  // the nodes are still those of the file: only the attached points (any rank may keep a part)
    b.push_back(kUnmoved);
    for (const auto &p : attached_) put(b, p);
    return b;
  }
  b.push_back(vel_.empty() ? 0.0 : 1.0);
  for (int t = 0; t < size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      put(b, node_[t][k]);
      put(b, edge_vec_[t][k]);
      put(b, edge_norm_[t][k]);
      if (!vel_.empty()) put(b, vel_[t][k]);
    }
    put(b, edge_len_[t]);
    put(b, normal_[t]);
    put(b, center_[t]);
    b.push_back(area_[t]);
    b.push_back(double(obtuse_[t]));
  }
  for (const auto &p : attached_) put(b, p);
  return b;
}

void TriangleMesh::restore_state(const std::vector<double> &b)
{
  ++version_;
  std::size_t i = 0;
  if (b.size() < 3 || int(b[0]) != global_size_)
    throw MeshError("the restart file holds a mesh with a different number of triangles");
  const std::size_t nattached = std::size_t(b[1]);
  i = 3;
  if (b[2] == kUnmoved) {
    if (moved_) throw MeshError("the saved mesh is at its file position but this one has moved");
    restore_attached(b, i, nattached);
    return;
  }
  if (!whole()) throw MeshError("a moved mesh state needs the whole mesh (this rank keeps a part of it)");
  const bool has_vel = b[2] != 0.0;
  if (has_vel) zero_velocity();
  else vel_.clear();
  try {
    for (int t = 0; t < size(); ++t) {
      for (int k = 0; k < 3; ++k) {
        get(b, i, node_[t][k], moved_);
        get(b, i, edge_vec_[t][k], moved_);
        get(b, i, edge_norm_[t][k], moved_);
        if (has_vel) get(b, i, vel_[t][k]);
      }
      get(b, i, edge_len_[t], moved_);
      get(b, i, normal_[t], moved_);
      get(b, i, center_[t], moved_);
      moved_ = moved_ || area_[t] != b.at(i) || obtuse_[t] != std::int8_t(b.at(i + 1));
      area_[t] = b.at(i++);
      obtuse_[t] = std::int8_t(b.at(i++));
    }
    restore_attached(b, i, nattached);
  } catch (const std::out_of_range &) {
    throw MeshError("the mesh state in the restart file is truncated");
  }
}

void TriangleMesh::restore_attached(const std::vector<double> &b, std::size_t i, std::size_t n)
{
  if (i + 3 * n > b.size()) throw MeshError("the mesh state in the restart file is truncated");
  restored_attached_.resize(n);
  for (auto &p : restored_attached_) get(b, i, p);
  for (std::size_t k = 0; k < attached_.size() && k < n; ++k) attached_[k] = restored_attached_[k];
}

int TriangleMesh::local_id(int g) const
{
  if (gid_.empty()) return g >= 0 && g < size() ? g : -1;
  const auto it = std::lower_bound(gid_.begin(), gid_.end(), g);
  return it != gid_.end() && *it == g ? int(it - gid_.begin()) : -1;
}

void TriangleMesh::keep_only(const std::vector<int> &ids)
{
  ++version_;
  std::vector<int> new_of(node_.size(), -1);
  for (std::size_t j = 0; j < ids.size(); ++j) new_of[std::size_t(ids[j])] = int(j);
  auto pick = [&ids](auto &v) {
    if (v.empty()) return;
    std::remove_reference_t<decltype(v)> kept;
    kept.reserve(ids.size());
    for (int t : ids) kept.push_back(v[std::size_t(t)]);
    v.swap(kept);
  };
  pick(node_);
  pick(edge_vec_);
  pick(edge_norm_);
  pick(edge_len_);
  pick(normal_);
  pick(center_);
  pick(rbound_);
  pick(area_);
  pick(obtuse_);
  pick(active_);
  pick(vel_);
  std::vector<std::vector<int>> neigh(ids.size());
  for (std::size_t j = 0; j < ids.size(); ++j)
    for (int u : neigh_[std::size_t(ids[j])])
      if (new_of[std::size_t(u)] >= 0) neigh[j].push_back(new_of[std::size_t(u)]);
  neigh_.swap(neigh);
  std::vector<int> gid(ids.size());
  for (std::size_t j = 0; j < ids.size(); ++j) gid[j] = global_id(ids[j]);
  gid_.swap(gid);
}

void TriangleMesh::bounding_box(Vec3 &lo, Vec3 &hi) const
{
  if (!whole() || node_.empty()) {
    lo = box_lo_;
    hi = box_hi_;
    return;
  }
  lo = node_[0][0];
  hi = lo;
  for (const auto &nd : node_)
    for (const auto &p : nd)
      for (int d = 0; d < 3; ++d) {
        lo[d] = std::min(lo[d], p[d]);
        hi[d] = std::max(hi[d], p[d]);
      }
}

std::uint64_t TriangleMesh::node_digest() const
{
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a
  for (const auto &nd : node_)
    for (const auto &p : nd)
      for (double c : p) {
        std::uint64_t bits;
        std::memcpy(&bits, &c, sizeof bits);
        h = (h ^ bits) * 1099511628211ull;
      }
  return h;
}

void TriangleMesh::take_attached_points(const TriangleMesh &from)
{
  attached_ = from.attached_;
  restored_attached_ = from.restored_attached_;
  version_ = from.version_ + 1;
}

double TriangleMesh::memory_bytes() const
{
  double bytes = double(node_.size()) * (sizeof(TriangleNodes) * 3 + sizeof(Vec3) * 3 + sizeof(double) * 2 + 2);
  bytes += double(vel_.size()) * sizeof(std::array<Vec3, 3>);
  for (const auto &nb : neigh_) bytes += sizeof(nb) + nb.capacity() * sizeof(int);
  bytes += double(gid_.capacity()) * sizeof(int);
  return bytes;
}

}  // namespace dembridge::mesh
