// A triangle mesh wall exactly as LIGGGHTS 3.8 holds it (spec liggghts-walls §4, §7).
//
// CONTRACT (for the wall contact code and any other user of a mesh):
//  * Triangles keep file order; triangle ids are 0..size()-1. Each triangle owns its 3 nodes
//    (nodes are not shared in storage; topology is found once, at construction, with the mesh
//    precision as node-equality tolerance).
//  * Per-triangle quantities (edge_vec, edge_len, edge_norm, normal, center, rbound, obtuse) are
//    those of spec §4.2. For a moving mesh they follow the mover (translate: unchanged; rotate:
//    rotated with the same quaternion) and are recomputed from the nodes only by
//    refresh_geometry(), which the glue calls at every re-neighbouring step (the §7.3 quirk).
//  * edge_active / corner_active are fixed at construction (§4.3) and never recomputed.
//  * node_velocity(t, k) is zero for a static mesh; movers set it each step (§7.1, §7.2).
//  * A distributed rank keeps a subset (keep_only): local ids 0..size()-1 stay in ascending file
//    order, global_id(t) is the file-order id (history keys, output), local_id(g) the way back.
//  * The sphere-triangle distance is in triangle_contact.h, the binned candidate search in
//    mesh_neighbors.h, the movers in mesh_movers.h. Nothing here depends on LAMMPS.
#pragma once

