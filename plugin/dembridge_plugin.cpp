// lammpsplugin_init: the only exported symbol. Checks the host version, then registers every
// style collected in the style registry.
#include "mpi_flavour.h"
#include "plugin_abi.h"
#include "style_registry.h"
#include "version_check.h"

#include "comm.h"
#include "error.h"
#include "lammps.h"
#include "modify.h"
#include "output.h"
#include "utils.h"

#include <cstdlib>
#include <cstring>

namespace dembridge {
std::vector<StyleEntry> &style_registry()
{
  static std::vector<StyleEntry> entries;
  return entries;
}

void register_dump_styles(LAMMPS_NS::LAMMPS *lmp)
{
  for (const auto &e : style_registry())
    if (std::strcmp(e.kind, "dump") == 0)
      (*lmp->output->dump_map)[e.name] = reinterpret_cast<LAMMPS_NS::Output::DumpCreator>(e.v2);
}
}  // namespace dembridge


extern "C" __attribute__((visibility("default"))) void lammpsplugin_init(void *lmp, void *handle, void *regfunc)
{
  auto *host = static_cast<LAMMPS_NS::LAMMPS *>(lmp);
  const auto verdict = dembridge::check_host_version(DEMBRIDGE_LAMMPS_NUM_VER, host->num_ver, host->version,
                                                     std::getenv("DEMBRIDGE_ALLOW_VERSION_MISMATCH"));
  // logmesg writes on every rank that has a screen during plugin auto-load: print once
  const bool first_rank = host->comm->me == 0;
  // a refusal stops the deck (an exception in Python); before it, nothing of the plugin ran but this check
  if (!verdict.accept) host->error->all(FLERR, verdict.message);
  if (!verdict.message.empty() && first_rank) LAMMPS_NS::utils::logmesg(host, verdict.message + "\n");
  // regfunc is LAMMPS's plugin_register: in liblammps, whose dependencies name the MPI it runs on
  const auto host_mpi = dembridge::mpi_of_object(regfunc);
  const auto mpi_why = dembridge::mpi_mismatch_message(dembridge::mpi_flavour_from_name(DEMBRIDGE_MPI_FLAVOUR),
                                                       host_mpi.flavour, host_mpi.object);
  if (!mpi_why.empty()) host->error->all(FLERR, mpi_why);  // liblammps's own MPI reports it: no call of ours
  if (first_rank)
    LAMMPS_NS::utils::logmesg(host, dembridge::load_banner(DEMBRIDGE_VERSION, DEMBRIDGE_LAMMPS_NUM_VER) + "\n");

  auto reg = reinterpret_cast<dembridge_regfunc>(regfunc);
  for (const auto &e : dembridge::style_registry()) {
    if (std::strcmp(e.kind, "dump") == 0) {  // see register_dump_styles()
      if (first_rank) LAMMPS_NS::utils::logmesg(host, std::string("Loading plugin: ") + e.info + " by dembridge developers\n");
      continue;
    }
    if (e.builtin && host->modify->fix_map) {  // remember the built-in fix this style overrides
      auto it = host->modify->fix_map->find(e.name);
      if (it != host->modify->fix_map->end() && reinterpret_cast<void *>(it->second) != reinterpret_cast<void *>(e.v2))
        *e.builtin = reinterpret_cast<dembridge::FixFactory>(it->second);
    }
    dembridge_plugin_t p{};
    p.version = host->version;  // accepted: avoid the loader's "compiled for" notice
    p.style = e.kind;
    p.name = e.name;
    p.info = e.info;
    p.author = "dembridge developers";
    if (e.v1) p.creator.v1 = reinterpret_cast<dembridge_factory1 *>(e.v1);
    else p.creator.v2 = reinterpret_cast<dembridge_factory2 *>(e.v2);
    p.handle = handle;
    reg(&p, lmp);
  }
  dembridge::register_dump_styles(host);
}
