#pragma once
// A route's world (a built-in one, or any trajectory) in summer with the KITTI camera scaled by
// `scale`, and its rendered views as OpenCV images: the scenes of the renderer, VO and
// image-baseline tests (the `short` street; the open road).
#include <cstdint>
#include <string>
#include <utility>

#include <opencv2/core.hpp>

#include "loopscan/sim/renderer.hpp"
#include "loopscan/sim/trajectory.hpp"
#include "loopscan/sim/world.hpp"

namespace loopscan::test {

struct RenderedRoute {
  RenderedRoute(const std::string& route_name, const sim::WorldConfig& config, double scale)
      : RenderedRoute(sim::make_builtin_trajectory(route_name), config, scale) {}
  RenderedRoute(sim::Trajectory trajectory, const sim::WorldConfig& config, double scale)
      : route(std::move(trajectory)),
        world(sim::World::build(route.centres(), config)),
        camera(sim::scaled_camera(sim::StereoCamera{}, scale)) {}
  sim::Trajectory route;
  sim::World world;
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

struct ShortStreet : RenderedRoute {
  explicit ShortStreet(double scale) : RenderedRoute("short", sim::WorldConfig{}, scale) {}
};

}  // namespace loopscan::test
