// The plugin loads in-process and registers its styles (a missing file is only a log line in
// LAMMPS, so registration is asserted, not assumed).
#include "lammps_fixture.h"

#include <set>

TEST_F(LammpsWithPlugin, RegistersGranularStylesAndPropertyFix)
{
  EXPECT_TRUE(lammps_has_style(lmp, "pair", "gran/hooke"));
  EXPECT_TRUE(lammps_has_style(lmp, "fix", "property/global"));
  std::set<std::string> names;
  char style[64], name[64];
  for (int k = 0; k < lammps_plugin_count(); ++k) {
    lammps_plugin_name(k, style, name, sizeof name);
    names.insert(std::string(style) + ":" + name);
  }
  EXPECT_TRUE(names.count("pair:gran/hooke"));
  EXPECT_TRUE(names.count("fix:property/global"));
}
