#include "per_atom_state_fix.h"
#include "lammps_compat.h"
#include "rank_error.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "memory.h"
#include "modify.h"
#include "neighbor.h"
#include "update.h"
#include "utils.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_map>

using namespace LAMMPS_NS;

namespace dembridge::state {

PerAtomStateFix::PerAtomStateFix(LAMMPS *lmp, int narg, char **arg, int record_size) :
    PerAtomRecordsFix(lmp, narg, arg, record_size)
{
  restart_global = 1;
}

PerAtomStateFix::~PerAtomStateFix()
{
  memory->destroy(array_local);
}

void PerAtomStateFix::define_entities(const std::string &noun, const std::vector<long> &ids,
                                      const std::vector<std::pair<long, long>> &atoms, int width)
{
  if (ids.empty()) error->all(FLERR, cmd_ + ": no " + noun + " defined (expected at least one definition)");
  noun_ = noun;
  ids_ = ids;
  atoms_ = atoms;
  by_first_.clear();
  two_atom_ = false;
  std::size_t most = 0;
  for (std::size_t key = 0; key < atoms.size(); key++) {
    std::vector<int> &keys = by_first_[atoms[key].first];
    keys.push_back(static_cast<int>(key));
    most = std::max(most, keys.size());
    if (atoms[key].second >= 0) two_atom_ = true;
  }
  set_records_per_atom(static_cast<int>(most));
  comm_reverse = sums_.configure(width, atoms);
}

void PerAtomStateFix::initial_records(const std::function<void(int key, double *rec)> &init)
{
  for (int i = 0; i < atom->nlocal; i++) {
    records_.clear(i);
    auto it = by_first_.find(atom->tag[i]);
    if (it == by_first_.end()) continue;
    for (int key : it->second) init(key, records_.append(i, key));
  }
}

std::vector<AtomSnapshot> PerAtomStateFix::snapshot_entity_atoms()
{
  std::vector<long> tags;
  for (const auto &a : atoms_) {
    tags.push_back(a.first);
    tags.push_back(a.second);
  }
  std::vector<AtomSnapshot> snap = snapshot_atoms(lmp, tags);
  for (std::size_t key = 0; key < atoms_.size(); key++)
    for (int side = 0; side < 2; side++) {
      const long tag = side == 0 ? atoms_[key].first : atoms_[key].second;
      if (tag >= 0 && !snap[2 * key + side].found)
        error->all(FLERR, fmt::format("{}: {}: part{} atom ID {} does not exist (unknown atom ID)", cmd_,
                                      who(static_cast<int>(key)), side + 1, tag));
    }
  return snap;
}

void PerAtomStateFix::second_atom_missing(int key, const char *hint)
{
  fail_on_this_rank(lmp, FLERR, fmt::format("{}: {}: part2 atom {} is not available to the owner of part1 atom {} (not a ghost, "
                                            "or lost): raise 'comm_modify cutoff'{}", cmd_, who(key), atoms_[key].second,
                                            atoms_[key].first, hint));
}

int PerAtomStateFix::second_atom(int key, int i, bool closest_image, const char *hint)
{
  const int k = second_atom_or_missing(key, i, closest_image);
  if (k < 0) second_atom_missing(key, hint);
  return k;
}

bool PerAtomStateFix::restored_record_fits(int i, const double *rec) const
{
  const long key = static_cast<long>(rec[0]);
  return key >= 0 && key < static_cast<long>(atoms_.size()) && atoms_[key].first == atom->tag[i];
}

// Records read from a restart file must belong to the definitions.
void PerAtomStateFix::check_restored(int i)
{
  for (int r = 0; r < records_.count(i); r++)
    if (!restored_record_fits(i, records_.record(i, r)))
      fail_on_this_rank(lmp, FLERR, fmt::format("{}: restart file holds {} states that do not match the definitions (define the "
                                                "same {}s in the same order as before write_restart)", cmd_, noun_, noun_));
}

// ---------------------------------------------------------------------------------------------------
// ghost contributions

int PerAtomStateFix::pack_reverse_comm(int n, int first, double *buf)
{
  return sums_.pack(n, first, buf);
}

void PerAtomStateFix::unpack_reverse_comm(int n, int *list, double *buf)
{
  if (!sums_.unpack(n, list, buf)) fail_on_this_rank(lmp, FLERR, cmd_ + ": internal error: too many contributions to one atom");
}

void PerAtomStateFix::reset_sums()
{
  sums_.reset(atom->nlocal + atom->nghost);
}

void PerAtomStateFix::contribution_overflow()
{
  fail_on_this_rank(lmp, FLERR, cmd_ + ": internal error: too many contributions on one atom");
}

void PerAtomStateFix::collect_sums()
{
  if (two_atom_) comm->reverse_comm(this);
}

// ---------------------------------------------------------------------------------------------------
// checks

void PerAtomStateFix::check_run_style_and_ghosts(const std::string &ghost_velocities)
{
  if (update->integrate_style && std::strncmp(update->integrate_style, "respa", 5) == 0)
    error->all(FLERR, cmd_ + " does not support run_style respa (use run_style verlet)");
  if (two_atom_ && atom->map_style == Atom::MAP_NONE)
    error->all(FLERR, cmd_ + " needs an atom map (atom_modify map array or hash) to find part2 atoms");
  if (two_atom_ && !comm->ghost_velocity)
    error->all(FLERR, cmd_ + ": " + ghost_velocities + ": use 'comm_modify vel yes'");
}

void PerAtomStateFix::check_record_count()
{
  const long expected = static_cast<long>(atoms_.size());
  const std::string &noun = noun_;
  bigint mine = records_.total(atom->nlocal), total = 0;
  MPI_Allreduce(&mine, &total, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  if (total != static_cast<bigint>(expected))
    error->all(FLERR, cmd_ + ": " + std::to_string(total) + " " + noun + " states for " + std::to_string(expected) +
                          " " + noun + "s (an atom of a " + noun +
                          " was deleted, or the restart file does not match)");
}

PerAtomStateFix::Farthest PerAtomStateFix::farthest_beyond(double cutoff)
{
  const bool periodic = domain->xperiodic || domain->yperiodic || domain->zperiodic;
  struct {
    double distance;
    int key;
  } worst{0.0, -1}, gworst{0.0, -1};
  for (int i = 0; i < atom->nlocal; i++)
    for (int r = 0; r < records_.count(i); r++) {
      const long tag2 = atoms_[records_.key(i, r)].second;
      if (tag2 < 0) continue;
      int k = atom->map(tag2);
      if (k < 0) continue;  // the evaluation reports it with the atom IDs
      if (periodic) k = domain->closest_image(i, k);
      const double dx = atom->x[k][0] - atom->x[i][0], dy = atom->x[k][1] - atom->x[i][1],
                   dz = atom->x[k][2] - atom->x[i][2];
      const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
      if (d > cutoff && d > worst.distance) worst = {d, records_.key(i, r)};
    }
  MPI_Allreduce(&worst, &gworst, 1, MPI_DOUBLE_INT, MPI_MAXLOC, world);
  return {gworst.key, gworst.distance};
}

// ---------------------------------------------------------------------------------------------------
// reach of the second atoms (see the header). Cost: nothing while every pair stays within near_of(cutoff) but
// one flag reduction per re-neighbouring; beyond it one forward communication and a pass over the entities
// per re-neighbouring; a raised cutoff brings more ghost atoms to every rank (up to all of them).

// A run's set-up, before its exchange and borders: the ghosts of the last run may be stale or gone, so the
// lengths come from the owners' positions (one reduction of the entities' atoms).
void PerAtomStateFix::setup_pre_exchange()
{
  if (!two_atom_) return;
  double cut = comm->get_comm_cutoff();
  const std::vector<AtomSnapshot> snap = snapshot_entity_atoms();
  Farthest far;
  for (std::size_t key = 0; key < atoms_.size(); key++) {
    if (atoms_[key].second < 0) continue;
    double d[3];
    for (int c = 0; c < 3; c++) d[c] = snap[2 * key + 1].x[c] - snap[2 * key].x[c];
    dembridge::minimum_image(domain, FLERR, d[0], d[1], d[2]);
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (len > cut && len > far.distance) far = {static_cast<int>(key), len};
  }
  if (far.key >= 0) cut = raise_ghost_cutoff(cut, far);  // the set-up's comm->setup() takes it
  near_ = near_of(cut);
  near_seen_ = false;
}

// A re-neighbouring, before its exchange and borders: the ghosts still hold the atoms of the last borders, each
// second atom among them; if an evaluation since then met a long pair, this step's positions are sent to them
// and every length measured.
void PerAtomStateFix::pre_exchange()
{
  if (!two_atom_) return;
  const int mine = near_seen_ ? 1 : 0;
  int any = 0;
  MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, world);
  near_seen_ = false;
  if (!any) return;
  comm->forward_comm();
  double cut = comm->get_comm_cutoff();
  const Farthest far = farthest_beyond(cut);
  if (far.key < 0) return;
  cut = raise_ghost_cutoff(cut, far);
  comm->setup();  // the swaps of the new cutoff (the integrator calls it only when the box changes)
  if (neighbor->style) neighbor->setup_bins();
  near_ = near_of(cut);
}

// The distance beyond which an evaluation reports a pair: the next borders find a pair that was nearer at the
// last evaluation within the cutoff unless its distance grew by more than the neighbour skin in one step (LAMMPS's
// own limit: an atom moving half the skin between neighbour checks), or by half the cutoff with a larger skin.
double PerAtomStateFix::near_of(double cutoff) const
{
  return std::max(0.5 * cutoff, cutoff - neighbor->skin);
}

double PerAtomStateFix::raise_ghost_cutoff(double cutoff, const Farthest &far)
{
  const double raised = 2.0 * far.distance;
  comm->cutghostuser = raised;
  if (comm->me == 0)
    utils::logmesg(lmp, "{}: {} between atoms {} and {} is {:.6g} long, beyond the ghost cutoff {:.6g}: ghost "
                   "cutoff raised to {:.6g}\n", cmd_, who(far.key), atoms_[far.key].first, atoms_[far.key].second,
                   far.distance, cutoff, raised);
  return comm->get_comm_cutoff();
}

void PerAtomStateFix::write_entity_restart(FILE *fp, int per, double sign,
                                           const std::function<void(int key, double *o)> &fill)
{
  const std::size_t n = atoms_.size(), stride = 2 + per;
  std::vector<double> list(1 + stride * n);
  list[0] = sign * static_cast<double>(n);
  for (std::size_t key = 0; key < n; key++) {
    double *o = &list[1 + stride * key];
    o[0] = static_cast<double>(atoms_[key].first);
    o[1] = static_cast<double>(atoms_[key].second);
    fill(static_cast<int>(key), o + 2);
  }
  if (comm->me == 0) {
    const int size = static_cast<int>(list.size() * sizeof(double));
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list.data(), sizeof(double), list.size(), fp);
  }
}

