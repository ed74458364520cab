#include "definition_file.h"

#include "comm.h"
#include "error.h"

#include <cstdlib>
#include <fstream>
#include <mpi.h>
#include <sstream>

namespace dembridge {

std::vector<std::string> read_definition_words(LAMMPS_NS::LAMMPS *lmp, const std::string &path, const std::string &command)
{
  std::string text;
  int ok = 1;
  if (lmp->comm->me == 0) {
    std::ifstream in(path);
    if (!in) {
      ok = 0;
    } else {
      std::ostringstream ss;
      std::string line;
      while (std::getline(in, line)) {
        const auto hash = line.find('#');
        if (hash != std::string::npos) line.resize(hash);
        ss << line << '\n';
      }
      text = ss.str();
    }
  }
  MPI_Bcast(&ok, 1, MPI_INT, 0, lmp->world);
  if (!ok) lmp->error->all(FLERR, command + ": file '" + path + "' cannot be opened");
  long len = text.size();
  MPI_Bcast(&len, 1, MPI_LONG, 0, lmp->world);
  text.resize(len);
  if (len > 0) MPI_Bcast(&text[0], static_cast<int>(len), MPI_CHAR, 0, lmp->world);
  std::vector<std::string> words;
  std::istringstream is(text);
  std::string w;
  while (is >> w) words.push_back(w);
  return words;
}

namespace {
// The files being parsed, outermost first (one chain at a time: fix commands are parsed one after the other)
std::vector<std::pair<std::string, std::string>> &open_files()
{
  static std::vector<std::pair<std::string, std::string>> chain;  // (identity, path as written)
  return chain;
}

// The file's canonical path, or the path as written when it does not resolve. POSIX realpath, not
// std::filesystem: the wheel keeps to the C++ library of manylinux_2_24 systems (gcc 6's, without it).
std::string identity(const std::string &path)
{
  char *real = ::realpath(path.c_str(), nullptr);
  if (!real) return path;
  const std::string id(real);
  std::free(real);
  return id;
}
}  // namespace

void parse_definition_file(LAMMPS_NS::LAMMPS *lmp, const std::string &path, const std::string &command,
                           const std::function<void(const std::vector<std::string> &, const std::string &)> &parse)
{
  auto &chain = open_files();
  const std::string id = identity(path);
  for (const auto &open : chain)
    if (open.first == id) {
      std::string names;
      for (const auto &o : chain) names += "'" + o.second + "' -> ";
      lmp->error->all(FLERR, command + ": file '" + path + "' includes itself (" + names + "'" + path +
                                 "'): a definition file cannot be read again while it is being read");
    }
  chain.emplace_back(id, path);
  struct Pop {
    std::vector<std::pair<std::string, std::string>> &c;
    ~Pop() { c.pop_back(); }  // also when an ERROR unwinds the parse
  } pop{chain};
  parse(read_definition_words(lmp, path, command), "file " + path);
}

}  // namespace dembridge
