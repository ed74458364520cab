// Bytes held by a fix's containers, for its memory_usage() (LAMMPS's memory line): a vector's capacity;
// a hash map's bucket array and its nodes (the value, the next pointer and the allocator's chunk header each).
#pragma once

#include <cstddef>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

namespace dembridge::state {

constexpr double kNodeOverhead = 2 * sizeof(void *);  // next pointer + malloc chunk header

template <class T, class A> double container_bytes(const std::vector<T, A> &v)
{
  return double(v.capacity()) * sizeof(T);
}
template <class K, class V, class... R> double container_bytes(const std::unordered_map<K, V, R...> &m)
{
  return double(m.bucket_count()) * sizeof(void *) + double(m.size()) * (sizeof(std::pair<const K, V>) + kNodeOverhead);
}
template <class K, class... R> double container_bytes(const std::unordered_set<K, R...> &s)
{
  return double(s.bucket_count()) * sizeof(void *) + double(s.size()) * (sizeof(K) + kNodeOverhead);
}
template <class... C> double containers_bytes(const C &...c) { return (0.0 + ... + container_bytes(c)); }

}  // namespace dembridge::state
