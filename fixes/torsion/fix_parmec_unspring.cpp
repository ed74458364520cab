// fix parmec/unspring: LAMMPS glue for the UNSPRING kernels. See fix_parmec_unspring.h for the design.
#include "fix_parmec_unspring.h"
#include "command_args.h"

#include "fix_parmec_spring.h"
#include "style_registry.h"

#include "unspring_test.h"

#include "comm.h"
#include "error.h"
#include "modify.h"
#include "update.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

using namespace LAMMPS_NS;
using namespace LAMMPS_NS::FixConst;
namespace sp = dembridge::springs;
namespace ts = dembridge::torsion;

namespace dembridge {

namespace {

using args::is_number;

FixParmecSpring::Entity spring_entity(ts::Entity e)
{
  switch (e) {
    case ts::Entity::Stroke: return FixParmecSpring::Entity::Stroke;
    case ts::Entity::F: return FixParmecSpring::Entity::F;
    case ts::Entity::FF: return FixParmecSpring::Entity::FF;
    default: return FixParmecSpring::Entity::SF;
  }
}

}  // namespace

FixParmecUnspring::FixParmecUnspring(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), cmd_(std::string("fix ") + arg[0] + " parmec/unspring"),
    reader_(lmp, cmd_, state::DefinitionReader::kFile, "rule", "tseries, rule or file")
{
  if (narg < 5)
    error->all(FLERR, cmd_ + ": expected the ID of a fix parmec/spring, then definitions (tseries, rule, file)");
  spring_fix_id_ = arg[3];
  restart_global = 1;
  nevery = 1;
  static std::vector<std::shared_ptr<std::map<int, sp::TimeSeries>>> keep_alive;
  tseries_ = std::make_shared<std::map<int, sp::TimeSeries>>();
  keep_alive.push_back(tseries_);
  FixParmecSpring *sf = springs();

  reader_.parse(std::vector<std::string>(arg + 4, arg + narg), "command line",
                [this](const std::vector<std::string> &tok, std::size_t &i, const std::string &where) {
                  return parse_definition(tok, i, where);
                });
  if (rules_.empty()) error->all(FLERR, cmd_ + ": no rule defined (expected at least one 'rule' definition)");

  for (std::size_t r = 0; r < rules_.size(); r++) {
    const ts::UnspringRule &rule = rules_[r];
    const int index = static_cast<int>(r);
    try {
      rule.validate(index);
      ts::check_unload_curves(rule, index, [&](int id) -> const sp::TimeSeries * {
        auto it = tseries_->find(id);
        return it == tseries_->end() ? nullptr : &it->second;
      });
    } catch (std::invalid_argument &e) {
      error->all(FLERR, cmd_ + ": " + e.what());
    }
    auto known = [&](const std::vector<int> &ids, const char *list) {
      for (int id : ids)
        if (sf->spring_index(id) < 0)
          error->all(FLERR, fmt::format("{}: UNSPRING #{}: unknown spring ID {} in {} (not a spring of fix {})", cmd_,
                                        index, id, list, spring_fix_id_));
    };
    known(rule.tsprings, "tsprings");
    known(rule.msprings, "msprings");
    known(rule.activate, "activate");
  }
  for (auto &kv : *tseries_)
    if (!kv.second.is_constant()) sf->set_unspring_unload(kv.first, &kv.second.as_table("unload"));

  remaining_.resize(rules_.size());
  last_value_.assign(rules_.size(), 0.0);
  fired_at_.assign(rules_.size(), -1.0);
  for (std::size_t r = 0; r < rules_.size(); r++) remaining_[r] = rules_[r].nfreq;
  vector_flag = 1;  // per rule: remaining counter, last combined value, trigger step
  size_vector = 3 * static_cast<int>(rules_.size());
  global_freq = 1;
  extvector = 0;
}

FixParmecUnspring::~FixParmecUnspring() = default;

int FixParmecUnspring::setmask()
{
  return END_OF_STEP;
}

FixParmecSpring *FixParmecUnspring::springs()
{
  Fix *f = modify->get_fix_by_id(spring_fix_id_);
  if (!f)
    error->all(FLERR, cmd_ + ": fix ID '" + spring_fix_id_ + "' does not exist (define the fix parmec/spring first)");
  auto *sf = dynamic_cast<FixParmecSpring *>(f);
  if (!sf) error->all(FLERR, cmd_ + ": fix '" + spring_fix_id_ + "' is not a fix parmec/spring");
  return sf;
}

// ---------------------------------------------------------------------------------------------------
// parsing

bool FixParmecUnspring::parse_definition(const std::vector<std::string> &tok, std::size_t &i, const std::string &where)
{
  const std::string ctx = cmd_ + " (" + where + ")";
  auto number = [&](const std::string &s, const std::string &what) { return reader_.number(s, what, where); };
  auto integer = [&](const std::string &s, const std::string &what) { return reader_.integer(s, what, where); };
  auto ints = [&](std::vector<int> &out) {
    while (i < tok.size() && is_number(tok[i])) out.push_back(static_cast<int>(integer(tok[i++], "spring ID")));
  };
  const std::string kw = tok[i];
  if (kw == "tseries") {
    if (i + 1 >= tok.size()) error->all(FLERR, ctx + ": tseries needs an integer ID and values");
    const long id = integer(tok[i + 1], "tseries ID");
    if (id < 0) error->all(FLERR, ctx + ": tseries ID must be >= 0 (it is the state code SS while unloading)");
    std::vector<double> tv;
    i += 2;
    while (i < tok.size() && is_number(tok[i])) tv.push_back(number(tok[i++], "tseries value"));
    if (tseries_->count(static_cast<int>(id))) error->all(FLERR, ctx + ": tseries " + std::to_string(id) + ": ID defined twice");
    try {
      tseries_->emplace(static_cast<int>(id), tv.size() == 1 ? sp::TimeSeries::constant(tv[0]) : sp::TimeSeries::from_pairs(tv));
    } catch (std::invalid_argument &e) {
      error->all(FLERR, ctx + ": tseries " + std::to_string(id) + ": " + e.what());
    }
  } else if (kw == "rule") {
    ts::UnspringRule r;
    const std::string who = ctx + ": rule " + std::to_string(rules_.size());
    i++;
    bool limits = false;
    while (i < tok.size() && tok[i] != "rule" && tok[i] != "tseries" && tok[i] != "file") {
      const std::string o = tok[i++];
      auto need = [&](const char *what) -> const std::string & {
        if (i >= tok.size()) error->all(FLERR, who + ": " + o + " needs " + what);
        return tok[i++];
      };
      if (o == "tsprings") {
        ints(r.tsprings);
      } else if (o == "msprings") {
        ints(r.msprings);
      } else if (o == "activate") {
        ints(r.activate);
      } else if (o == "limits") {
        const std::string lo = need("MIN MAX (numbers or None)"), hi = need("MIN MAX (numbers or None)");
        r.min = (lo == "None" || lo == "none") ? -std::numeric_limits<double>::infinity() : number(lo, "limits min");
        r.max = (hi == "None" || hi == "none") ? std::numeric_limits<double>::infinity() : number(hi, "limits max");
        limits = true;
      } else if (o == "entity" || o == "operator") {
        const std::string v = need(o == "entity" ? "STROKE, F, SF or FF" : "SUM, MIN or MAX");
        try {
          if (o == "entity")
            r.entity = ts::parse_entity(v);
          else
            r.op = ts::parse_operator(v);
        } catch (std::invalid_argument &e) {
          error->all(FLERR, who + ": " + e.what());
        }
      } else if (o == "abs") {
        r.abs = true;
      } else if (o == "nsteps") {
        r.nsteps = integer(need("an integer"), "nsteps");
      } else if (o == "nfreq") {
        r.nfreq = static_cast<int>(integer(need("an integer"), "nfreq"));
      } else if (o == "unload") {
        r.unload = static_cast<int>(integer(need("a TSERIES ID"), "unload TSERIES ID"));
      } else if (o == "unload_map") {
        while (i + 1 < tok.size() && is_number(tok[i]) && is_number(tok[i + 1])) {
          const int s = static_cast<int>(integer(tok[i], "unload_map spring ID"));
          r.unload_by_spring[s] = static_cast<int>(integer(tok[i + 1], "unload_map TSERIES ID"));
          i += 2;
        }
      } else {
        error->all(FLERR, who + ": unknown word '" + o +
                              "' (expected tsprings, msprings, limits, entity, operator, abs, nsteps, nfreq, "
                              "unload, unload_map, activate)");
      }
    }
    if (!limits) error->all(FLERR, who + ": limits MIN MAX is required (None for an open side)");
    rules_.push_back(r);
  } else {
    return false;
  }
  return true;
}

// ---------------------------------------------------------------------------------------------------
// input effects (first run; a restarted fix has them in the restored spring states) and the per-step test

void FixParmecUnspring::init()
{
  FixParmecSpring *sf = springs();
  if (registered_) return;
  std::vector<double> ss;
  sf->gather_entity(FixParmecSpring::Entity::SS, ss);
  std::map<int, int> codes;
  for (int s = 0; s < sf->spring_count(); s++) codes[static_cast<int>(sf->spring_id(s))] = static_cast<int>(ss[s]);
  for (std::size_t r = 0; r < rules_.size(); r++) {
    try {
      ts::register_rule(rules_[r], static_cast<int>(r), codes);
    } catch (std::invalid_argument &e) {
      error->all(FLERR, cmd_ + ": " + e.what());
    }
  }
  for (const ts::UnspringRule &rule : rules_)
    for (int id : rule.msprings) sf->set_state_code(sf->spring_index(id), -2);
  start_ = update->ntimestep;
  registered_ = true;
}

void FixParmecUnspring::end_of_step()
{
  FixParmecSpring *sf = springs();
  const long step = static_cast<long>(update->ntimestep - start_ - 1);  // 0 = first force evaluation
  std::map<ts::Entity, std::vector<double>> gathered;
  for (std::size_t r = 0; r < rules_.size(); r++) {
    const ts::UnspringRule &rule = rules_[r];
    if (remaining_[r] <= 0 || step % rule.nsteps != 0) continue;
    auto it = gathered.find(rule.entity);
    if (it == gathered.end()) {
      it = gathered.emplace(rule.entity, std::vector<double>()).first;
      sf->gather_entity(spring_entity(rule.entity), it->second);
    }
    std::vector<double> values;
    values.reserve(rule.tsprings.size());
    for (int id : rule.tsprings) values.push_back(it->second[sf->spring_index(id)]);
    const ts::UnspringOutcome out = ts::unspring_test(rule, remaining_[r], step, values);
    if (out.tested) last_value_[r] = out.value;
    remaining_[r] = out.remaining;
    if (out.triggered) {
      fired_at_[r] = static_cast<double>(step);
      for (const auto &kv : out.new_codes) sf->set_state_code(sf->spring_index(kv.first), kv.second);
    }
  }
}

double FixParmecUnspring::compute_vector(int n)
{
  const int r = n / 3;
  if (n % 3 == 0) return remaining_[r];
  if (n % 3 == 1) return last_value_[r];
  return fired_at_[r];
}

// Global restart: the start step, and per rule the counter, the last value and the trigger step.
void FixParmecUnspring::write_restart(FILE *fp)
{
  std::vector<double> list;
  list.push_back(static_cast<double>(rules_.size()));
  list.push_back(static_cast<double>(start_));
  for (std::size_t r = 0; r < rules_.size(); r++) {
    list.push_back(remaining_[r]);
    list.push_back(last_value_[r]);
    list.push_back(fired_at_[r]);
  }
  if (comm->me == 0) {
    const int size = static_cast<int>(list.size() * sizeof(double));
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list.data(), sizeof(double), list.size(), fp);
  }
}

void FixParmecUnspring::restart(char *buf)
{
  const double *list = reinterpret_cast<const double *>(buf);
  if (static_cast<std::size_t>(list[0]) != rules_.size())
    error->all(FLERR, cmd_ + ": the restart file holds a different number of rules (define the same rules)");
  start_ = static_cast<bigint>(list[1]);
  for (std::size_t r = 0; r < rules_.size(); r++) {
    remaining_[r] = static_cast<int>(list[2 + 3 * r]);
    last_value_[r] = list[3 + 3 * r];
    fired_at_[r] = list[4 + 3 * r];
  }
  registered_ = true;  // the msprings' -2 codes are in the restored spring states
}

static RegisterStyle reg_fix_parmec_unspring("fix", "parmec/unspring",
                                             "Parmec UNSPRING: conditional unloading, removal and activation of springs",
                                             create_fix<FixParmecUnspring>);

}  // namespace dembridge