void PerAtomStateFix::read_entity_restart(const char *buf, const std::function<int(bool negative)> &per_of,
                                          const std::function<void(int key, const double *o, int per)> &apply)
{
  const double *list = reinterpret_cast<const double *>(buf);
  const int per = per_of(list[0] < 0);
  const std::size_t n = static_cast<std::size_t>(std::fabs(list[0])), stride = 2 + per;
  bool match = n == atoms_.size();
  for (std::size_t key = 0; match && key < n; key++)
    match = list[1 + stride * key] == atoms_[key].first && list[2 + stride * key] == atoms_[key].second;
  if (!match)
    error->all(FLERR, fmt::format("{}: the restart file holds different {}s (define the same {}s in the same order "
                                  "as before write_restart)", cmd_, noun_, noun_));
  for (std::size_t key = 0; key < n; key++) apply(static_cast<int>(key), &list[3 + stride * key], per);
}

void PerAtomStateFix::local_output(int cols)
{
  local_flag = 1;
  size_local_cols = cols;
  size_local_rows = 0;
  local_freq = 1;
}

void PerAtomStateFix::local_rows(int n)
{
  if (n > maxlocal_) {
    maxlocal_ = std::max(n, 2 * maxlocal_);
    memory->destroy(array_local);
    memory->create(array_local, maxlocal_, size_local_cols, "per_atom_state:array_local");
  }
  size_local_rows = n;
}

