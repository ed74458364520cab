// A LAMMPS instance on MPI_COMM_WORLD with the dembridge plugin loaded, driven through the C
// library interface so input errors come back as messages instead of aborts.
#pragma once

#define LAMMPS_LIB_MPI  // lammps_open() with an MPI communicator
#include "library.h"

#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

// Full-precision number for a command line (std::to_string keeps only 6 decimals).
inline std::string num(double v)
{
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

class LammpsWithPlugin : public ::testing::Test {
 protected:
  void *lmp = nullptr;

  static std::string plugin_path()
  {
    const char *p = std::getenv("DEMBRIDGE_PLUGIN");
    return p ? p : "";
  }

  void SetUp() override
  {
    const char *args[] = {"lammps_tests", "-log", "none", "-screen", "none", "-nocite"};
    lmp = lammps_open(6, const_cast<char **>(args), MPI_COMM_WORLD, nullptr);
    ASSERT_NE(lmp, nullptr);
    ASSERT_FALSE(plugin_path().empty()) << "DEMBRIDGE_PLUGIN is not set";
    cmd("plugin load " + plugin_path());
  }
  void TearDown() override { lammps_close(lmp); }

  // Runs one command; returns the error message ("" when it succeeded).
  std::string cmd(const std::string &line)
  {
    lammps_command(lmp, line.c_str());
    if (lammps_has_error(lmp)) {
      char buf[2048];
      lammps_get_last_error_message(lmp, buf, sizeof buf);
      return buf;
    }
    return "";
  }
  void ok(const std::string &line) { ASSERT_EQ(cmd(line), "") << "command failed: " << line; }

  // Per-atom 3-vector gathered on every rank, ordered by atom ID.
  std::vector<double> gather3(const char *name)
  {
    const int n = static_cast<int>(lammps_get_natoms(lmp));
    std::vector<double> out(3 * n);
    lammps_gather_atoms(lmp, const_cast<char *>(name), 1, 3, out.data());
    return out;
  }
};
