// Helpers for the components' save() and load(): boost's archives and the containers they hold.
#ifndef dieflow_serialization_h
#define dieflow_serialization_h

#include <dieflow/base/archive.h>

#include <boost/archive/binary_iarchive.hpp>
#include <boost/archive/binary_oarchive.hpp>
#include <boost/serialization/map.hpp>
#include <boost/serialization/set.hpp>
#include <boost/serialization/string.hpp>
#include <boost/serialization/utility.hpp>
#include <boost/serialization/vector.hpp>

#include <cstddef>
#include <vector>

namespace dieflow
{
  /// Saves or loads a vector: its size, then @p item(x) for each element x.
  template <class Archive, typename T, typename Item>
  void
  serialize_each(Archive &ar, std::vector<T> &items, const Item &item)
  {
    std::size_t n = items.size();
    ar &n;
    items.resize(n);
    for (auto &x : items)
      item(x);
  }
} // namespace dieflow

#endif
