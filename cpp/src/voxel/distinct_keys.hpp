// Deduplication by key, shared by the PCA frame (area moments) and the voxelizer: of the items
// listed in `candidates`, keeps the first (lowest index) of each group with equal keys[item].
// Cost O(n log n); the result is sorted by index, so later stages see the input order.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace curvedslicer::detail {

template <class Key>
std::vector<std::size_t> firstOfEachDistinctKey(const std::vector<Key>& keys,
                                                std::vector<std::size_t> candidates) {
  std::stable_sort(candidates.begin(), candidates.end(),
                   [&](std::size_t a, std::size_t b) { return keys[a] < keys[b]; });
  candidates.erase(std::unique(candidates.begin(), candidates.end(),
                               [&](std::size_t a, std::size_t b) { return keys[a] == keys[b]; }),
                   candidates.end());
  std::sort(candidates.begin(), candidates.end());
  return candidates;
}

}  // namespace curvedslicer::detail
