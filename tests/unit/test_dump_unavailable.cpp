// The dump command's refusal of a dump style this build has not got: names the style, the dump id,
// the reason given by the build, and what writes the same files.
#include "dump_unavailable.h"

#include <gtest/gtest.h>

TEST(DumpUnavailable, MeshDumpNamesStyleIdReasonAndTheFixThatWritesTheFiles)
{
  EXPECT_EQ(dembridge::dump_unavailable_message("mesh/stl", "d1", "no dump.h"),
            "dump mesh/stl (id d1) is not available in this build of dembridge: no dump.h; "
            "fix mesh/dump writes the same mesh files");
  EXPECT_EQ(dembridge::dump_unavailable_message("mesh/gran/VTK", "m", "why"),
            "dump mesh/gran/VTK (id m) is not available in this build of dembridge: why; "
            "fix mesh/dump writes the same mesh files");
}

TEST(DumpUnavailable, CustomVtkPointsToDumpCustom)
{
  EXPECT_EQ(dembridge::dump_unavailable_message("custom/vtk", "p", "why"),
            "dump custom/vtk (id p) is not available in this build of dembridge: why; "
            "LAMMPS's dump custom writes the same per-atom columns as text");
}
