// fix mbdyn ... modal's restart record: what a new LAMMPS process needs to continue the coupling
// where write_restart left it, bit for bit, with a peer that continues it too (doc/fix_mbdyn.md,
// "Restart info"). The atoms, the mesh vertices (fix mesh/surface) and the wall history carry
// their own state; this record holds the last kinematics received, the last loads answered, the
// binding of the points to the FEM nodes and where the exchange sequence stands. One MBDyn step is
// one LAMMPS step and tight iterates end within the step, so write_restart (between runs) always
// finds the step answered.
#include "fix_mbdyn_modal.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "group.h"

#include <cstdio>
#include <cstring>
#include <exception>

#include "restart_doubles.h"

using namespace LAMMPS_NS;
namespace mb = dembridge::mbdyn;

namespace dembridge {

namespace {
constexpr double kModalMagic = 25122026.0;  // marks fix mbdyn ... modal's record (fix mbdyn's is another)
constexpr double kVersion = 1.0;
constexpr int kHead = 8;  // count, magic, version, modes, type, tight, points, mesh flag

double type_code(mb::ModalType t) { return t == mb::ModalType::All ? 0 : t == mb::ModalType::Rigid ? 1 : 2; }
const char *type_word(double code) { return code == 0 ? "all" : code == 1 ? "rigid" : "modal"; }
}  // namespace

void FixMBDynModal::write_restart(FILE *fp)
{
  if (comm->me != 0) return;  // every rank holds the same state; rank 0 writes
  std::vector<double> buf;
  RestartDoubles r(buf);
  r.put(0.0);  // the count of doubles, set at the end
  r.put(kModalMagic);
  r.put(kVersion);
  r.put(static_cast<double>(config_.num_modes));
  r.put(type_code(config_.type));
  r.put(tight_ ? 1 : 0);
  r.put(static_cast<double>(body_.num_points()));
  r.put(deform_ ? 1 : 0);
  r.put_text(mesh_id_);
  r.put(bound_ && messages_ > 0);  // else written before the coupling started: a new one starts
  r.put(ended_);
  r.put(first_is_step1_);
  r.put(t0_answered_);
  r.put(static_cast<double>(messages_));
  r.put(last_change_);
  r.put(kin_.x.data(), 3);
  r.put(kin_.R.data(), 9);
  r.put(kin_.v.data(), 3);
  r.put(kin_.omega.data(), 3);
  r.put_vector(kin_.q);
  r.put_vector(kin_.qdot);
  r.put(last_.force.data(), 3);
  r.put(last_.moment.data(), 3);
  r.put_vector(last_.p);
  for (const auto &x : body_.rest) r.put(x.data(), 3);
  for (std::size_t n : body_.fem_node) r.put(static_cast<double>(n));
  r.put_vector(body_.shapes);
  r.put(static_cast<double>(tags_.size()));
  for (tagint t : tags_) r.put(static_cast<double>(t));
  buf[0] = static_cast<double>(buf.size());
  const int size = static_cast<int>(buf.size() * sizeof(double));
  std::fwrite(&size, sizeof(int), 1, fp);
  std::fwrite(buf.data(), sizeof(double), buf.size(), fp);
}

void FixMBDynModal::restart(char *raw)
{
  const std::string prefix = "fix mbdyn modal: read_restart: ";
  double first[kHead];
  std::memcpy(first, raw, sizeof(first));
  if (first[1] != kModalMagic || first[2] != kVersion || !(first[0] >= kHead && first[0] < 1e12))
    error->all(FLERR, prefix + "the restart file's record of fix ID '{}' is not one of fix mbdyn ... modal (of this "
                               "version): the run that wrote it used fix mbdyn without 'modal', or another version",
               id);
  if (!resume_) {
    if (comm->me == 0)
      error->warning(FLERR, prefix + "resume no: the coupling state of the restart file is ignored; this run starts a "
                                     "new coupling with MBDyn's start-up (t0) message");
    return;
  }
  std::vector<double> in(static_cast<std::size_t>(first[0]));
  std::memcpy(in.data(), raw, in.size() * sizeof(double));
  RestartDoubles r(in.data(), in.size());
  for (int i = 0; i < kHead; ++i) r.get();
  auto refuse = [&](const std::string &why) {
    failed_ = true;
    error->all(FLERR, prefix + why + " (the command after read_restart must describe the coupling of the run that "
                               "wrote the restart file; 'resume no' starts a new coupling instead)");
  };
  if (static_cast<std::uint32_t>(first[3]) != config_.num_modes)
    refuse("the restart file's coupling has " + std::to_string(static_cast<long long>(first[3])) +
           " modes, this command " + std::to_string(config_.num_modes) + " ('modes')");
  if (first[4] != type_code(config_.type))
    refuse(std::string("the restart file's coupling is type ") + type_word(first[4]) + ", this command's type " +
           type_word(type_code(config_.type)) + " ('type')");
  if ((first[5] != 0) != tight_)
    refuse(std::string("the restart file's coupling is ") + (first[5] != 0 ? "tight" : "loose") + ", this command's " +
           (tight_ ? "tight" : "loose") + " ('coupling')");
  const std::string mesh = r.get_text();
  if ((first[7] != 0) != !mesh_id_.empty() || mesh != mesh_id_)
    refuse("the restart file's coupling carries " + (mesh.empty() ? std::string("the group's atoms") : "mesh '" + mesh + "'") +
           ", this command " + (mesh_id_.empty() ? std::string("the group's atoms") : "mesh '" + mesh_id_ + "'") +
           " ('mesh')");
  const std::size_t points = static_cast<std::size_t>(first[6]);
  if (!mesh_id_.empty() && points != fem_.num_nodes())
    refuse("the restart file's mesh follows " + std::to_string(points) + " FEM nodes, this command's FEM file has " +
           std::to_string(fem_.num_nodes()) + " ('modal FEM-FILE')");
  if (r.get() == 0.0) return;  // written before the coupling started: a new one starts here
  ended_ = r.get() != 0.0;
  first_is_step1_ = r.get() != 0.0;
  t0_answered_ = r.get() != 0.0;
  messages_ = r.get_int();
  last_change_ = r.get();
  r.get(kin_.x.data(), 3);
  r.get(kin_.R.data(), 9);
  r.get(kin_.v.data(), 3);
  r.get(kin_.omega.data(), 3);
  r.get_vector(kin_.q);
  r.get_vector(kin_.qdot);
  r.get(last_.force.data(), 3);
  r.get(last_.moment.data(), 3);
  r.get_vector(last_.p);
  mb::ModalBody body;
  body.num_modes = config_.num_modes;
  body.rest.resize(points);
  body.fem_node.resize(points);
  for (auto &x : body.rest) r.get(x.data(), 3);
  bool nodes_ok = true;
  for (std::size_t &n : body.fem_node) {
    const long long k = r.get_int();
    nodes_ok = nodes_ok && k >= 0 && static_cast<std::size_t>(k) < fem_.num_nodes();
    n = nodes_ok ? static_cast<std::size_t>(k) : 0;
  }
  r.get_vector(body.shapes);
  const long long ntags = r.get_int();
  tags_.clear();
  for (long long k = 0; k < ntags && r.ok(); ++k) tags_.push_back(static_cast<tagint>(r.get_int()));
  if (!r.ok() || kin_.q.size() != config_.num_modes || last_.p.size() != config_.num_modes)
    refuse("the restart file's record of this fix is truncated or damaged");
  if (!nodes_ok)
    refuse("the restart file's points sit on FEM nodes this command's FEM file does not have ('modal FEM-FILE')");
  // the mode shapes at the carried points, from this command's FEM file and modes
  std::vector<std::array<double, 3>> at;
  for (std::size_t n : body.fem_node) at.push_back(fem_.node_xyz[n]);
  if (mb::map_points_to_fem_nodes(fem_, at, origin_, 0.0).shapes != body.shapes)
    refuse("the restart file's mode shapes at the carried points differ from this command's ('modal FEM-FILE', "
           "'modes', 'list')");
  if (first_is_step1_ && !ended_)
    refuse("the restart file was written before the first step of a tight coupling without start-up exchange; its "
           "message of step 1 is not answered and cannot be received again");
  body_ = std::move(body);
  point_of_.clear();
  for (std::size_t p = 0; p < tags_.size(); ++p) point_of_[tags_[p]] = p;
  if (!mesh_id_.empty() ? !tags_.empty() : tags_.size() != points)
    refuse("the restart file's record of this fix is truncated or damaged");
  bound_ = true;
  restored_ = true;
}

// The mesh restored by its fix has every vertex at its point of the last kinematics: bound to
// the FEM nodes again there, with the velocities of that message. Atoms carry their own x and v.
// The next message is MBDyn's next step, over a new connection (negotiated at the first receive).
void FixMBDynModal::resume_coupling()
{
  restored_ = false;
  if (!deform_) {
    if (group->count(igroup) != static_cast<bigint>(tags_.size()))
      fail("read_restart: group '" + std::string(group->names[igroup]) + "' has " + std::to_string(group->count(igroup)) +
           " atoms, the run that wrote the restart file carried " + std::to_string(tags_.size()));
    for (int i = 0; i < atom->nlocal; ++i)
      if ((atom->mask[i] & groupbit) && !point_of_.count(atom->tag[i]))
        fail("read_restart: atom " + std::to_string(atom->tag[i]) + " of group '" + group->names[igroup] +
             "' was not carried by the run that wrote the restart file");
    return;
  }
  try {
    mb::modal_point_states(body_, kin_, x_, v_);
  } catch (const std::exception &e) {
    fail(e.what());
  }
  std::vector<MbdynDeformDriver::V3> xs(x_.size() / 3), vs(x_.size() / 3);
  for (std::size_t p = 0; p < xs.size(); ++p)
    for (int c = 0; c < 3; ++c) {
      xs[p][c] = x_[3 * p + c];
      vs[p][c] = v_[3 * p + c];
    }
  const std::string why = deform_->bind(xs, match_);
  if (!why.empty())
    fail("read_restart: mesh " + mesh_id_ + ": " + why + " (the mesh of the restart file is not at the FEM nodes of "
         "the restart file's last pose: define the mesh with the same file and options as the run that wrote it)");
  mesh_bound_ = true;
  deform_->move_to(xs, vs);
}

}  // namespace dembridge
