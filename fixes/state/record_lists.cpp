#include "record_lists.h"

#include <algorithm>

namespace dembridge::state {

double *RecordLists::append(int i, double key)
{
  std::vector<double> &l = lists_[i];
  l.resize(l.size() + rs_, 0.0);
  double *rec = &l[l.size() - rs_];
  rec[0] = key;
  ++generation_;
  return rec;
}

void RecordLists::erase(int i, int r)
{
  std::vector<double> &l = lists_[i];
  const std::size_t last = l.size() - rs_;
  if (std::size_t(r) * rs_ != last) std::copy(l.begin() + last, l.end(), l.begin() + std::size_t(r) * rs_);
  l.resize(last);
  ++generation_;
}

int RecordLists::find(int i, double key) const
{
  const std::vector<double> &l = lists_[i];
  for (std::size_t at = 0; at < l.size(); at += rs_)
    if (l[at] == key) return static_cast<int>(at / rs_);
  return -1;
}

void RecordLists::remove(int i, int r)
{
  std::vector<double> &l = lists_[i];
  const auto first = l.begin() + std::size_t(r) * rs_;
  l.erase(first, first + rs_);
  ++generation_;
}

void RecordLists::clear(int i)
{
  std::vector<double>().swap(lists_[i]);
  ++generation_;
}

void RecordLists::copy(int from, int to)
{
  lists_[to] = lists_[from];
  ++generation_;
}

int RecordLists::pack(int i, double *buf) const
{
  const std::vector<double> &l = lists_[i];
  buf[0] = static_cast<double>(l.size());
  std::copy(l.begin(), l.end(), buf + 1);
  return 1 + static_cast<int>(l.size());
}

int RecordLists::unpack(int i, const double *buf)
{
  const int n = static_cast<int>(buf[0]);
  lists_[i].assign(buf + 1, buf + 1 + n);
  ++generation_;
  return 1 + n;
}

bool RecordLists::is_packed_atom(const double *buf, int size) const
{
  if (size < 1) return false;
  const int n = static_cast<int>(buf[0]);
  return size == 1 + n && n >= 0 && n % rs_ == 0;
}

long RecordLists::total(int n) const
{
  long t = 0;
  for (int i = 0; i < n; i++) t += count(i);
  return t;
}

double RecordLists::bytes(int n) const
{
  double b = double(lists_.capacity()) * sizeof(lists_[0]);  // every atom slot's (empty or not) list object
  for (int i = 0; i < n; i++)
    if (lists_[i].capacity()) b += lists_[i].capacity() * sizeof(double) + kChunkHeader;
  return b;
}

std::pair<int, int> RecordIndex::find(const RecordLists &lists, int n, int nkeys, int key)
{
  if (key < 0 || key >= nkeys) return {-1, -1};
  if (generation_ != lists.generation() || n_ != n || static_cast<int>(where_.size()) != nkeys) {
    where_.assign(nkeys, {-1, -1});
    for (int i = 0; i < n; i++)
      for (int r = 0; r < lists.count(i); r++) where_[lists.key(i, r)] = {i, r};
    generation_ = lists.generation();
    n_ = n;
  }
  return where_[key];
}

}  // namespace dembridge::state
