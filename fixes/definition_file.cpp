#include "definition_file.h"

#include "comm.h"
#include "error.h"

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

}  // namespace dembridge
