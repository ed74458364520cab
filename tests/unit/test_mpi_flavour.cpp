// The plugin tells the MPI of its host LAMMPS from the shared object holding LAMMPS's plugin_register,
// here from real libmpi builds of each flavour (opened locally, not initialised), and refuses a mismatch.
#include "mpi_flavour.h"

#include <dlfcn.h>
#include <gtest/gtest.h>

#include <string>

using dembridge::MpiFlavour;

namespace {
dembridge::ObjectMpi of_library(const char *path)
{
  void *h = dlopen(path, RTLD_LAZY | RTLD_LOCAL);
  if (!h) return {};
  // Left open: unloading Open MPI's libmpi drops the buffers its constructors allocated, which LeakSanitizer
  // then reports from an unknown module; kept loaded they stay reachable until exit.
  return dembridge::mpi_of_object(dlsym(h, "MPI_Comm_rank"));
}
int no_mpi_here() { return 0; }
}  // namespace

TEST(MpiFlavour, AnObjectWithoutMpiIsUnknown)
{
  EXPECT_EQ(dembridge::mpi_of_object(reinterpret_cast<const void *>(&no_mpi_here)).flavour, MpiFlavour::unknown);
  EXPECT_EQ(dembridge::mpi_of_object(nullptr).flavour, MpiFlavour::unknown);
}

TEST(MpiFlavour, TheMpichWheelIsMpich)
{
  const auto r = of_library(DEMBRIDGE_TEST_MPICH_LIBMPI);
  EXPECT_EQ(r.flavour, MpiFlavour::mpich) << DEMBRIDGE_TEST_MPICH_LIBMPI;
  EXPECT_NE(r.object.find("libmpi.so.12"), std::string::npos) << r.object;
}

TEST(MpiFlavour, OpenMpiIsOpenMpi)
{
  if (std::string(DEMBRIDGE_TEST_OPENMPI_LIBMPI).find("NOTFOUND") != std::string::npos)
    GTEST_SKIP() << "Open MPI (libmpi.so.40) is not installed on this machine";
  EXPECT_EQ(of_library(DEMBRIDGE_TEST_OPENMPI_LIBMPI).flavour, MpiFlavour::openmpi) << DEMBRIDGE_TEST_OPENMPI_LIBMPI;
}

TEST(MpiFlavour, MismatchNamesBothSides)
{
  EXPECT_EQ(dembridge::mpi_mismatch_message(MpiFlavour::mpich, MpiFlavour::mpich, "liblammps.so.0"), "");
  EXPECT_EQ(dembridge::mpi_mismatch_message(MpiFlavour::mpich, MpiFlavour::unknown, "lmp"), "");
  EXPECT_EQ(dembridge::mpi_mismatch_message(MpiFlavour::mpich, MpiFlavour::openmpi, "/opt/lammps/lib/liblammps.so.0"),
            "dembridge was built for MPICH but this LAMMPS (/opt/lammps/lib/liblammps.so.0) runs on OpenMPI: the "
            "plugin would crash at its first MPI call. Rebuild it against this LAMMPS (cmake -DLAMMPS_DIR=...; its "
            "MPI is chosen from what liblammps.so links)");
  EXPECT_EQ(dembridge::mpi_flavour_from_name("OpenMPI"), MpiFlavour::openmpi);
  EXPECT_EQ(dembridge::mpi_flavour_from_name("none"), MpiFlavour::unknown);
}
