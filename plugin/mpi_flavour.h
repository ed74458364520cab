// Which MPI a host LAMMPS runs on, so that a plugin built for another one stops with an ERROR at load
// instead of crashing at its first MPI call (MPICH and Open MPI differ in the ABI: MPI_Comm is an int in
// one and a pointer in the other). LAMMPS-free, unit tested.
#pragma once

#include <string>

namespace dembridge {

enum class MpiFlavour { unknown, mpich, openmpi };

// "MPICH" / "OpenMPI" (the names CMake's DEMBRIDGE_MPI_FLAVOUR uses) / "unknown"
const char *mpi_flavour_name(MpiFlavour f);
MpiFlavour mpi_flavour_from_name(const std::string &name);

// The MPI linked by the shared object that contains `addr` (e.g. a function of liblammps.so), looked up
// in that object and its dependencies only: Open MPI when ompi_mpi_comm_world is there, the MPICH ABI
// when MPI_Init is, else unknown (a static executable, a serial LAMMPS).
struct ObjectMpi {
  MpiFlavour flavour = MpiFlavour::unknown;
  std::string object;  // the shared object's file name
};
ObjectMpi mpi_of_object(const void *addr);

// "" when a plugin built for `built` may run in `host`; else the reason, naming both.
std::string mpi_mismatch_message(MpiFlavour built, MpiFlavour host, const std::string &host_object);

}  // namespace dembridge
