// Checks shared by the plugin's sphere integrators (fix nve/sphere, fix nve/bpm/sphere/omp): the same words and
// conditions as LAMMPS's own sphere integrators, written once.
#pragma once

#include <string>

namespace LAMMPS_NS {
class LAMMPS;
}

namespace dembridge::integrate {

// Moment-of-inertia prefactor for the keyword 'disc' (0.5); an ERROR naming cmd unless the run is 2d.
double disc_inertia(LAMMPS_NS::LAMMPS *lmp, const std::string &cmd);

// ERROR naming cmd and run_style respa if the run uses rRESPA (its levels need LAMMPS's Respa class, whose header
// the wheel does not ship); what_to_do says what the user does instead.
void refuse_respa(LAMMPS_NS::LAMMPS *lmp, const std::string &cmd, const std::string &what_to_do);

// ERROR naming cmd and the first atom of the group (bit groupbit) with radius 0: the integrators need extended
// particles.
void require_extended_particles(LAMMPS_NS::LAMMPS *lmp, const std::string &cmd, int groupbit);

}  // namespace dembridge::integrate
