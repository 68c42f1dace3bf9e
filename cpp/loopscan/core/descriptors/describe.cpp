#include "loopscan/core/descriptors/describe.hpp"

#include <memory>

#include "loopscan/core/descriptors/delight.hpp"
#include "loopscan/core/descriptors/m2dp.hpp"
#include "loopscan/core/descriptors/scan_context.hpp"

#include <stdexcept>
#include <vector>

namespace loopscan {

DescriptorConfig DescriptorConfig::for_mode(Mode mode, double range_m) {
  DescriptorConfig c;
  c.scan_context.mode = c.m2dp.mode = c.delight.mode = mode;
  c.scan_context.max_radius_m = c.m2dp.max_radius_m = range_m;
  if (mode == Mode::Default) {
    // Scan Context keyframe-centred (the camera's up, yaw left to the sector search) with
    // lateral versions: a revisit a metre aside, or one lane over the other way round, matches
    // (docs/experiments/direction-lane-season.md: every sequence we measured gains).
    c.scan_context.frame = DescriptorFrame::Camera;
    c.scan_context.lateral_versions_m = kDefaultLateralVersions;
  }
  return c;
}

DescriptorFrame descriptor_frame(Method method, const DescriptorConfig& config) {
  switch (method) {
    case Method::ScanContext:
      return config.scan_context.mode == Mode::Reference ? DescriptorFrame::Pca
                                                         : config.scan_context.frame;
    case Method::M2dp:
      return config.m2dp.mode == Mode::Reference ? DescriptorFrame::Pca : config.m2dp.frame;
    case Method::Delight:
      break;
    case Method::BirdsEye:
      return DescriptorFrame::Camera;
  }
  return config.delight.mode == Mode::Reference ? DescriptorFrame::Pca : config.delight.frame;
}

namespace {

// The describer a thread keeps for the configuration it last described with: building one
// tables the transform, the key's samples and the taper, which costs about a place's
// description.
const BirdsEyeDescriber& birds_eye_describer(const BirdsEyePlaceConfig& config) {
  thread_local std::unique_ptr<BirdsEyeDescriber> describer;
  if (!describer || !same_description(describer->config(), config)) {
    describer = std::make_unique<BirdsEyeDescriber>(config);
  }
  return *describer;
}

}  // namespace

Signature describe(Method method, const Cloud& scan, const DescriptorConfig& config,
                   Eigen::Matrix3d* frame) {
  if (frame) frame->setIdentity();
  switch (method) {
    case Method::ScanContext:
      return scan_context_signature(scan, config.scan_context, frame);
    case Method::M2dp:
      return m2dp_signature(scan, config.m2dp);
    case Method::Delight:
      return delight_signature(scan, config.delight);
    case Method::BirdsEye: {
      std::vector<float> x(scan.size()), y(scan.size()), z(scan.size());
      for (std::size_t i = 0; i < scan.size(); ++i) {
        const Eigen::Vector3d& p = scan[i].p;
        if (!p.allFinite()) throw std::invalid_argument("describe: a scan point is not finite");
        x[i] = static_cast<float>(p.x());
        y[i] = static_cast<float>(p.y());
        z[i] = static_cast<float>(p.z());
      }
      return birds_eye_signature(
          birds_eye_describer(config.birds_eye).describe(x.data(), y.data(), z.data(), x.size()));
    }
  }
  return {};
}

}  // namespace loopscan
