// Built without the fix mesh/surface glue: node mesh is refused at init.
#include "mbdyn_mesh_driver.h"

#include "error.h"
#include "lammps.h"

namespace dembridge {

void MbdynMeshDriver::attach(LAMMPS_NS::LAMMPS *lmp, const std::string &mesh_id, const std::string &caller)
{
  lmp->error->all(FLERR, caller + ": node mesh " + mesh_id + " needs fix mesh/surface/stress, which this build "
                                  "of the plugin does not have");
}
void MbdynMeshDriver::bind(const V3 &, const M9 &) {}
void MbdynMeshDriver::move_to(const V3 &, const M9 &, const V3 &, const V3 &) {}
void MbdynMeshDriver::loads(const V3 &, double *) const {}
void MbdynMeshDriver::restart_totals() {}
MbdynMeshDriver::V3 MbdynMeshDriver::tracked_point() const { return {0, 0, 0}; }

}  // namespace dembridge

#include "mbdyn_deform_driver.h"

namespace dembridge {

void MbdynDeformDriver::attach(LAMMPS_NS::LAMMPS *lmp, const std::string &mesh_id, const std::string &caller)
{
  lmp->error->all(FLERR, caller + ": mapping " + mesh_id + " needs fix mesh/surface/stress, which this build "
                                  "of the plugin does not have");
}
std::string MbdynDeformDriver::bind(const std::vector<V3> &, double) { return ""; }
void MbdynDeformDriver::move_to(const std::vector<V3> &, const std::vector<V3> &) {}
void MbdynDeformDriver::loads(double *) const {}
void MbdynDeformDriver::restart_totals() {}

}  // namespace dembridge
