// A hash index from keys to uint32 ids that stores the ids alone: a key is not kept in the table
// but derived again from the id (KeyOf), e.g. a vertex's coordinates or its grid cell. The table
// is then 4 bytes per slot (open addressing, linear probing, at most half full), a quarter of a
// hash map that keeps the keys, which is what a lookup per mesh corner costs in cache misses
// (the STL reader's corner welding, repair's weld).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "absl/hash/hash.h"

namespace femsimp {

template <typename Key, typename KeyOf>
class IdIndex {
 public:
  static constexpr uint32_t kNoId = std::numeric_limits<uint32_t>::max();

  // `expected`: how many ids it will likely hold (it grows past that).
  IdIndex(size_t expected, KeyOf key_of) : key_of_(std::move(key_of)) {
    size_t capacity = 16;
    while (capacity < 2 * expected) capacity *= 2;
    slots_.assign(capacity, kNoId);
  }

  // The id whose key equals `key`, or kNoId.
  uint32_t Find(const Key& key) const { return slots_[SlotOf(key)]; }

  // The id whose key equals `key`; when there is none, `id` becomes its id and is returned
  // (KeyOf(id) must then be `key` already: growing the table reads it).
  uint32_t FindOrInsert(const Key& key, uint32_t id) {
    const size_t s = SlotOf(key);
    if (slots_[s] != kNoId) return slots_[s];
    Put(s, id);
    return id;
  }

  // Makes `id` the id of `key` (KeyOf(id) == key) and returns the one it had before, or kNoId.
  uint32_t Exchange(const Key& key, uint32_t id) {
    const size_t s = SlotOf(key);
    const uint32_t before = slots_[s];
    if (before != kNoId) {
      slots_[s] = id;
      return before;
    }
    Put(s, id);
    return kNoId;
  }

 private:
  // The slot holding key's id, or the empty slot where it would go.
  size_t SlotOf(const Key& key) const {
    const size_t mask = slots_.size() - 1;
    for (size_t s = absl::Hash<Key>{}(key)&mask;; s = (s + 1) & mask)
      if (slots_[s] == kNoId || key_of_(slots_[s]) == key) return s;
  }

  void Put(size_t slot, uint32_t id) {
    slots_[slot] = id;
    if (2 * ++size_ <= slots_.size()) return;
    std::vector<uint32_t> old(2 * slots_.size(), kNoId);
    old.swap(slots_);
    for (uint32_t held : old)
      if (held != kNoId) slots_[SlotOf(key_of_(held))] = held;
  }

  KeyOf key_of_;
  std::vector<uint32_t> slots_;
  size_t size_ = 0;
};

}  // namespace femsimp
