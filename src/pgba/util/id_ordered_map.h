// A map from image ids to values held in one contiguous array sorted by id: it iterates in
// id order like std::map, and its elements' addresses are in id order too, which a
// std::map's nodes are not (they lie wherever the allocator put them, which depends on
// everything allocated before: the --out path's length, which thread ran which task).
//
// Why it matters: Ceres orders the parameter blocks of an elimination group by address
// (ParameterBlockOrdering holds std::set<double*>), and the order changes the last bits of
// the solution. Parameter blocks held here give the same order, hence the same bytes, in
// every run. As with a vector, an insertion invalidates references: fill it first, then
// hand addresses to Ceres.
#pragma once

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace pgba {

template <typename Value>
class IdOrderedMap {
 public:
  using value_type = std::pair<uint32_t, Value>;
  using iterator = typename std::vector<value_type>::iterator;
  using const_iterator = typename std::vector<value_type>::const_iterator;

  Value& operator[](uint32_t id) {
    const iterator it = LowerBound(id);
    if (it != items_.end() && it->first == id) return it->second;
    return items_.insert(it, value_type(id, Value()))->second;
  }
  Value& at(uint32_t id) { return const_cast<Value&>(static_cast<const IdOrderedMap&>(*this).at(id)); }
  const Value& at(uint32_t id) const {
    const const_iterator it = find(id);
    if (it == items_.end()) throw std::out_of_range("IdOrderedMap::at: no id " + std::to_string(id));
    return it->second;
  }
  iterator find(uint32_t id) {
    const iterator it = LowerBound(id);
    return it != items_.end() && it->first == id ? it : items_.end();
  }
  const_iterator find(uint32_t id) const { return const_cast<IdOrderedMap*>(this)->find(id); }
  size_t count(uint32_t id) const { return find(id) != items_.end() ? 1 : 0; }
  size_t size() const { return items_.size(); }
  bool empty() const { return items_.empty(); }
  iterator begin() { return items_.begin(); }
  iterator end() { return items_.end(); }
  const_iterator begin() const { return items_.begin(); }
  const_iterator end() const { return items_.end(); }

 private:
  iterator LowerBound(uint32_t id) {
    return std::lower_bound(items_.begin(), items_.end(), id,
                            [](const value_type& item, uint32_t key) { return item.first < key; });
  }
  std::vector<value_type> items_;
};

}  // namespace pgba
