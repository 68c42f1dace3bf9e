// Fifty laps of one block with a drifting VO (new noise and drift every lap): the map and the
// pose graph stay the size of the area (that of three laps, which drive all of it: the way back
// to the start too), every lap keeps closing its revisits, no loop is false, and the trajectory
// stays as accurate as after three laps. About 10 minutes.
#include <gtest/gtest.h>

#include <iostream>

#include "closure/drives.hpp"

namespace loopscan {
namespace {

TEST(LifelongSoak, FiftyLapsStayTheSizeOfTheArea) {
  const closure::LoopCloserConfig config = closure::LoopCloserConfig::make(Method::ScanContext);
  const test::Closed three =
      test::close_drive(test::drive(sim::Season::Summer, 1, "short", 0.02, 3), config);
  const test::Drive fifty = test::drive(sim::Season::Summer, 1, "short", 0.02, 50);
  const test::Closed soak = test::close_drive(fifty, config);
  std::cout << "3 laps: " << three.map_places << " places, graph " << three.graph_nodes
            << " nodes / " << three.graph_edges << " edges, ATE " << three.ate_before << " -> "
            << three.ate_after << " m\n50 laps: " << fifty.vo.poses.size() << " keyframes, "
            << soak.map_places << " places, graph " << soak.graph_nodes << " nodes / "
            << soak.graph_edges << " edges, " << soak.closed << " of " << soak.revisits
            << " revisits closed, ATE " << soak.ate_before << " -> " << soak.ate_after << " m\n";
  EXPECT_EQ(soak.false_loops, 0) << soak.false_list;
  EXPECT_GE(soak.closed, 0.9 * soak.revisits) << soak.closed << " of " << soak.revisits;
  EXPECT_LE(soak.map_places, 1.5 * three.map_places);
  EXPECT_LE(soak.graph_nodes, 1.5 * three.graph_nodes);
  EXPECT_LE(soak.graph_edges, 1.5 * three.graph_edges);
  EXPECT_GT(soak.ate_before, 2 * three.ate_before);  // fifty laps of drift
  EXPECT_LE(soak.ate_after, 1.5 * three.ate_after + 0.1);
}

}  // namespace
}  // namespace loopscan
