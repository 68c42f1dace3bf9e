#pragma once
// The `short` route's world in summer with the KITTI camera scaled by `scale`, and its rendered
// views as OpenCV images: the scene of the renderer, VO and image-baseline tests.
#include <cstdint>

#include <opencv2/core.hpp>

#include "loopscan/sim/renderer.hpp"
#include "loopscan/sim/trajectory.hpp"
#include "loopscan/sim/world.hpp"

namespace loopscan::test {

struct ShortStreet {
  explicit ShortStreet(double scale) : camera(sim::scaled_camera(sim::StereoCamera{}, scale)) {}
  sim::Trajectory route = sim::make_builtin_trajectory("short");
  sim::World world = sim::World::build(route.centres(), sim::WorldConfig{});
  sim::Conditions conditions = sim::Conditions::for_season(sim::Season::Summer);
  sim::StereoCamera camera;

  // camera_index 0 = left, 1 = right; rendered on 2 threads (the image does not depend on it).
  cv::Mat render(int frame, int camera_index) const {
    sim::RenderConfig rc;
    rc.threads = 2;
    const sim::GrayImage g = sim::render_view(world, conditions, camera, route.T_world_cam[frame],
                                              camera_index, frame, rc);
    return cv::Mat(g.height, g.width, CV_8UC1, const_cast<std::uint8_t*>(g.pixels.data())).clone();
  }
};

}  // namespace loopscan::test
