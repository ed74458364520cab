#include "restart_record.h"

#include <cstring>
#include <stdexcept>
#include <string>

namespace dembridge::insertion {

namespace {
constexpr double kMaxLength = 1e7;  // far above any insertion record: a larger header is not one
}

void RestartWriter::put(const ParkMiller &rng)
{
  for (double x : rng.saved()) v_.push_back(x);
}

void RestartWriter::write(FILE *fp)
{
  v_[1] = static_cast<double>(v_.size());
  const int bytes = static_cast<int>(v_.size() * sizeof(double));
  std::fwrite(&bytes, sizeof(int), 1, fp);
  std::fwrite(v_.data(), sizeof(double), v_.size(), fp);
}

RestartReader::RestartReader(const char *buf, double kind)
{
  double head[2];
  std::memcpy(head, buf, sizeof head);
  if (head[0] != kind || !(head[1] >= 2. && head[1] <= kMaxLength))
    throw std::invalid_argument("the restart file holds another kind of record for this fix ID (written by "
                                "another fix style or plugin version)");
  v_.resize(static_cast<std::size_t>(head[1]));
  std::memcpy(v_.data(), buf, v_.size() * sizeof(double));
}

double RestartReader::get()
{
  if (next_ >= v_.size()) throw std::invalid_argument("the restart record is shorter than this fix expects");
  return v_[next_++];
}

void RestartReader::get(ParkMiller &rng)
{
  std::array<double, 3> s;
  for (double &x : s) x = get();
  rng.restore(s);
}

void put(RestartWriter &w, const InsertionProgress &p)
{
  for (double x : {double(p.seed), double(p.next_step), double(p.most_recent), double(p.ninserted), p.mass_inserted,
                   p.exact_number ? 1. : 0.})
    w.put(x);
}

InsertionProgress get_progress(RestartReader &r, int expected_seed)
{
  InsertionProgress p;
  p.seed = static_cast<int>(r.get());
  if (p.seed != expected_seed)
    throw std::invalid_argument("seed " + std::to_string(expected_seed) + " differs from the seed " +
                                std::to_string(p.seed) +
                                " the restart file was written with (define the fix with the same seed as before "
                                "write_restart)");
  p.next_step = static_cast<std::int64_t>(r.get());
  p.most_recent = static_cast<std::int64_t>(r.get());
  p.ninserted = r.get_long();
  p.mass_inserted = r.get();
  p.exact_number = r.get_bool();
  return p;
}

}  // namespace dembridge::insertion
