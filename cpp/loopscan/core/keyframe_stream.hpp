#pragma once
// A VO export streamed as the VO produced it: each keyframe in order with the points exported
// since the previous one (those with an id up to its own; points sorted by id).
#include <cstddef>
#include <vector>

#include "loopscan/core/types.hpp"

namespace loopscan {

// Calls fn(keyframe, first point, point count) for every keyframe of `poses`, in order.
template <typename Fn>
void for_each_keyframe(const std::vector<KeyframePose>& poses, const std::vector<IdPoint>& points,
                       Fn&& fn) {
  std::size_t next = 0;
  for (const KeyframePose& keyframe : poses) {
    const std::size_t first = next;
    while (next < points.size() && points[next].id <= keyframe.id) ++next;
    fn(keyframe, points.data() + first, next - first);
  }
}

}  // namespace loopscan
