#pragma once
// An array put in another order, or cut to some of its entries: values[k] becomes values[order[k]]
// for k < order.size(), and the rest go (the fluid's cell order, a rank's rows kept).
#include <span>
#include <vector>

#include "spall/core/types.hpp"

namespace spall {

template <typename T>
void reorder(std::vector<T>& values, std::span<const Index> order) {
  std::vector<T> out(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) out[k] = values[order[k]];
  values.swap(out);
}

}  // namespace spall