int PerAtomStateFix::setmask()
{
  using namespace FixConst;
  return POST_FORCE | MIN_POST_FORCE | (nevery > 0 && history_.is_open() ? END_OF_STEP : 0) |
         (two_atom_ ? PRE_EXCHANGE | MIN_PRE_EXCHANGE : 0);
}

void PerAtomStateFix::open_history(const DefinitionReader::History &request, const std::string &prefix,
                                   const std::vector<const char *> &columns)
{
  if (request.every <= 0) return;
  std::unordered_map<long, int> index;
  for (std::size_t key = 0; key < ids_.size(); key++) index[ids_[key]] = static_cast<int>(key);
  std::vector<int> keys;
  for (long hid : request.ids) {
    auto it = index.find(hid);
    if (it == index.end())
      error->all(FLERR, fmt::format("{}: history: {} ID {} is not defined (unknown {} ID)", cmd_, noun_, hid, noun_));
    keys.push_back(it->second);
  }
  nevery = request.every;
  history_.open(lmp, cmd_, request.file, prefix, keys, request.ids, columns);
}

// History rows: the values of the step just completed, labelled with the LAMMPS time.
void PerAtomStateFix::end_of_step()
{
  if (!history_.is_open()) return;
  flush_records();
  history_.begin_row();
  for (int i = 0; i < atom->nlocal; i++)
    for (int r = 0; r < records_.count(i); r++)
      if (double *o = history_.values_of(records_.key(i, r))) history_values(records_.record(i, r), o);
  history_.write_row(lmp, update->atime + (update->ntimestep - update->atimestep) * update->dt);
}

