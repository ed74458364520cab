// Option parsing of the Parmec-style fixes, written once (doc/per_atom_state.md): the keyword loop, the
// common keywords (table, tseries, file, history, start), numbers and integers with ERRORs naming the
// command, the argument and what was expected, and the reading of one entity definition.
#pragma once

#include "table_registry.h"

#include "pointers.h"

#include <functional>
#include <stdexcept>
#include <string>
#include <unordered_set>
#include <vector>

namespace dembridge::state {

class DefinitionReader : protected LAMMPS_NS::Pointers {
 public:
  // Common keywords a fix accepts (bit set).
  enum : unsigned { kTable = 1, kTseries = 2, kFile = 4, kHistory = 8, kStart = 16 };
  using Words = std::vector<std::string>;
  // Reads a fix-specific keyword at tok[i] and advances i past it; false: not one of this fix's keywords.
  using Handler = std::function<bool(const Words &tok, std::size_t &i, const std::string &where)>;

  // cmd: "fix ID style" (prefix of every message). entity: what the fix defines ("spring", "torsion
  // spring"). expected: the keyword list for the unknown-keyword message.
  DefinitionReader(LAMMPS_NS::LAMMPS *lmp, std::string cmd, unsigned common, std::string entity, std::string expected);

  // The keyword loop over tok ('file FILE' recurses with where = "file FILE").
  void parse(const Words &tok, const std::string &where, const Handler &handler);

  // "<cmd> (<where>): <what>: expected a finite number, got '<s>'"
  double number(const std::string &s, const std::string &what, const std::string &where) const;
  // "<cmd> (<where>): <what>: expected an integer, got '<s>'"
  long integer(const std::string &s, const std::string &what, const std::string &where) const;
  // tok[i + 1] must be one of choices (i advanced by 2); returns its position in choices.
  int choice(const Words &tok, std::size_t &i, const std::string &where, const std::vector<std::string> &choices) const;
  // Error unless tok has n words after tok[i].
  void need(const Words &tok, std::size_t i, std::size_t n, const std::string &what, const std::string &where) const;

  // Resolution after parsing; errors "<who><role> table ID '<id>' is not defined (...)".
  const springs::SpringTable *table(const std::string &id, const std::string &who, const std::string &role) const;
  const springs::TimeSeries *tseries(const std::string &id, const std::string &who, const std::string &role) const;

  LAMMPS_NS::LAMMPS *lammps() const { return lmp; }
  const std::string &cmd() const { return cmd_; }
  const std::string &entity() const { return entity_; }
  TableRegistry tables;
  struct History {
    std::string file;
    int every = 0;  // 0: no history
    std::vector<long> ids;
  } history;
  bool parmec_start = false;  // 'start parmec': no force before the first committed step

 private:
  std::string cmd_, entity_, expected_;
  unsigned common_;
  void table_or_tseries(const Words &tok, std::size_t &i, const std::string &where);
  void history_request(const Words &tok, std::size_t &i, const std::string &where);
};

// One entity definition ('spring SID ...', 'torsion SID ...') being read: the next word, integers, the
// entity ID and atom IDs, each ERROR naming the entity and the usage.
class EntityWords : protected LAMMPS_NS::Pointers {
 public:
  // tok[i] is the entity keyword; usage: "spring SID part1 ... [options]" for "missing" messages.
  EntityWords(const DefinitionReader &reader, const DefinitionReader::Words &tok, std::size_t i,
              const std::string &where, std::string usage);

  const std::string &next(const std::string &what);
  bool more() const { return k_ < tok_.size(); }
  const std::string &peek() const { return tok_[k_]; }
  long integer(const std::string &s, const std::string &what) const;
  double number(const std::string &s, const std::string &what) const { return reader_.number(s, what, where_); }
  // The entity ID (unique within `ids`); sets who() to "<ctx> <id>".
  long id(std::unordered_set<long> &ids);
  // part1 (>= 1) and part2 (>= 1, or -1 with meaning anchor, e.g. "spatial anchor"); distinct.
  long part1();
  long part2(long part1, const std::string &anchor);
  const std::string &ctx() const { return ctx_; }   // "<cmd> (<where>): <entity keyword>"
  const std::string &who() const { return who_; }   // "<ctx> <id>"
  [[noreturn]] void fail(const std::string &msg) const;  // ERROR "<who>: <msg>"
  // Runs f; a std::invalid_argument it throws (a kernel's validation) becomes fail(what).
  template <class F> void check(F &&f) const
  {
    try {
      f();
    } catch (std::invalid_argument &e) {
      fail(e.what());
    }
  }
  // The definition was read: i moves past it; returns true (the handler's answer).
  bool accept(std::size_t &i) const
  {
    i = k_;
    return true;
  }

 private:
  const DefinitionReader &reader_;
  const DefinitionReader::Words &tok_;
  std::size_t k_;
  std::string where_, usage_, ctx_, who_;
};

}  // namespace dembridge::state
