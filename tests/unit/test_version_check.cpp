// The plugin refuses a host LAMMPS of another version unless the expert override is set.
#include "version_check.h"

#include <gtest/gtest.h>

using dembridge::check_host_version;

TEST(VersionCheck, SameVersionIsAcceptedSilently)
{
  const auto v = check_host_version(20250722, 20250722, "22 Jul 2025", nullptr);
  EXPECT_TRUE(v.accept);
  EXPECT_TRUE(v.message.empty());
}

TEST(VersionCheck, OtherVersionIsRefusedWithReason)
{
  const auto v = check_host_version(20250722, 20230802, "2 Aug 2023", nullptr);
  EXPECT_FALSE(v.accept);
  // the text of the ERROR the plugin stops with (Error::all adds the "ERROR: ")
  EXPECT_EQ(v.message.rfind("dembridge plugin was built for LAMMPS 20250722 but is loaded into LAMMPS 20230802 "
                            "(2 Aug 2023)", 0), 0u);
  EXPECT_NE(v.message.find("DEMBRIDGE_ALLOW_VERSION_MISMATCH"), std::string::npos);
}

TEST(VersionCheck, OverrideAcceptsWithWarning)
{
  const auto v = check_host_version(20250722, 20230802, "2 Aug 2023", "1");
  EXPECT_TRUE(v.accept);
  EXPECT_NE(v.message.find("WARNING"), std::string::npos);
}

TEST(VersionCheck, OverrideSetToZeroOrEmptyDoesNotCount)
{
  EXPECT_FALSE(check_host_version(20250722, 20230802, "2 Aug 2023", "0").accept);
  EXPECT_FALSE(check_host_version(20250722, 20230802, "2 Aug 2023", "").accept);
}

TEST(VersionCheck, LoadBannerNamesBothVersions)
{
  EXPECT_EQ(dembridge::lammps_date(20250722), "22 Jul 2025");
  EXPECT_EQ(dembridge::lammps_date(20230802), "2 Aug 2023");
  EXPECT_EQ(dembridge::lammps_date(20251399), "20251399");  // not a date: printed as is
  EXPECT_EQ(dembridge::load_banner("0.2.0", 20250722), "dembridge 0.2.0 loaded (built for LAMMPS 22 Jul 2025, 20250722)");
}
