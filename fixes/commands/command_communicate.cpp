// communicate single|multi [cutoff Rc] [group ID] [vel yes|no]: LIGGGHTS 3.8's (and LAMMPS 2.x's)
// name of comm_modify, as a command style: the style becomes comm_modify's 'mode', the keywords
// pass through unchanged (comm_modify checks them and names a bad one).
#include "style_registry.h"

#include "comm.h"
#include "command.h"
#include "error.h"

#include <string>
#include <vector>

using namespace LAMMPS_NS;

namespace dembridge {

namespace {

class CommandCommunicate : public Command {
 public:
  explicit CommandCommunicate(LAMMPS *lmp) : Command(lmp) {}
  void command(int narg, char **arg) override
  {
    register_dump_styles(lmp);  // dump custom/vtk etc. in this LAMMPS instance (style_registry.h)
    if (narg < 1)
      error->all(FLERR, "communicate: expected a style, 'single' or 'multi' (communicate single vel yes)");
    const std::string style = arg[0];
    if (style != "single" && style != "multi")
      error->all(FLERR, "communicate: style '" + style + "': expected 'single' or 'multi'");
    std::vector<std::string> words = {"mode", style};
    for (int i = 1; i < narg; ++i) words.emplace_back(arg[i]);
    std::vector<char *> args;
    for (auto &w : words) args.push_back(w.data());
    comm->modify_params(static_cast<int>(args.size()), args.data());
  }
};

void *create(void *lmp) { return new CommandCommunicate(static_cast<LAMMPS *>(lmp)); }

}  // namespace

static RegisterStyle reg_communicate("command", "communicate", "LIGGGHTS communicate (= comm_modify mode ...)", create);

}  // namespace dembridge
