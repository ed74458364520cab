// One grammar for a number in a command: the LAMMPS-free parsers' reader (math/number_word.h) accepts
// exactly the words LAMMPS's utils::is_double and utils::is_integer accept, and reads the value utils::numeric
// does; the glue reads through utils, so `pair_modify timestep_check 0x1` (strtod's hex) is now an ERROR
// naming the command, the argument and what was expected.
#include "lammps_fixture.h"

#include "math/number_word.h"
#include "utils.h"

namespace {

const char *const kWords[] = {"0", "-7", "+3", "1.5", "-.5", "5.", ".", "1e5", "1E-3", "2.5e+07", "-1.e2", "e5", "1e",
                              "1e+", "1.2.3", "0x1A", "inf", "-inf", "nan", "NaN", "1e999", " 1", "1 ", "", "+", "-",
                              "1d5", "12abc", "007", "99999999999999999999", "1,5", "--1"};

}  // namespace

TEST(NumberWords, SameGrammarAsLammpsUtils)
{
  for (const char *w : kWords) {
    EXPECT_EQ(dembridge::math::is_number_word(w), LAMMPS_NS::utils::is_double(w)) << "'" << w << "'";
    EXPECT_EQ(dembridge::math::is_integer_word(w), LAMMPS_NS::utils::is_integer(w)) << "'" << w << "'";
    double v = 0.0;
    if (dembridge::math::read_number(w, v)) {
      EXPECT_EQ(v, LAMMPS_NS::utils::numeric(__FILE__, __LINE__, w, false, nullptr)) << w;
    }
  }
  double v = 0.0;
  EXPECT_FALSE(dembridge::math::read_number("1e999", v));  // a number to utils, but not finite
  long long n = 0;
  EXPECT_FALSE(dembridge::math::read_integer("99999999999999999999", n));  // beyond long long
  EXPECT_TRUE(dembridge::math::read_integer("-42", n));
  EXPECT_EQ(n, -42);
}

TEST_F(LammpsWithPlugin, TimestepCheckFractionReadByUtils)
{
  ok("units si");
  ok("atom_style sphere");
  ok("region box block 0 1 0 1 0 1");
  ok("create_box 1 box");
  ok("pair_style gran/hooke/history 1000 NULL 0 NULL 0.5 0");
  ok("pair_coeff * *");
  ok("pair_modify timestep_check 0.5");
  const std::string e = cmd("pair_modify timestep_check 0x1");
  EXPECT_NE(e.find("pair_modify timestep_check"), std::string::npos) << e;
  EXPECT_NE(e.find("a fraction of the Rayleigh/Hertz time"), std::string::npos) << e;
  EXPECT_NE(e.find("got '0x1'"), std::string::npos) << e;
}