double PerAtomStateFix::memory_usage()
{
  return PerAtomRecordsFix::memory_usage() + sums_.bytes() + double(maxlocal_) * size_local_cols * sizeof(double);
}

// ---------------------------------------------------------------------------------------------------

std::vector<AtomSnapshot> snapshot_atoms(LAMMPS *lmp, const std::vector<long> &tags)
{
  Atom *atom = lmp->atom;
  constexpr int kG = 8;  // found x(3) q(4)
  std::vector<double> mine(tags.size() * kG, 0.0), all(tags.size() * kG, 0.0);
  std::unordered_map<tagint, int> local;
  for (int i = 0; i < atom->nlocal; i++) local[atom->tag[i]] = i;
  const bool hasq = atom->quat_flag && atom->quat;
  for (std::size_t s = 0; s < tags.size(); s++) {
    auto it = tags[s] < 0 ? local.end() : local.find(tags[s]);
    if (it == local.end()) continue;
    double *out = &mine[s * kG];
    out[0] = 1.0;
    lmp->domain->unmap(atom->x[it->second], atom->image[it->second], out + 1);
    if (hasq)
      for (int c = 0; c < 4; c++) out[4 + c] = atom->quat[it->second][c];
    else
      out[4] = 1.0;
  }
  MPI_Allreduce(mine.data(), all.data(), static_cast<int>(mine.size()), MPI_DOUBLE, MPI_SUM, lmp->world);
  std::vector<AtomSnapshot> out(tags.size());
  for (std::size_t s = 0; s < tags.size(); s++) {
    const double *a = &all[s * kG];
    out[s].found = a[0] != 0.0;
    if (!out[s].found) continue;
    for (int c = 0; c < 3; c++) out[s].x[c] = a[1 + c];
    for (int c = 0; c < 4; c++) out[s].q[c] = a[4 + c];
  }
  return out;
}

// ---------------------------------------------------------------------------------------------------

HistoryCsv::~HistoryCsv()
{
  if (fp_) fclose(fp_);
}

void HistoryCsv::open(LAMMPS *lmp, const std::string &cmd, const std::string &file, const std::string &prefix,
                      const std::vector<int> &keys, const std::vector<long> &ids,
                      const std::vector<const char *> &columns)
{
  ncols_ = columns.size();
  for (std::size_t h = 0; h < keys.size(); h++) group_[keys[h]] = static_cast<int>(group_.size());
  row_.assign(ncols_ * keys.size(), 0.0);
  sum_.assign(row_.size(), 0.0);
  if (lmp->comm->me != 0) return;
  fp_ = fopen(file.c_str(), "w");
  if (!fp_) fail_on_this_rank(lmp, FLERR, cmd + ": history: cannot open file '" + file + "' for writing");
  fprintf(fp_, "TIME");
  for (long id : ids)
    for (const char *c : columns) fprintf(fp_, ",%s%ld_%s", prefix.c_str(), id, c);
  fprintf(fp_, "\n");
  fflush(fp_);
}

bool HistoryCsv::is_open() const
{
  return !group_.empty();
}

void HistoryCsv::begin_row()
{
  std::fill(row_.begin(), row_.end(), 0.0);
}

double *HistoryCsv::values_of(int key)
{
  auto it = group_.find(key);
  return it == group_.end() ? nullptr : &row_[ncols_ * std::size_t(it->second)];
}

void HistoryCsv::write_row(LAMMPS *lmp, double time)
{
  MPI_Allreduce(row_.data(), sum_.data(), static_cast<int>(row_.size()), MPI_DOUBLE, MPI_SUM, lmp->world);
  if (!fp_) return;
  fprintf(fp_, "%.17g", time);
  for (double v : sum_) fprintf(fp_, ",%.17g", v);
  fprintf(fp_, "\n");
  fflush(fp_);
}

}  // namespace dembridge::state
