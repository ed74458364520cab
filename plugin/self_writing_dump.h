// The base of the plugin's dump styles: each writes a whole frame in write(), so the per-atom
// machinery of liblammps's Dump (header, pack, write_data) is never used.
#pragma once

#include "lammps_dump_base.h"

namespace dembridge {

class SelfWritingDump : public LAMMPS_NS::Dump {
 public:
  using LAMMPS_NS::Dump::Dump;

 protected:
  void write_header(LAMMPS_NS::bigint) override {}
  void pack(LAMMPS_NS::tagint *) override {}
  void write_data(int, double *) override {}
};

}  // namespace dembridge
