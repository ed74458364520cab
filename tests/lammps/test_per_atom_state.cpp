// The per-atom state layer (fixes/state, doc/per_atom_state.md) under the disturbances LAMMPS puts
// atoms through: atom sorting every step, migration between ranks (mpi.lammps_tests_2ranks), unrelated
// atoms created and deleted between runs, and a restart file. Spring and torsion-spring states must
// follow their atoms, so every disturbed run ends bit for bit where the undisturbed run does (spring
// forces are summed in spring order, independent of atom order and ranks). In-process, so the
// sanitizer layer (./dembridge test, build-sanitize/) checks the layer's memory handling too.
#include "lammps_fixture.h"

#include <cmath>
#include <cstdio>

namespace {

constexpr int kNx = 6, kNy = 4;

int ident(int i, int j) { return 1 + i + kNx * j; }

}  // namespace

class PerAtomState : public LammpsWithPlugin {
 protected:
  // A kNx x kNy grid of bpm/sphere bodies drifting along x through a periodic box (they cross the rank
  // boundary), joined by translational springs along x and torsion springs along y; spins vary.
  void setup_grid(bool sort_every_step)
  {
    const int me = rank();
    if (me == 0) {
      FILE *fp = std::fopen(file("per_atom_state.data").c_str(), "w");
      std::fprintf(fp, "grid\n\n%d atoms\n2 atom types\n-1 %d xlo xhi\n-2 %d ylo yhi\n-3 3 zlo zhi\n\nAtoms # bpm/sphere\n\n",
                   kNx * kNy, kNx + 5, kNy + 2);
      for (int j = 0; j < kNy; j++)
        for (int i = 0; i < kNx; i++) std::fprintf(fp, "%d 0 1 0.8 1000 %d %d 0\n", ident(i, j), i, j);
      std::fclose(fp);
    }
    MPI_Barrier(MPI_COMM_WORLD);
    ok("units si");
    ok("atom_style bpm/sphere");
    ok("atom_modify map array");
    ok("boundary p f f");
    ok("comm_modify vel yes cutoff 2.5");
    ok("read_data " + file("per_atom_state.data"));
    ok(sort_every_step ? "atom_modify sort 1 0.5" : "atom_modify sort 0 0");
    ok("variable wx atom 2*sin(id*0.37)");
    ok("variable wy atom 2*cos(id*0.53)");
    ok("variable wz atom sin(id*1.7)");
    ok("set group all omega v_wx v_wy v_wz");
    ok("variable vy atom 0.2*sin(id*0.71)");
    ok("velocity all set 3 v_vy 0 units box");
    ok("neighbor 0.3 bin");
    define_fixes();
  }

  // Translational springs along x, torsion springs along y (the same lines after a restart).
  void define_fixes()
  {
    std::string springs = "fix S all parmec/spring table K -1 -2000 1 2000 table D -1 -5 1 5";
    std::string torsion = "fix T all parmec/torsion table R -1 50 1 -50 table RD -1 5 1 -5";
    int sid = 1, tid = 1;
    for (int j = 0; j < kNy; j++)
      for (int i = 0; i < kNx; i++) {
        if (i + 1 < kNx)
          springs += " spring " + std::to_string(sid++) + " " + std::to_string(ident(i, j)) + " centre " +
                     std::to_string(ident(i + 1, j)) + " centre K dashpot D";
        if (j + 1 < kNy)
          torsion += " torsion " + std::to_string(tid++) + " " + std::to_string(ident(i, j)) + " " +
                     std::to_string(ident(i, j + 1)) + " 1 0 0 0 0.6 0.8 kroll R kpitch R kyaw R droll RD";
      }
    ok(springs);
    ok(torsion);
    ok("fix I all nve/bpm/sphere");
    ok("timestep 2e-3");
    ok("thermo 0");
  }

  // Files per rank count: the serial and the 2-rank runs of this executable may run at the same time.
  std::string file(const char *stem)
  {
    int n = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &n);
    return std::string(stem) + "_np" + std::to_string(n);
  }

  int rank()
  {
    int me = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &me);
    return me;
  }

  std::vector<double> grid_state()
  {
    std::vector<double> s = gather3("x");
    for (const char *name : {"v", "omega", "torque"}) {
      const std::vector<double> a = gather3(name);
      s.insert(s.end(), a.begin(), a.end());
    }
    return s;
  }
};

TEST_F(PerAtomState, SortingInsertionDeletionAndRestartLeaveTheStatesWithTheirAtoms)
{
  setup_grid(false);
  ok("run 400 post no");
  const std::vector<double> reference = grid_state();
  lammps_close(lmp);

  // The same 400 steps with atoms sorted every step, 3 unrelated atoms (type 2) created after step 100
  // and deleted after step 200, and a restart file written at step 300 and read back.
  const char *args[] = {"lammps_tests", "-log", "none", "-screen", "none", "-nocite"};
  lmp = lammps_open(6, const_cast<char **>(args), MPI_COMM_WORLD, nullptr);
  ok("plugin load " + plugin_path());
  setup_grid(true);
  ok("run 100 post no");
  ok("create_atoms 2 single 9 -1.5 0 units box");
  ok("create_atoms 2 single 9.5 -1.5 1 units box");
  ok("create_atoms 2 single 10 -1.5 -1 units box");
  ok("set type 2 diameter 0.2 density 1000");
  ok("run 100 post no");
  ok("group extra type 2");
  ok("delete_atoms group extra compress no");
  ok("run 100 post no");
  ok("write_restart " + file("per_atom_state.restart"));
  ok("clear");
  ok("plugin load " + plugin_path());
  ok("atom_modify map array");
  ok("read_restart " + file("per_atom_state.restart"));
  ok("comm_modify vel yes cutoff 2.5");
  ok("atom_modify sort 1 0.5");
  ok("neighbor 0.3 bin");
  define_fixes();  // the same definitions, as a user restarting the deck gives them
  ok("run 100 post no");
  const std::vector<double> disturbed = grid_state();

  ASSERT_EQ(disturbed.size(), reference.size());
  int differ = 0;
  for (std::size_t k = 0; k < reference.size(); k++)
    if (disturbed[k] != reference[k]) differ++;
  EXPECT_EQ(differ, 0) << "values differing from the undisturbed run (x, v, omega, torque of 24 bodies)";
  // the springs act: torques on the bodies at the end (torque follows x, v, omega in grid_state)
  double torque = 0.0;
  for (int k = 9 * kNx * kNy; k < 12 * kNx * kNy; k++) torque += std::fabs(reference[k]);
  EXPECT_GT(torque, 1e-3);
}
