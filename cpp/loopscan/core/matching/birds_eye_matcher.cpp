// Bird's-eye difference-matrix rows: exact key distances to every place; the evaluation's rows
// search the images of the query's key finalists (the two stages of birds_eye_match.hpp).
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <limits>

#include "loopscan/core/matching/place_matcher.hpp"

namespace loopscan {
namespace {

class BirdsEyeMatcher final : public PlaceMatcher {
 public:
  BirdsEyeMatcher(const BirdsEyePlaceConfig& place, const BirdsEyeSearchConfig& search)
      : place_config_(place), search_(search) {
    validate(place);
  }

  void add(const Signature& place) override {
    places_.push_back(birds_eye_place(place, place_config_));
    const BirdsEyeKeySpectrum s = key_spectrum(places_.back(), place_config_.angles);
    rings_ = s.rings;
    stride_ = s.stride;
    norms_.push_back(s.norm);
    parts_.insert(parts_.end(), s.re.begin(), s.re.end());
    parts_.insert(parts_.end(), s.im.begin(), s.im.end());
    rounded_.insert(rounded_.end(), s.rounded.begin(), s.rounded.end());
  }
  std::size_t size() const override { return places_.size(); }
  int components() const override { return 1; }

  void distances(const Signature& query, Eigen::MatrixXd& rows) const override {
    const BirdsEyeKeySpectrum q =
        key_spectrum(birds_eye_place(query, place_config_), place_config_.angles);
    rows.resize(1, static_cast<Eigen::Index>(places_.size()));
    for (std::size_t j = 0; j < places_.size(); ++j) {
      rows(0, static_cast<Eigen::Index>(j)) = match_key_spectra(view(q), spectrum(j)).distance;
    }
  }

  // The allowed columns' key finalists by nearest_keys (what sorting distances()' allowed
  // columns by (distance, column) gives, without matching every key in full).
  void rows(const Signature& query, int query_index, int mask_width,
            Eigen::MatrixXd& rows) const override {
    const BirdsEyePlace q = birds_eye_place(query, place_config_);
    const BirdsEyeKeySpectrum qs = key_spectrum(q, place_config_.angles);
    const auto finalists = nearest_keys(
        view(qs), places_.size(),
        [&](std::size_t j) { return std::abs(query_index - static_cast<int>(j)) >= mask_width; },
        [&](std::size_t j) { return spectrum(j); },
        static_cast<std::size_t>(std::max(0, search_.finalists)));
    rows = Eigen::MatrixXd::Constant(1, static_cast<Eigen::Index>(places_.size()),
                                     std::numeric_limits<double>::infinity());
    const BirdsEyeImageSearch images(q, place_config_, search_);
    for (const auto& [key_distance, j] : finalists) {
      const double yaw = match_key_spectra(view(qs), spectrum(j)).yaw_rad;
      rows(0, static_cast<Eigen::Index>(j)) = birds_eye_distance(images.pose(places_[j], yaw));
    }
  }

 private:
  BirdsEyeKeySpectrumView spectrum(std::size_t j) const {
    const std::size_t floats = static_cast<std::size_t>(rings_) * stride_;
    return {rings_,
            place_config_.angles,
            stride_,
            parts_.data() + 2 * j * floats,
            parts_.data() + (2 * j + 1) * floats,
            norms_[j],
            rounded_.data() + 2 * j * floats};
  }

  BirdsEyePlaceConfig place_config_;
  BirdsEyeSearchConfig search_;
  std::vector<BirdsEyePlace> places_;
  // The places' key spectra, contiguous (what the key scan streams): per place its real then
  // imaginary parts (rings x stride each), and the same again as bfloat16.
  int rings_ = 0, stride_ = 0;
  std::vector<double> norms_;
  std::vector<float> parts_;
  std::vector<std::uint16_t> rounded_;
};

}  // namespace

std::unique_ptr<PlaceMatcher> make_birds_eye_matcher(const BirdsEyePlaceConfig& place,
                                                     const BirdsEyeSearchConfig& search) {
  return std::make_unique<BirdsEyeMatcher>(place, search);
}

}  // namespace loopscan
