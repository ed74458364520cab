// The force re-evaluation of a tight-coupling iterate, shared by fix mbdyn and fix mbdyn ... modal:
// after the coupled atoms (or meshes) were moved to MBDyn's next iterate, the forces are computed
// again without advancing anything else.
#pragma once

#include <functional>

namespace LAMMPS_NS {
class LAMMPS;
}

namespace dembridge {

// Zeroes f (and torque), runs the pair and bond styles and the post_force of the fixes defined
// before fix `fix_id`, with update->setupflag = 1 so that the granular pair styles do not update
// their contact history on these trial evaluations. before_fixes runs just before those fixes
// (the mesh drivers restart their totals there). Fixes defined after fix_id are not run.
void reevaluate_forces_for_iterate(LAMMPS_NS::LAMMPS *lmp, const char *fix_id, int vflag,
                                   const std::function<void()> &before_fixes);

}  // namespace dembridge
