#include "definition_reader.h"
#include "command_args.h"

#include "definition_file.h"

#include "error.h"

#include <cmath>
#include <stdexcept>

using namespace LAMMPS_NS;

namespace dembridge::state {

DefinitionReader::DefinitionReader(LAMMPS *lmp, std::string cmd, unsigned common, std::string entity,
                                   std::string expected) :
    Pointers(lmp), cmd_(std::move(cmd)), entity_(std::move(entity)), expected_(std::move(expected)), common_(common)
{
}

void DefinitionReader::need(const Words &tok, std::size_t i, std::size_t n, const std::string &what,
                            const std::string &where) const
{
  if (i + n >= tok.size())
    error->all(FLERR, cmd_ + " (" + where + "): '" + tok[i] + "' needs " + what + ", the arguments ended");
}

double DefinitionReader::number(const std::string &s, const std::string &what, const std::string &where) const
{
  double v;
  if (!args::parse_double(lmp, s, v))
    error->all(FLERR, cmd_ + " (" + where + "): " + what + ": expected a finite number, got '" + s + "'");
  return v;
}

long DefinitionReader::integer(const std::string &s, const std::string &what, const std::string &where) const
{
  long v;
  if (!args::parse_long(lmp, s, v))
    error->all(FLERR, cmd_ + " (" + where + "): " + what + ": expected an integer, got '" + s + "'");
  return v;
}

int DefinitionReader::choice(const Words &tok, std::size_t &i, const std::string &where,
                             const std::vector<std::string> &choices) const
{
  std::string list;
  for (std::size_t c = 0; c < choices.size(); c++)
    list += (c == 0 ? "" : (c + 1 == choices.size() ? " or " : ", ")) + ("'" + choices[c] + "'");
  need(tok, i, 1, list, where);
  for (std::size_t c = 0; c < choices.size(); c++)
    if (tok[i + 1] == choices[c]) {
      i += 2;
      return static_cast<int>(c);
    }
  error->all(FLERR, cmd_ + " (" + where + "): " + tok[i] + ": expected " + list + ", got '" + tok[i + 1] + "'");
  return -1;
}

void DefinitionReader::parse(const Words &tok, const std::string &where, const Handler &handler)
{
  std::size_t i = 0;
  while (i < tok.size()) {
    const std::string &kw = tok[i];
    if ((kw == "table" && (common_ & kTable)) || (kw == "tseries" && (common_ & kTseries))) {
      table_or_tseries(tok, i, where);
    } else if (kw == "file" && (common_ & kFile)) {
      need(tok, i, 1, "a file name", where);
      const std::string path = tok[i + 1];
      parse_definition_file(lmp, path, cmd_, [&](const Words &words, const std::string &w) { parse(words, w, handler); });
      i += 2;
    } else if (kw == "history" && (common_ & kHistory)) {
      history_request(tok, i, where);
    } else if (kw == "start" && (common_ & kStart)) {
      parmec_start = choice(tok, i, where, {"lammps", "parmec"}) == 1;
    } else if (!handler(tok, i, where)) {
      error->all(FLERR, cmd_ + " (" + where + "): unknown keyword '" + kw + "' (expected " + expected_ + ")");
    }
  }
}

void DefinitionReader::table_or_tseries(const Words &tok, std::size_t &i, const std::string &where)
{
  const std::string kw = tok[i];
  need(tok, i, 1, "an ID and values", where);
  const std::string tid = tok[i + 1];
  if (args::is_number(tid)) error->all(FLERR, cmd_ + " (" + where + "): " + kw + " ID '" + tid + "' must not be a number");
  std::vector<double> xy;
  i += 2;
  while (i < tok.size() && args::is_number(tok[i])) xy.push_back(number(tok[i++], kw + " " + tid + " value", where));
  const std::string who = cmd_ + " (" + where + "): " + kw + " " + tid + ": ";
  if (kw == "table" ? tables.table(tid) != nullptr : tables.tseries(tid) != nullptr)
    error->all(FLERR, who + "ID defined twice");
  try {
    if (kw == "table")
      tables.define_table(tid, xy);
    else
      tables.define_tseries(tid, xy);
  } catch (std::invalid_argument &e) {
    error->all(FLERR, who + e.what() + " (expected x1 y1 x2 y2 ... with at least 2 points, x strictly increasing)");
  }
}

void DefinitionReader::history_request(const Words &tok, std::size_t &i, const std::string &where)
{
  const std::string ctx = cmd_ + " (" + where + "): history: ";
  need(tok, i, 2, "a file name, an interval N and " + entity_ + " IDs", where);
  history.file = tok[i + 1];
  const double every = number(tok[i + 2], "history interval N", where);
  if (every < 1 || every != std::floor(every))
    error->all(FLERR, ctx + "interval N must be an integer >= 1, got '" + tok[i + 2] + "'");
  history.every = static_cast<int>(every);
  i += 3;
  while (i < tok.size() && args::is_number(tok[i]))
    history.ids.push_back(std::lround(number(tok[i++], "history " + entity_ + " ID", where)));
  if (history.ids.empty()) error->all(FLERR, ctx + "expected at least one " + entity_ + " ID after the interval");
}

// A resolved ID, or the ERROR "<who><role> <kind> ID '<id>' is not defined (expected the ID of a '<kw>' ...)".
template <class T> static const T *resolved(Error *error, const T *found, const std::string &id, const std::string &who,
                                            const std::string &role, const char *kind, const char *keyword)
{
  if (!found)
    error->all(FLERR, who + role + " " + kind + " ID '" + id + "' is not defined (expected the ID of a '" + keyword +
                          "' definition)");
  return found;
}

const springs::SpringTable *DefinitionReader::table(const std::string &id, const std::string &who,
                                                    const std::string &role) const
{
  return resolved(error, tables.table(id), id, who, role, "table", "table");
}

const springs::TimeSeries *DefinitionReader::tseries(const std::string &id, const std::string &who,
                                                     const std::string &role) const
{
  return resolved(error, tables.tseries(id), id, who, role, "TSERIES", "tseries");
}

// ---------------------------------------------------------------------------------------------------

EntityWords::EntityWords(const DefinitionReader &reader, const DefinitionReader::Words &tok, std::size_t i,
                         const std::string &where, std::string usage) :
    Pointers(reader.lammps()), reader_(reader), tok_(tok), k_(i + 1), where_(where), usage_(std::move(usage)),
    ctx_(reader.cmd() + " (" + where + "): " + tok[i]), who_(ctx_)
{
}

const std::string &EntityWords::next(const std::string &what)
{
  if (k_ >= tok_.size()) error->all(FLERR, ctx_ + ": missing " + what + " (expected: " + usage_ + ")");
  return tok_[k_++];
}

long EntityWords::integer(const std::string &s, const std::string &what) const
{
  long v;
  if (!args::parse_long(lmp, s, v)) error->all(FLERR, ctx_ + ": " + what + ": expected an integer, got '" + s + "'");
  return v;
}

void EntityWords::fail(const std::string &msg) const
{
  error->all(FLERR, who_ + ": " + msg);
}

long EntityWords::id(std::unordered_set<long> &ids)
{
  const std::string what = reader_.entity() + " ID";
  const long v = integer(next(what), what);
  who_ = ctx_ + " " + std::to_string(v);
  if (!ids.insert(v).second) fail(what + " defined twice");
  return v;
}

long EntityWords::part1()
{
  const long t = integer(next("part1 atom ID"), "part1 atom ID");
  if (t < 1) fail("part1 atom ID must be >= 1, got " + std::to_string(t));
  return t;
}

long EntityWords::part2(long part1, const std::string &anchor)
{
  const long t = integer(next("part2 atom ID"), "part2 atom ID");
  if (t < 1 && t != -1) fail("part2 atom ID must be >= 1 or -1 (" + anchor + "), got " + std::to_string(t));
  if (t == part1) fail("part1 and part2 are the same atom");
  return t;
}

}  // namespace dembridge::state
