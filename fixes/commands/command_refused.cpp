// LIGGGHTS 3.8 input commands with no LAMMPS counterpart: an ERROR that says what to use instead
// (LAMMPS alone would stop with a bare "Unknown command").
#include "style_registry.h"

#include "command.h"
#include "error.h"

#include <string>

using namespace LAMMPS_NS;

namespace dembridge {

namespace {

template <const char *Name, const char *Instead> class CommandRefused : public Command {
 public:
  explicit CommandRefused(LAMMPS *lmp) : Command(lmp) {}
  void command(int, char **) override
  {
    error->all(FLERR, std::string(Name) + ": LIGGGHTS's command '" + Name + "' is not available: " + Instead);
  }
};

template <const char *Name, const char *Instead> void *create(void *lmp)
{
  return new CommandRefused<Name, Instead>(static_cast<LAMMPS *>(lmp));
}

constexpr char kThermoLog[] = "thermo_log";
constexpr char kThermoLogInstead[] =
    "write the thermo quantities to a file with fix print (or fix ave/time ... file NAME)";
constexpr char kModifyTiming[] = "modify_timing";
constexpr char kModifyTimingInstead[] = "LAMMPS's 'timer full' prints the time spent per part of the step";

}  // namespace

static RegisterStyle reg_thermo_log("command", kThermoLog, "LIGGGHTS thermo_log (refused)",
                                    create<kThermoLog, kThermoLogInstead>);
static RegisterStyle reg_modify_timing("command", kModifyTiming, "LIGGGHTS modify_timing (refused)",
                                       create<kModifyTiming, kModifyTimingInstead>);

}  // namespace dembridge