#include "mesh_vec3.h"

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace dembridge::mesh {

// Bad mesh input (unreadable or malformed file, NaN or degenerate triangle, bad option value).
struct MeshError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

using TriangleNodes = std::array<Vec3, 3>;

struct MeshOptions {
  double precision = 1e-8;              // node-equality tolerance and barycentric threshold
  double curvature = 1.0 - 0.00001;     // cos of the coplanarity angle (LIGGGHTS default)
  bool curvature_tolerant = false;      // accept elements with an angle below acos(curvature)
  bool heal_remove_duplicates = false;  // 'heal auto_remove_duplicates'
};

class TriangleMesh {
 public:
  // Validates every triangle (finite, non-degenerate, angles; see MeshOptions) and builds the
  // topology. Throws MeshError naming the first bad triangle (1-based, file order).
  TriangleMesh(std::vector<TriangleNodes> triangles, const MeshOptions &opt = {});

  int size() const { return static_cast<int>(node_.size()); }
  // The whole mesh's triangle count and the file-order id of local triangle t (identity while whole).
  int global_size() const { return global_size_; }
  bool whole() const { return gid_.empty(); }
  int global_id(int t) const { return gid_.empty() ? t : gid_[t]; }
  int local_id(int g) const;  // -1 if triangle g is not kept here
  // Keep only the triangles with the given local ids (ascending): geometry, flags, velocities and
  // node-neighbour lists (restricted to the kept ones) follow; attached points stay.
  void keep_only(const std::vector<int> &ids);
  // Bounding box of the whole mesh's nodes (for a distributed mesh: as it was when it was split).
  void bounding_box(Vec3 &lo, Vec3 &hi) const;
  // Whether a node has ever moved (translate, rotate, place_nodes, a restored state that differs).
  bool moved() const { return moved_; }
  // Hash of every node coordinate's bits (tells whether a re-read file still holds the same mesh).
  std::uint64_t node_digest() const;
  // Attached points (and restored ones) of another mesh of the same file, after a reload.
  void take_attached_points(const TriangleMesh &from);
  const MeshOptions &options() const { return opt_; }
  int removed_duplicates() const { return removed_duplicates_; }

  const Vec3 &node(int t, int k) const { return node_[t][k]; }
  const TriangleNodes &nodes(int t) const { return node_[t]; }
  const Vec3 &edge_vec(int t, int k) const { return edge_vec_[t][k]; }
  double edge_len(int t, int k) const { return edge_len_[t][k]; }
  const Vec3 &edge_norm(int t, int k) const { return edge_norm_[t][k]; }
  const Vec3 &normal(int t) const { return normal_[t]; }
  const Vec3 &center(int t) const { return center_[t]; }
  double rbound(int t) const { return rbound_[t]; }
  double area(int t) const { return area_[t]; }
  int obtuse(int t) const { return obtuse_[t]; }  // 2 or -1 (only node 2 is ever flagged, §4.2)
  bool edge_active(int t, int k) const { return (active_[t] >> k) & 1u; }
  bool corner_active(int t, int k) const { return (active_[t] >> (3 + k)) & 1u; }

  // Triangles sharing at least one node with t (ascending ids, t excluded).
  const std::vector<int> &node_neighbors(int t) const { return neigh_[t]; }
  bool are_node_neighbors(int a, int b) const;
  // §4.5: node neighbours and |n_a . n_b| > curvature (strict).
  bool coplanar_node_neighbors(int a, int b) const;

  // Motion state.
  bool has_velocity() const { return !vel_.empty(); }
  const Vec3 &node_velocity(int t, int k) const { return vel_[t][k]; }
  void zero_velocity();                       // allocates on first use
  void add_node_velocity(int t, int k, const Vec3 &v) { vel_[t][k] = add(vel_[t][k], v); }
  // Bary-weighted wall velocity at a contact (spec §7.1); zero for a static mesh.
  Vec3 velocity_at(int t, const Vec3 &bary) const;

  void translate(const Vec3 &dx);  // nodes, centres and attached points += dx
  // Incremental rotation by dphi about the unit axis through origin: nodes, attached points,
  // edge vectors, edge normals and normals rotated with the same quaternion (§7.2).
  void rotate(double dphi, const Vec3 &axis, const Vec3 &origin);
  // §7.3: edge vectors/lengths, normals, edge normals, obtuse flag, areas from the current nodes.
  void refresh_geometry();
  // A rigid placement computed by the caller (the triangles of a body at x + Λ(P − X)): every node
  // replaced, all per-triangle geometry recomputed from them; topology and edge/corner flags kept.
  // Throws MeshError if the triangle count differs.
  void place_nodes(const std::vector<TriangleNodes> &nodes);
  // The same as place_nodes with node (t, k) = points[corner[t][k]], and with velocity (t, k) =
  // velocities[corner[t][k]] as zero_velocity then add_node_velocity give it (0.0 + v, bit for bit),
  // written in place: a deforming mesh is placed at every exchange without copies of its nodes.
  void place_corners(const std::vector<std::array<int, 3>> &corner, const std::vector<Vec3> &points,
                     const std::vector<Vec3> &velocities);

  // Points that move with the mesh (rotation origins of stacked movers, stress reference point).
  int attach_point(const Vec3 &p);
  const Vec3 &attached_point(int i) const { return attached_[i]; }

  // Restart: the full motion state (nodes, the incrementally updated vectors, velocities,
  // attached points) as doubles; restore_state() requires a mesh built from the same file. Points
  // attached after restore_state() (in the same order as before) get their saved positions.
  // A mesh that never moved saves only its attached points (its nodes are the file's), so a
  // distributed rank's part gives the whole state.
  std::vector<double> save_state() const;
  void restore_state(const std::vector<double> &buf);

  double memory_bytes() const;
  // Changes whenever a node moves (translate, rotate, restore_state): cached search structures
  // compare it to know whether they are stale.
  std::uint64_t geometry_version() const { return version_; }

 private:
  MeshOptions opt_;
  int removed_duplicates_ = 0;
  std::vector<TriangleNodes> node_;
  std::vector<std::array<Vec3, 3>> edge_vec_, edge_norm_;
  std::vector<Vec3> edge_len_;  // [t][k] = length of edge k
  std::vector<Vec3> normal_, center_;
  std::vector<double> rbound_, area_;
  std::vector<std::int8_t> obtuse_;
  std::vector<std::uint8_t> active_;  // bits 0-2 edges, 3-5 corners
  std::vector<std::vector<int>> neigh_;
  std::vector<std::array<Vec3, 3>> vel_;
  std::vector<Vec3> attached_;
  std::vector<Vec3> restored_attached_;  // from restore_state(), for points attached afterwards
  std::uint64_t version_ = 0;
  int global_size_ = 0;
  std::vector<int> gid_;  // empty while whole
  Vec3 box_lo_{}, box_hi_{};  // kept by keep_only()
  bool moved_ = false;

  void validate();
  void compute_geometry(int t);
  void compute_center_rbound(int t);
  void placed();  // geometry of every triangle from its nodes after place_nodes / place_corners
  void restore_attached(const std::vector<double> &b, std::size_t i, std::size_t n);
  void build_topology(const std::vector<std::array<int, 3>> &node_id);
};

}  // namespace dembridge::mesh
