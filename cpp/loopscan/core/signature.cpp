#include "loopscan/core/signature.hpp"

#include <stdexcept>

#include "loopscan/core/config.hpp"
#include "loopscan/core/descriptors/birds_eye_place.hpp"

namespace loopscan {

int rows_per_place(Method method) {
  switch (method) {
    case Method::ScanContext:
      return 1;
    case Method::M2dp:
      return 4;
    case Method::Delight:
      return 16;
    case Method::BirdsEye:
      return 1;
  }
  return 1;
}

int signature_columns(Method method) {
  switch (method) {
    case Method::ScanContext: {
      const ScanContextConfig c;
      return 2 * c.rings * c.sectors;
    }
    case Method::M2dp: {
      const M2dpConfig c;
      return 2 * (c.plane_azimuths * c.plane_elevations + c.azimuth_bins * c.radial_bins);
    }
    case Method::Delight:
      return DelightConfig{}.intensity_bins;
    case Method::BirdsEye:
      return birds_eye_signature_columns(BirdsEyePlaceConfig{});
  }
  return 0;
}

std::string method_name(Method method) {
  switch (method) {
    case Method::ScanContext:
      return "sc";
    case Method::M2dp:
      return "m2dp";
    case Method::Delight:
      return "delight";
    case Method::BirdsEye:
      return "bev";
  }
  return "?";
}

Method parse_method(const std::string& name) {
  if (name == "sc") return Method::ScanContext;
  if (name == "m2dp") return Method::M2dp;
  if (name == "delight") return Method::Delight;
  if (name == "bev") return Method::BirdsEye;
  throw std::invalid_argument("unknown method '" + name + "' (expected sc, m2dp, delight or bev)");
}

std::string mode_name(Mode mode) { return mode == Mode::Reference ? "reference" : "default"; }

Mode parse_mode(const std::string& name) {
  if (name == "reference") return Mode::Reference;
  if (name == "default") return Mode::Default;
  throw std::invalid_argument("unknown mode '" + name + "' (expected reference or default)");
}

}  // namespace loopscan
