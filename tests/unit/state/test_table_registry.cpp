// TableRegistry of the Parmec-style definitions (their words are read by LAMMPS's utils: fixes/command_args.h).
#include "table_registry.h"

#include <gtest/gtest.h>

#include <stdexcept>

using namespace dembridge::state;

TEST(TableRegistry, DefinesLooksUpAndRejectsTwice)
{
  TableRegistry r;
  r.define_table("K", {-1, -100, 1, 100});
  r.define_tseries("C", {2.5});
  r.define_tseries("T", {0, 0, 1, 2});
  ASSERT_NE(r.table("K"), nullptr);
  EXPECT_EQ(r.table("K")->lookup(0.5).value, 50.0);
  EXPECT_EQ(r.table("X"), nullptr);
  ASSERT_NE(r.tseries("C"), nullptr);
  EXPECT_TRUE(r.tseries("C")->is_constant());
  EXPECT_EQ(r.tseries("T")->value_clamped(0.5), 1.0);
  EXPECT_EQ(r.tseries("K"), nullptr);  // tables and TSERIES are separate name spaces
  const dembridge::springs::SpringTable *k = r.table("K");
  r.define_table("L", {0, 0, 1, 1});
  EXPECT_EQ(r.table("K"), k);  // pointers stay valid as definitions are added
  EXPECT_THROW(r.define_table("K", {0, 0, 1, 1}), std::invalid_argument);
  EXPECT_THROW(r.define_tseries("T", {3}), std::invalid_argument);
  EXPECT_THROW(r.define_table("Z", {0, 0, 1}), std::invalid_argument);  // the table's own rule
}
