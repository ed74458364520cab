#include "dump_modify_snapshot.h"

#include <cstring>

namespace dembridge {

std::vector<unsigned char> dump_modify_snapshot(const LAMMPS_NS::Dump *dump)
{
  std::vector<unsigned char> bytes;
#ifdef DEMBRIDGE_DUMP_MODIFY_FIELDS
  const auto *base = reinterpret_cast<const unsigned char *>(dump);
  for (const auto &f : LAMMPS_NS::dump_modify_fields) bytes.insert(bytes.end(), base + f.offset, base + f.offset + f.size);
#else
  (void)dump;
#endif
  return bytes;
}

const char *changed_dump_modify_keyword(const LAMMPS_NS::Dump *dump, const std::vector<unsigned char> &snapshot)
{
#ifdef DEMBRIDGE_DUMP_MODIFY_FIELDS
  const std::vector<unsigned char> now = dump_modify_snapshot(dump);
  std::size_t at = 0;
  for (const auto &f : LAMMPS_NS::dump_modify_fields) {
    if (std::memcmp(now.data() + at, snapshot.data() + at, f.size) != 0) return f.keyword;
    at += f.size;
  }
#else
  (void)dump;
  (void)snapshot;
#endif
  return nullptr;
}

}  // namespace dembridge
