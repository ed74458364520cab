#include "mpi_flavour.h"

#include <dlfcn.h>

namespace dembridge {

const char *mpi_flavour_name(MpiFlavour f)
{
  switch (f) {
    case MpiFlavour::mpich: return "MPICH";
    case MpiFlavour::openmpi: return "OpenMPI";
    default: return "unknown";
  }
}

MpiFlavour mpi_flavour_from_name(const std::string &name)
{
  if (name == "MPICH") return MpiFlavour::mpich;
  if (name == "OpenMPI") return MpiFlavour::openmpi;
  return MpiFlavour::unknown;
}

ObjectMpi mpi_of_object(const void *addr)
{
  ObjectMpi r;
  Dl_info info{};
  if (!addr || !dladdr(addr, &info) || !info.dli_fname) return r;
  r.object = info.dli_fname;
  // RTLD_NOLOAD: the object is loaded already (it holds addr); only a handle on it is taken, and
  // dlsym on that handle searches the object and its own dependencies, not what others loaded
  void *h = dlopen(info.dli_fname, RTLD_LAZY | RTLD_NOLOAD);
  if (!h) return r;
  if (dlsym(h, "ompi_mpi_comm_world")) r.flavour = MpiFlavour::openmpi;
  else if (dlsym(h, "MPI_Init")) r.flavour = MpiFlavour::mpich;
  dlclose(h);
  return r;
}

std::string mpi_mismatch_message(MpiFlavour built, MpiFlavour host, const std::string &host_object)
{
  if (built == MpiFlavour::unknown || host == MpiFlavour::unknown || built == host) return "";
  return std::string("dembridge was built for ") + mpi_flavour_name(built) + " but this LAMMPS (" + host_object +
         ") runs on " + mpi_flavour_name(host) + ": the plugin would crash at its first MPI call. Rebuild it " +
         "against this LAMMPS (cmake -DLAMMPS_DIR=...; its MPI is chosen from what liblammps.so links)";
}

}  // namespace dembridge
