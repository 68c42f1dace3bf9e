// Bird's-eye difference-matrix rows: exact key distances to every place; the evaluation's rows
// search the images of the query's key finalists (the two stages of birds_eye_match.hpp).
#include <algorithm>
#include <cstdlib>
#include <limits>

#include "loopscan/core/matching/place_matcher.hpp"
#include "loopscan/core/payload_arena.hpp"

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
    std::vector<float> packed(spectra_.floats_per_record());
    pack_key_spectrum(s, packed.data());
    spectra_.append(packed.data());
    rounded_.append(reinterpret_cast<const float*>(s.rounded.data()));  // copied as bytes
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
    return packed_key_spectrum(spectra_.at(j), place_config_.rings, place_config_.angles,
                               rounded_.at(j));
  }

  BirdsEyePlaceConfig place_config_;
  BirdsEyeSearchConfig search_;
  std::vector<BirdsEyePlace> places_;
  // The places' key spectra packed, and their bfloat16 copies, each contiguous as the
  // database keeps them (what the key scan streams).
  PayloadArena spectra_{packed_key_spectrum_floats(place_config_.rings, place_config_.angles)};
  PayloadArena rounded_{packed_rounded_floats(place_config_.rings, place_config_.angles)};
};

}  // namespace

std::unique_ptr<PlaceMatcher> make_birds_eye_matcher(const BirdsEyePlaceConfig& place,
                                                     const BirdsEyeSearchConfig& search) {
  return std::make_unique<BirdsEyeMatcher>(place, search);
}

}  // namespace loopscan
