// Internal: welding corners at exactly equal positions into one vertex (STL, glTF), numbered in
// order of first appearance; -0.0 and +0.0 weld together.
#pragma once

#include "freeform/mesh/types.h"

#include <array>
#include <bit>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

namespace freeform::io_detail {

class PositionWelder {
 public:
  explicit PositionWelder(std::vector<Vec3>& positions) : positions_(positions) {}
  void reserve(std::size_t corners) { map_.reserve(corners); }
  // The vertex at `p` (appended to the positions when new) and whether it is new.
  std::pair<int, bool> add(const Vec3& p) {
    // Adding +0.0 turns -0.0 into +0.0, so both weld together.
    const Vec3 q(p.x() + 0.0, p.y() + 0.0, p.z() + 0.0);
    const Key key{std::bit_cast<std::uint64_t>(q.x()), std::bit_cast<std::uint64_t>(q.y()),
                  std::bit_cast<std::uint64_t>(q.z())};
    const auto [it, inserted] = map_.try_emplace(key, static_cast<int>(positions_.size()));
    if (inserted) positions_.push_back(q);
    return {it->second, inserted};
  }

 private:
  using Key = std::array<std::uint64_t, 3>;
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = 0x9e3779b97f4a7c15ull;
      for (std::uint64_t v : k) {
        h ^= v + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
        h *= 0xff51afd7ed558ccdull;
        h ^= h >> 33;
      }
      return static_cast<std::size_t>(h);
    }
  };
  std::vector<Vec3>& positions_;
  std::unordered_map<Key, int, KeyHash> map_;
};

}  // namespace freeform::io_detail
