// plugin/lammps_compat.h calls the Domain::minimum_image form the LAMMPS at hand has: the FLERR form of
// 22 Jul 2025 (the file and line reach it), the bare form of 4 Feb 2025.
#include "lammps_compat.h"

#include <gtest/gtest.h>

namespace {
struct DomainJul2025 {  // the signature of LAMMPS 22 Jul 2025
  mutable std::string file;
  mutable int line = 0;
  void minimum_image(const std::string &f, int l, double *d) const
  {
    file = f;
    line = l;
    d[0] -= 10.0;
  }
  void minimum_image(const std::string &f, int l, double &x, double &, double &) const
  {
    file = f;
    line = l;
    x -= 10.0;
  }
};
struct DomainFeb2025 {  // the signature of LAMMPS 4 Feb 2025
  mutable int calls = 0;
  void minimum_image(double *d) const
  {
    ++calls;
    d[2] += 4.0;
  }
  void minimum_image(double &, double &, double &z) const
  {
    calls += 10;
    z += 4.0;
  }
};
}  // namespace

TEST(LammpsCompat, MinimumImageWithFileAndLineWhereLammpsHasIt)
{
  const DomainJul2025 dom;
  double d[3] = {7.0, 1.0, 2.0};
  dembridge::minimum_image(&dom, "caller.cpp", 42, d);
  EXPECT_EQ(dom.file, "caller.cpp");
  EXPECT_EQ(dom.line, 42);
  EXPECT_EQ(d[0], -3.0);
  double x = 8.0, y = 1.0, z = 2.0;
  dembridge::minimum_image(&dom, "other.cpp", 7, x, y, z);
  EXPECT_EQ(dom.line, 7);
  EXPECT_EQ(x, -2.0);
  EXPECT_EQ(y, 1.0);
  EXPECT_EQ(z, 2.0);
}

TEST(LammpsCompat, MinimumImageWithoutFileAndLineInFebruary2025)
{
  const DomainFeb2025 dom;
  double d[3] = {7.0, 1.0, -3.0};
  dembridge::minimum_image(&dom, "caller.cpp", 42, d);
  EXPECT_EQ(dom.calls, 1);
  EXPECT_EQ(d[2], 1.0);
  double x = 8.0, y = 1.0, z = -2.5;
  dembridge::minimum_image(&dom, "caller.cpp", 43, x, y, z);
  EXPECT_EQ(dom.calls, 11);
  EXPECT_EQ(x, 8.0);
  EXPECT_EQ(z, 1.5);
}
